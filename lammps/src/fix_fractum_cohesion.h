/* fix ID group fractum/cohesion KIC N: the cohesive springs that hold the halves of each split
   of fix fractum/fracture together (granular paper, Section 3.4): N springs per break plane,
   their fracture energy from the toughness KIC (Pa m^0.5) and the pair's material. Each split's
   springs are made in the post_force of the step that split, from the halves' forces at their
   new shapes (fractum_kernel_bond), and evaluated at every step (fractum_kernel_spring) until
   their force falls to zero and they break; a grain held by intact springs is not checked for
   failure. Needs fix fractum/fracture (the splits it bonds); define it after that fix.

   Per-atom state: d2_fr_springs (21 doubles per spring slot, N slots):
     [partner tag, role (+1: this atom is A, -1: B), on_a (3), on_b (3), direction (3), f0, k,
      opening, last_gap (3), last_force (3), broken]
   and column 4 of d2_fr_grain (the atom's intact springs). Both atoms of a spring hold a copy
   at the same slot and advance it identically, so a spring needs no communication beyond the
   ghost positions and orientations; a rank that owns both ends evaluates it once.

   Global scalar: the intact springs. */
#ifndef FRACTUM_FIX_COHESION_H
#define FRACTUM_FIX_COHESION_H

#include "fix.h"
#include "fractum_atoms.h"

#include <vector>

namespace LAMMPS_NS {

class FixFractumCohesion : public Fix {
 public:
  FixFractumCohesion(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void setup(int) override;
  void post_force(int) override;
  double compute_scalar() override;

  enum { SPRING_SLOT = 21 };

  /* For fix fractum/fracture, which splits the grains this fix bonds. */
  /* The springs per break plane. */
  int springs_per_plane() const { return springs; }
  /* The fracture energy G_c (J/m^2) of the toughness at the material's E and nu. */
  double cohesive_energy(const FractumMaterial &m) const;
  /* The fracture law the bonds are made with (its springs and G_c this fix's). */
  void use_law(const FractumFractureLaw &l) { law = l; }
  /* Owned atom i holds no springs (a split's parent reshaped, a half created). */
  void clear(int i);
  /* A split of this step (every rank's, in parent tag order): halves a and b, bonded in this
     step's post_force. */
  void bond_next(tagint a, tagint b, const FractumPending &p) { pending.push_back({a, b, p}); }

 private:
  FractumFractureLaw law{};
  double kic = 0.0;
  int springs = 0;
  double **shape = nullptr, **quat = nullptr, **inertia = nullptr, **grain = nullptr;
  double **slots = nullptr;
  struct Pending {
    tagint a, b;
    FractumPending p;
  };
  std::vector<Pending> pending;

  void arrays();
  void spring_forces(bool advance);
  void bond();
};

}    // namespace LAMMPS_NS

#endif
