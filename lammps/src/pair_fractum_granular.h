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

  /* The contact law, for the walls (fix fractum/platens) and fracture. */
  double young = 0.0, poisson = 0.0, restitution = -1.0, friction = -1.0;
  FractumContactLaw law{};
  /* The same law with the Coulomb coefficient mu (the faces may take their own). */
  FractumContactLaw law_with(double mu);
  /* Bodies that are not spheres take part: Fractum's POLY contact variant. */
  int shapes = 0;

  /* Grain fracture reads, per owned atom, its grain load (libfractum's FractumGrainLoad: the
     moment sum of its contacts and its critical contacts, summed by
     fractum_kernel_grain_load_add as Fractum's check sums them): the pair and the walls fill
     them while `recording` is set (by fix fractum/fracture). */
  bool recording = false;
  double sigma_f = 0.0;    // contact tensile strength (Pa) at Weibull factor 1
  std::vector<FractumGrainLoad> loads;    // 1 per owned atom
  double elastic_energy = 0.0, dissipated = 0.0;    // this rank's, last evaluation
  int contacts = 0;
  /* Record one contact of owned atom i: force f on it at point p. */
  void record(int i, const double *f, const double *p, double hertz_force, double radius,
              double strength);
  /* Fractum's step adaptation (fix fractum/fracture adapt_dt) reads, per owned atom, the sum of
     its contacts' frequency shares: the pair and the walls fill it in an evaluation while
     `frequency_due` is set. */
  bool frequency_due = false;
  std::vector<double> shares;    // 1 per owned atom
  /* Add contact c's share to owned atom i (body b; its partner, nullptr for a wall). */
  void add_share(int i, const FractumContact &c, const FractumBody &b,
                 const FractumBody *partner);
  /* Tags of bodies reshaped by a split: their contacts' held Hertz radii start afresh. */
  std::vector<tagint> reshaped;

  double **shape_arr = nullptr, **quat_arr = nullptr, **inertia_arr = nullptr;
  double **grain_arr = nullptr;

 protected:
  class FractumNeighHistoryView *history = nullptr;
  class Fix *dummy = nullptr;
  std::vector<FractumBody> bodies;
  std::vector<FractumPlacement> places;
  /* One touching contact of this evaluation: the force on i, the torques on i and j, and what
     fracture and the step adaptation read of it. */
  struct Touching {
    int i, j;    // the row's owned atom and its partner (owned or ghost)
    double force[3], torque_i[3], torque_j[3], point[3];
    double hertz_force, radius, share_i, share_j;
  };
  std::vector<Touching> touching;
  /* What an owned atom sums: its partner's tag (the order of the sum) and which side of which
     contact (2 n for atom i of touching[n], 2 n + 1 for atom j). Sorted instead of the contacts,
     which are ten times larger. */
  struct Side {
    int atom;
    tagint partner;
    int side;
  };
  std::vector<Side> sides, order;
  // Each atom's first slot in `order` and a cursor per atom (the counting sort).
  std::vector<int> first, cursor;
  /* Per evaluation: the bodies' tags and travels; per row: the kernel's touching contacts,
     their candidates, and a scratch copy of the row's records. */
  std::vector<int64_t> keys;
  std::vector<double> travel, row;
  std::vector<FractumContact> row_out;
  std::vector<int> row_at;
  double maxrad = 0.0;
  void check_history();
  static void reset_record(double *r);
};

}    // namespace LAMMPS_NS

#endif
#endif
