/* Registers the Fractum styles with LAMMPS (`plugin load dist/fractumplugin.so`). */
#include "lammpsplugin.h"

#include "compute_fractum_loads.h"
#include "fix_fractum_cohesion.h"
#include "fix_fractum_dt.h"
#include "fix_fractum_fracture.h"
#include "fix_fractum_nve_polyell.h"
#include "fix_fractum_platens.h"
#include "pair_fractum_granular.h"

#include "error.h"
#include "lammps.h"
#include "library.h"

#include <string>

using namespace LAMMPS_NS;

/* The LAMMPS this plugin is compiled against, set by lammps/CMakeLists.txt from the binary's
   banner (the wheel ships no version.h; else version.h): its version date ("22 Jul 2025", what
   LAMMPS::version holds) and, for a LAMMPS built from git, its descriptor, which names the
   stable release's update ("stable_22Jul2025_update4"; the date alone does not). */
#ifndef FRACTUM_LAMMPS_VERSION
#define FRACTUM_LAMMPS_VERSION "unknown"
#endif
#ifndef FRACTUM_LAMMPS_GIT
#define FRACTUM_LAMMPS_GIT ""
#endif

/* For the plugin's own tests only: a build that pretends to be built for another LAMMPS
   (version date, git descriptor, size of tagint in bytes), to see the load refuse it. */
#ifdef FRACTUM_PRETEND_LAMMPS_VERSION
#define FRACTUM_BUILT_VERSION FRACTUM_PRETEND_LAMMPS_VERSION
#else
#define FRACTUM_BUILT_VERSION FRACTUM_LAMMPS_VERSION
#endif
#ifdef FRACTUM_PRETEND_LAMMPS_GIT
#define FRACTUM_BUILT_GIT FRACTUM_PRETEND_LAMMPS_GIT
#else
#define FRACTUM_BUILT_GIT FRACTUM_LAMMPS_GIT
#endif
#ifdef FRACTUM_PRETEND_TAGINT_BYTES
#define FRACTUM_BUILT_TAGINT_BYTES FRACTUM_PRETEND_TAGINT_BYTES
#else
#define FRACTUM_BUILT_TAGINT_BYTES sizeof(tagint)
#endif

static std::string release(const std::string &version, const std::string &git)
{
  return git.empty() ? version : version + " (" + git + ")";
}

/* Stops the `plugin load` command with one sentence, before any style is registered, when the
   running LAMMPS is not the one the plugin was compiled against: another release (or another
   update of it) may lay out the classes the plugin reads differently (FixNeighHistory's layout
   is declared by hand, fix_neigh_history_layout.h; pair.h and atom.h change between releases),
   and other integer sizes (-DLAMMPS_SMALLBIG / BIGBIG / SMALLSMALL) change the layout of every
   per-atom tag and image array and of the MPI types the plugin sends them with. */
static void check_host(LAMMPS *lmp)
{
  const std::string host_git = LAMMPS::has_git_info() ? LAMMPS::git_descriptor() : "";
  const std::string built = release(FRACTUM_BUILT_VERSION, FRACTUM_BUILT_GIT);
  const std::string host = release(lmp->version, host_git);
  if (built != host)
    lmp->error->all(FLERR,
                    "This Fractum plugin was built for LAMMPS {} and this is LAMMPS {}: rebuild "
                    "it against this LAMMPS's headers (make lammps-plugin)",
                    built, host);
  const int built_sizes[3] = {static_cast<int>(sizeof(bigint)),
                              static_cast<int>(FRACTUM_BUILT_TAGINT_BYTES),
                              static_cast<int>(sizeof(imageint))};
  const int host_sizes[3] = {lammps_extract_setting(lmp, "bigint"),
                             lammps_extract_setting(lmp, "tagint"),
                             lammps_extract_setting(lmp, "imageint")};
  if (built_sizes[0] != host_sizes[0] || built_sizes[1] != host_sizes[1] ||
      built_sizes[2] != host_sizes[2])
    lmp->error->all(FLERR,
                    "This Fractum plugin was built for LAMMPS integers of {}, {} and {} bytes "
                    "(bigint, tagint, imageint) and this LAMMPS has {}, {} and {}: rebuild it "
                    "with this LAMMPS's size setting (-DLAMMPS_SMALLBIG, BIGBIG or SMALLSMALL)",
                    built_sizes[0], built_sizes[1], built_sizes[2], host_sizes[0], host_sizes[1],
                    host_sizes[2]);
}

static Pair *pair_creator(LAMMPS *lmp)
{
  return new PairFractumGranular(lmp);
}

static Compute *loads_creator(LAMMPS *lmp, int narg, char **arg)
{
  return new ComputeFractumLoads(lmp, narg, arg);
}

template <class F> static Fix *fix_creator(LAMMPS *lmp, int narg, char **arg)
{
  return new F(lmp, narg, arg);
}

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  check_host(static_cast<LAMMPS *>(lmp));
  auto reg = (lammpsplugin_regfunc) regfunc;
  lammpsplugin_t plugin;
  // The plugin loader compares this with the running LAMMPS and warns on a mismatch, after
  // check_host has refused any.
  plugin.version = FRACTUM_LAMMPS_VERSION;
  plugin.author = "Fractum developers";
  plugin.handle = handle;

  plugin.style = "pair";
  plugin.name = "fractum/granular";
  plugin.info = "Fractum Hertz-Mindlin contact of spheres and poly-ellipsoids";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &pair_creator;
  (*reg)(&plugin, lmp);

  plugin.style = "fix";
  plugin.name = "fractum/nve/polyell";
  plugin.info = "Fractum velocity Verlet for rigid spheres and poly-ellipsoids";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_creator<FixFractumNvePolyell>;
  (*reg)(&plugin, lmp);

  plugin.name = "fractum/platens";
  plugin.info = "Fractum rigid box faces with prescribed speeds";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_creator<FixFractumPlatens>;
  (*reg)(&plugin, lmp);

  plugin.name = "fractum/fracture";
  plugin.info = "Fractum grain fracture: criteria and splits";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_creator<FixFractumFracture>;
  (*reg)(&plugin, lmp);

  plugin.name = "fractum/cohesion";
  plugin.info = "Fractum cohesive springs between the halves of split grains";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_creator<FixFractumCohesion>;
  (*reg)(&plugin, lmp);

  plugin.name = "fractum/dt";
  plugin.info = "Fractum's step against the contacts: adapted or checked";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_creator<FixFractumDt>;
  (*reg)(&plugin, lmp);

  plugin.style = "compute";
  plugin.name = "fractum/loads";
  plugin.info = "Fractum grain loads of the fracture check (moment, critical contacts)";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &loads_creator;
  (*reg)(&plugin, lmp);
}
