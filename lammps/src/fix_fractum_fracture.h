/* fix ID group fractum/fracture: Fractum's grain fracture (granular paper, Section 3) on the
   owned grains: Hoek-Brown on the average stress and the contact tensile stress, Weibull
   strengths, the split into two sub-poly-ellipsoids (the parent reshaped in place, the other
   half created with a tag that does not depend on the rank count). Every decision goes through
   libfractum's kernels (fractum_kernel_check, _split), the functions Fractum's own run calls.
   The cohesive springs that hold the halves together are fix fractum/cohesion's, which this
   fix hands each split's halves.

   fix ID group fractum/fracture mi M sigma_c S sigma_f S [weibull W XM]
       [weibull_on contact|both|particle] [size_exponent B] [comminution_limit L]
       [critical_contacts N] [ideal_plane yes|no] [plane_jitter yes|no] [seed N]

   Per-atom state: d2_fr_grain (strength factor, sample grain, splits, intact springs, parent).

   Global vector: 1 splits, 2 grains of the sample broken, 3 splits by Hoek-Brown, 4 by contacts,
   5 intact springs (fix fractum/cohesion's scalar; 0 without it), 6 elastic energy of the
   contacts (J), 7 energy dissipated in the contacts over the last step (J), 8 the last step
   whose end found failing grains (split at the start of the next; Fractum splits them at the
   end of that step; -1 before any), 9 the largest relative mass change of a split
   (|m+ + m- - M| / M: 0, the halves' masses add up exactly), 10 the largest momentum change of
   a split relative to M (|v| + |omega| r), 11 the deepest overlap of two halves at their split
   (m; 0: none), over the splits since LAMMPS started.

   The grain loads come from pair fractum/granular's sums (Pair::extract "fractum/sums"); the
   step against the contacts is fix fractum/dt's, which must follow this fix (it reads the
   splits of the step). */
#ifndef FRACTUM_FIX_FRACTURE_H
#define FRACTUM_FIX_FRACTURE_H

#include "fix.h"
#include "fractum_atoms.h"

#include <vector>

namespace LAMMPS_NS {

class FixFractumFracture : public Fix {
 public:
  FixFractumFracture(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void setup(int) override;
  void pre_exchange() override;
  void end_of_step() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;

 private:
  class FractumSums *sums = nullptr;
  FractumFractureLaw law{};
  double mi = 0, sigma_c = 0, sigma_f = 0, weibull_w = 0, weibull_xm = 0;
  int critical_contacts = 3, ideal_plane = 1, plane_jitter = 0, weibull = 0,
      weibull_sigma_c = 0, particle = 0;
  double size_exponent = -1.0;       // < 0: Eq. 18's 2/w
  double comminution_limit = 0.0;    // 0: every piece may split
  class FixFractumCohesion *cohesion = nullptr;    // found at init
  bigint seed = 1;
  bool split_evaluated = false;
  double failed_at = -1.0;
  double split_audit[3] = {0.0, 0.0, 0.0};

  /* A grain that failed at the end of a step, split at the next step's pre_exchange. */
  struct Decision {
    tagint tag;
    FractumTrigger trigger;
    double force[3], torque[3];
  };
  std::vector<Decision> decisions;    // every rank's, in tag order
  double counts[4] = {0, 0, 0, 0};    // splits, grains broken, by Hoek-Brown, by contacts
  double **shape = nullptr, **quat = nullptr, **inertia = nullptr, **grain = nullptr;
  double **walls = nullptr, **travel = nullptr;
  int walls_cols = 0;    // the faces' histories (42 columns), and the sleeve's (49)

  void arrays();
  double draw_strength(tagint tag, int generation, const FractumBody &b);
  class FixFractumCohesion *find_cohesion() const;
  void audit(const FractumBody &parent, const FractumBody &plus, const FractumBody &minus);
};

}    // namespace LAMMPS_NS

#endif
