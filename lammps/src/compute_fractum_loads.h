/* compute ID group fractum/loads: each atom's grain load at fix fractum/fracture's last check,
   as pair fractum/granular summed it for that check (libfractum's FractumGrainLoad, added
   contact by contact by fractum_kernel_grain_load_add as Fractum's own check adds them): the
   near-failure map of a sample (dump c_ID[10] and c_ID[11] to see which grains are close to
   breaking, and where).

   Per-atom array, 22 columns, FractumGrainLoad's fields in its order:
     1-9    the moment of the atom's contact forces about its centre, row-major (N m)
     10     the number of critical contacts (contact tensile stress above the grain's strength)
     11-13  the three largest contact tensile stresses (Pa), largest first, 0 past the count
     14-22  their points (m), x y z each
   Zeros for atoms outside the group, atoms held by intact springs (not checked), atoms made by
   the last check's splits and before the first force evaluation. Fractum's runs give the same
   numbers through fractum_copy_grain_loads (the Python module's Simulation.grain_loads).

   Needs pair fractum/granular and fix fractum/fracture (the loads are summed for its check). */
#ifdef COMPUTE_CLASS
#else
#ifndef FRACTUM_COMPUTE_LOADS_H
#define FRACTUM_COMPUTE_LOADS_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputeFractumLoads : public Compute {
 public:
  static constexpr int COLUMNS = 22;

  ComputeFractumLoads(class LAMMPS *, int, char **);
  ~ComputeFractumLoads() override;
  void init() override;
  void compute_peratom() override;
  double memory_usage() override;

 private:
  class FractumSums *sums = nullptr;
  int nmax = 0;
  double **loads = nullptr;
};

}    // namespace LAMMPS_NS

#endif
#endif
