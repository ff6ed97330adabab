/* fix ID group fractum/fracture: Fractum's grain fracture (granular paper,
   Section 3) on the owned grains: Hoek-Brown on the average stress and the contact tensile
   stress, Weibull strengths, the split into two sub-poly-ellipsoids (the parent reshaped in
   place, the other half created with a tag that does not depend on the rank count) and the
   cohesive springs. Every decision goes through libfractum's kernels (fractum_kernel_check,
   _split, _bond, _spring), the functions Fractum's own run calls.

   fix ID group fractum/fracture mi M sigma_c S sigma_f S [weibull W XM] [weibull_on contact|both] [cohesion KIC N]
       [critical_contacts N] [ideal_plane yes|no] [plane_jitter yes|no] [seed N]

   Per-atom state: d2_fr_grain (strength factor, sample grain, splits, intact springs, parent) and
   d2_fr_springs (21 doubles per spring slot, N slots):
     [partner tag, role (+1: this atom is A, -1: B), on_a (3), on_b (3), direction (3), f0, k,
      opening, last_gap (3), last_force (3), broken]
   Both atoms of a spring hold a copy and advance it identically, so a spring needs no
   communication beyond the ghost positions and orientations; a rank that owns both evaluates
   it once (spring_forces).

   Global vector: 1 splits, 2 grains of the sample broken, 3 splits by Hoek-Brown, 4 by contacts,
   5 intact springs, 6 elastic energy of the contacts (J), 7 energy dissipated in the contacts
   over the last step (J), 8 the last step whose end found failing grains (split at the start
   of the next; Fractum splits them at the end of that step; -1 before any), 9 the largest
   relative mass change of a split (|m+ + m- - M| / M: 0, the halves' masses add up exactly),
   10 the largest momentum change of a split relative to M (|v| + |omega| r), 11 the deepest
   overlap of two halves at their split (m; 0: none), over the splits since LAMMPS started.

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
  void post_force(int) override;
  void end_of_step() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;

  enum { SPRING_SLOT = 21 };

 private:
  class FractumSums *sums = nullptr;
  FractumFractureLaw law{};
  double mi = 0, sigma_c = 0, sigma_f = 0, weibull_w = 0, weibull_xm = 0, kic = 0;
  int springs = 0, critical_contacts = 3, ideal_plane = 1, plane_jitter = 0, weibull = 0,
      weibull_sigma_c = 0;
  int cohesion = 0;
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
  /* A split made, bonded in the post_force of the same step. */
  struct Pending {
    tagint a, b;
    FractumPending p;
  };
  std::vector<Pending> pending;    // every rank's, in tag order

  double counts[4] = {0, 0, 0, 0};    // splits, grains broken, by Hoek-Brown, by contacts
  double **shape = nullptr, **quat = nullptr, **inertia = nullptr, **grain = nullptr;
  double **slots = nullptr, **walls = nullptr, **travel = nullptr;

  void arrays();
  double draw_strength(tagint tag, int generation, const FractumBody &b);
  void spring_forces(bool advance);
  void bond();
  void audit(const FractumBody &parent, const FractumBody &plus, const FractumBody &minus);
};

}    // namespace LAMMPS_NS

#endif
