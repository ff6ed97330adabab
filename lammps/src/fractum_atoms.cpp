#include "fractum_atoms.h"

#include "force.h"
#include "fractum_sums.h"
#include "lammps.h"
#include "pair.h"

using namespace LAMMPS_NS;

double **LAMMPS_NS::fractum_array_if(LAMMPS *lmp, const char *name, int *cols)
{
  int flag = -1, c = -1;
  int index = lmp->atom->find_custom(name, flag, c);
  if (index < 0 || flag != 1 || c <= 0) return nullptr;
  if (cols) *cols = c;
  return lmp->atom->darray[index];
}

double **LAMMPS_NS::fractum_array(LAMMPS *lmp, const char *style, const char *name, int min_cols,
                                  const char *hint)
{
  int cols = 0;
  double **a = fractum_array_if(lmp, name, &cols);
  if (!a)
    lmp->error->all(FLERR,
                    "{} needs the per-atom array d2_{} ({} columns) of a fix property/atom, "
                    "which is not defined: {}",
                    style, name, min_cols, hint);
  if (cols < min_cols)
    lmp->error->all(FLERR, "{} needs d2_{} with at least {} columns, and it has {}: {}", style,
                    name, min_cols, cols, hint);
  return a;
}

void LAMMPS_NS::fractum_grain_arrays(LAMMPS *lmp, const char *style, double **&shape,
                                     double **&quat, double **&inertia, double **&grain)
{
  const char *hint = "declare the fix property/atom arrays d2_fr_shape 7, d2_fr_orient 7, "
                     "d2_fr_inertia 7 and d2_fr_grain 5 (ghost yes) before read_data";
  shape = fractum_array(lmp, style, "fr_shape", SHAPE_COLS, hint);
  quat = fractum_array(lmp, style, "fr_orient", QUAT_COLS, hint);
  inertia = fractum_array(lmp, style, "fr_inertia", INERTIA_COLS, hint);
  grain = fractum_array(lmp, style, "fr_grain", GRAIN_COLS, hint);
}

void LAMMPS_NS::fractum_kernel_failed(LAMMPS *lmp, const char *style, const char *kernel,
                                      int status)
{
  lmp->error->one(FLERR,
                  "{}: the Fractum kernel {} refused its arguments (status {}): a non-finite or "
                  "non-positive value in the per-atom data",
                  style, kernel, status);
}

FractumContactLaw LAMMPS_NS::fractum_contact_law(LAMMPS *lmp, const char *style,
                                                 const FractumMaterial &m, double mu)
{
  FractumContactLaw out;
  int status = fractum_kernel_contact_law(m.young, m.poisson,
                                          m.restitution > 0 ? m.restitution : 1.0, mu,
                                          m.restitution > 0 ? 1 : 0, m.friction >= 0 ? 1 : 0, &out);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, style, "contact_law", status);
  return out;
}

FractumSums *LAMMPS_NS::fractum_sums(LAMMPS *lmp, const char *style)
{
  int dim = 0;
  Pair *pair = lmp->force->pair_match("fractum/granular", 1);
  void *sums = pair ? pair->extract("fractum/sums", dim) : nullptr;
  if (!sums) lmp->error->all(FLERR, "{} needs pair_style fractum/granular", style);
  return static_cast<FractumSums *>(sums);
}
