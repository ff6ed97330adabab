/* Registers the Fractum styles with LAMMPS (`plugin load dist/fractumplugin.so`). */
#include "lammpsplugin.h"

#include "fix_fractum_fracture.h"
#include "fix_fractum_nve_polyell.h"
#include "fix_fractum_platens.h"
#include "pair_fractum_granular.h"

#include "lammps.h"

using namespace LAMMPS_NS;

static Pair *pair_creator(LAMMPS *lmp)
{
  return new PairFractumGranular(lmp);
}

template <class F> static Fix *fix_creator(LAMMPS *lmp, int narg, char **arg)
{
  return new F(lmp, narg, arg);
}

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  auto reg = (lammpsplugin_regfunc) regfunc;
  lammpsplugin_t plugin;
  // The plugin loader compares this with the running LAMMPS and warns on a mismatch; the styles
  // refuse to run on another version (fractum_check_version).
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
  plugin.info = "Fractum grain fracture: criteria, splits, cohesive springs";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_creator<FixFractumFracture>;
  (*reg)(&plugin, lmp);
}
