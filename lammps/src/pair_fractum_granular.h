/* pair_style fractum/granular: Fractum's Hertz-Mindlin contact law between spheres and
   poly-ellipsoids (libfractum's fractum_kernel_pair_row: the very function Fractum's own contact
   loop runs, over one neighbour-list row per call, with Fractum's separated pairs' skip when the
   per-atom travels d2_fr_travel are declared), with per-contact history through LAMMPS's
   neighbour-history fix.

   pair_style fractum/granular
   pair_coeff * * young E poisson NU [restitution e] [friction MU]

   restitution turns on viscous damping (Fractum's `damping` effect), friction the Mindlin
   tangential force with the Coulomb limit (`friction`). Needs atom_style sphere, newton_pair off,
   comm_modify vel yes and the per-atom arrays of fractum_atoms.h. */
#ifdef PAIR_CLASS
#else
#ifndef FRACTUM_PAIR_GRANULAR_H
#define FRACTUM_PAIR_GRANULAR_H

#include "fractum_atoms.h"
#include "fractum_sums.h"
#include "pair.h"

#include <vector>

namespace LAMMPS_NS {

class PairFractumGranular : public Pair {
 public:
  /* Doubles per contact record in the neighbour history: a FractumPairMemory (7), then the
     pair's reach for the separated pairs' skip (fractum_kernel_pair_row). */
  static constexpr int HISTORY = 8;
  PairFractumGranular(class LAMMPS *);
  ~PairFractumGranular() override;
  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void transfer_history(double *, double *, int, int) override;
  double memory_usage() override;

  /* The fixes take what they need through extract: "fractum/sums" (the FractumSums of each
     evaluation), "fractum/material" (FractumMaterial: the pair_coeff values, from which the
     walls build their law), "fractum/shapes" (int: bodies other than spheres take part). */
  void *extract(const char *, int &) override;

 private:
  FractumMaterial material{};
  FractumContactLaw law{};
  /* Bodies that are not spheres take part: Fractum's POLY contact variant. */
  int shapes = 0;
  FractumSums sums;
  double **shape_arr = nullptr, **quat_arr = nullptr, **inertia_arr = nullptr;
  double **grain_arr = nullptr;

  class FractumNeighHistoryView *history = nullptr;
  class Fix *dummy = nullptr;
  std::vector<FractumBody> bodies;
  std::vector<FractumPlacement> places;
  /* The touching contacts of this evaluation (libfractum's FractumTouching: the force on i, the
     torques on i and j, and what fracture and the step adaptation read of it) and their sides in
     summing order (2 n for atom i of touching[n], 2 n + 1 for atom j), as
     fractum_kernel_pair_list gathers them over the whole neighbour list, summed into their atoms
     by one fractum_kernel_sum_contacts call. Grown, never shrunk nor cleared: the kernel writes
     what it counts. */
  std::vector<FractumTouching> touching;
  std::vector<int32_t> codes;
  // Per evaluation: the bodies' tags, the reshaped bodies' tags and the travels.
  std::vector<int64_t> keys, reshaped_keys;
  std::vector<double> travel;
  double maxrad = 0.0;
  void check_history();
};

}    // namespace LAMMPS_NS

#endif
#endif
