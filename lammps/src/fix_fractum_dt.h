/* fix ID group fractum/dt: Fractum's step against the contacts (as fix dt/reset changes the
   step): Fractum's frequency bound (libfractum's fractum_kernel_adapted_step and
   fractum_kernel_step_check on the frequency shares pair fractum/granular sums) keeps velocity
   Verlet stable.

   fix ID group fractum/dt EVERY [omega_dt X]
     EVERY     in (0, 2^53]: adapt as Fractum does with time.dt = "auto": every EVERY steps and in the
               step after a split (fix fractum/fracture), the step is shortened so that the
               estimated highest contact frequency omega gives omega dt = X when it is above
               (Fractum: X = 3 x safety). 0: never adapt, check the step at every step.
     omega_dt  X in [0.001, 2), default 0.6

   Both modes check the step at the setup: omega dt at or above 2 (unstable) stops the run
   with one sentence naming the step to use; above 1.6 a warning, once.

   Needs pair fractum/granular; after fix fractum/fracture when both are defined (it reads the
   splits of the step).

   Global vector: 1 the times the step was shortened, 2 the step (s). */
#ifdef FIX_CLASS
#else
#ifndef FRACTUM_FIX_DT_H
#define FRACTUM_FIX_DT_H

#include "fix.h"

namespace LAMMPS_NS {

class FixFractumDt : public Fix {
 public:
  FixFractumDt(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void setup(int) override;
  void end_of_step() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;

 private:
  class FractumSums *sums = nullptr;
  bigint every = 0;    // 0: check only
  double omega_dt = 0.6;
  bool warned = false;    // the omega dt warning given
  bool unstable_warned = false;    // the warning of unstable steps between adaptations given
  double shortened = 0.0;

  void adapt(double sum);
  void check();
  int step_verdict(double sum, double &wdt);
  void unstable_since_last(double sum);
  void schedule();
};

}    // namespace LAMMPS_NS

#endif
#endif
