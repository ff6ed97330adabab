/* fix ID group fractum/nve/polyell: Fractum's velocity Verlet for rigid grains (libfractum's
   fractum_kernel_kick_drift_atoms and fractum_kernel_kick_atoms over LAMMPS's arrays, one call
   per half step, the functions Fractum's integrator runs):
   spheres kick their angular velocity, poly-ellipsoids their angular momentum, and orientations
   turn by the midpoint rule. The orientations (d2_fr_orient) go to the ghost atoms every step,
   with, when d2_fr_travel is declared, each body's travel: the sum over its drifts of how far it
   may have moved (fractum_kernel_travel), which pair fractum/granular's skip reads. */
#ifndef FRACTUM_FIX_NVE_POLYELL_H
#define FRACTUM_FIX_NVE_POLYELL_H

#include "fix.h"
#include "fractum_atoms.h"

namespace LAMMPS_NS {

class FixFractumNvePolyell : public Fix {
 public:
  FixFractumNvePolyell(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void setup(int) override;
  void initial_integrate(int) override;
  void post_integrate() override;
  void final_integrate() override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;

 private:
  double **shape = nullptr, **quat = nullptr, **inertia = nullptr;
  double **last = nullptr;      // d2_fr_last, when declared
  double **travel = nullptr;    // d2_fr_travel, when declared
  bool resume = false;
  typedef FractumStatus (*Kernel)(const FractumAtomRows *, double);
  void arrays();
  void advance(Kernel step, const char *name);
};

}    // namespace LAMMPS_NS

#endif
