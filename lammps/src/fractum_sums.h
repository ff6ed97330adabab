/* What one force evaluation sums for the fixes: owned by pair fractum/granular and handed out
   through `Pair::extract("fractum/sums", dim)`, as LAMMPS's styles share their data.

   - Grain loads (libfractum's FractumGrainLoad per owned atom: the moment sum of its contacts
     and its critical contacts, added by fractum_kernel_grain_load_add as Fractum's check adds
     them), while fix fractum/fracture wants them (`want_loads`).
   - Frequency shares (per owned atom, the sum of its contacts' shares of Fractum's frequency
     bound), in an evaluation that fix fractum/dt asked for (`want_shares`).
   - The contacts' elastic energy and dissipation of this rank.
   - What fix fractum/fracture tells fix fractum/dt about splits: a split made in this step
     (its halves' first evaluation), splits waiting for the next step.

   The pair starts each evaluation (`begin`), the pair and fix fractum/platens add to it, the
   fixes read it after. Nothing here decides: the kernels do. */
#ifndef FRACTUM_SUMS_H
#define FRACTUM_SUMS_H

#include "fractum_atoms.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace LAMMPS_NS {

class FractumSums {
 public:
  /* fix fractum/fracture: every evaluation sums grain loads, a contact critical above sigma_f
     (Pa) times the grain's Weibull factor. */
  void want_loads(double sigma_f_at_factor_1, bool particle_strength)
  {
    loads_on = true;
    sigma_f = sigma_f_at_factor_1;
    particle = particle_strength;
  }
  /* fix fractum/dt: the next evaluation sums frequency shares (`on`), or not. */
  void want_shares(bool on) { shares_due = on; }
  bool shares_wanted() const { return shares_due; }
  bool loads_wanted() const { return loads_on; }
  /* The critical contact threshold at Weibull factor 1 (Pa), and the arrays the pair's bulk
     sum (fractum_kernel_sum_contacts) adds to after `begin`: loads while wanted, shares while
     due. */
  double threshold() const { return sigma_f; }
  /* The Weibull factor is the particle strength: the threshold is sigma_f times its cube root. */
  bool particle_strength() const { return particle; }
  FractumGrainLoad *loads_data() { return loads.data(); }
  double *shares_data() { return shares.data(); }

  /* The pair, at the start of an evaluation of `nlocal` owned atoms. */
  void begin(int nlocal)
  {
    if (loads_on) loads.assign(nlocal, FractumGrainLoad{});
    if (shares_due) shares.assign(nlocal, 0.0);
    elastic_energy = dissipated = 0.0;
  }
  /* One contact of owned atom i (not held by springs: `intact` 0): force `f` on it at point
     `p`, its Hertz force and radius, the grain's Weibull factor `strength`; a no-op unless
     loads are wanted. */
  void add_load(LAMMPS *lmp, const char *style, int i, const double *centre, const double *f,
                const double *p, double hertz_force, double radius, double poisson,
                double strength)
  {
    if (!loads_on) return;
    int status = fractum_kernel_grain_load_add(&loads[i], centre, f, p, hertz_force, radius,
                                               poisson,
                                               particle ? sigma_f * std::cbrt(strength)
                                                        : sigma_f * strength);
    if (status != FRACTUM_OK) fractum_kernel_failed(lmp, style, "grain_load_add", status);
  }
  /* Contact c's share of owned atom i's row (body b; its partner, nullptr for a wall). */
  void add_share(LAMMPS *lmp, const char *style, const FractumContactLaw &law, int i,
                 const FractumContact &c, const FractumBody &b, const FractumBody *partner)
  {
    double share = 0.0;
    int status = fractum_kernel_frequency_share(&law, &c, &b, partner, &share);
    if (status != FRACTUM_OK) fractum_kernel_failed(lmp, style, "frequency_share", status);
    shares[i] += share;
  }
  /* A share computed elsewhere (both atoms of a pair contact at once). */
  void add_share(int i, double share) { shares[i] += share; }
  void add_energy(double elastic, double dissipation)
  {
    elastic_energy += elastic;
    dissipated += dissipation;
  }

  /* Owned atom i's grain load of the last evaluation (nullptr before any). */
  const FractumGrainLoad *load(int i) const
  {
    return i < static_cast<int>(loads.size()) ? &loads[i] : nullptr;
  }
  /* The largest row of the frequency bound over every rank's owned atoms (the shares of the last
     evaluation that summed them). */
  double largest_share(MPI_Comm world, int nlocal) const
  {
    double local = 0.0, all = 0.0;
    if (static_cast<int>(shares.size()) >= nlocal)
      for (int i = 0; i < nlocal; i++) local = local > shares[i] ? local : shares[i];
    MPI_Allreduce(&local, &all, 1, MPI_DOUBLE, MPI_MAX, world);
    return all;
  }
  double energy() const { return elastic_energy; }
  double dissipation() const { return dissipated; }

  /* fix fractum/fracture: bodies reshaped by this step's splits (their contacts' held Hertz
     radii start afresh in the next evaluation). */
  void reshape(tagint tag) { reshaped.push_back(tag); }
  /* The pair: the reshaped tags, sorted, for this evaluation; cleared by `reshaped_done`. */
  const std::vector<tagint> &reshaped_sorted()
  {
    std::sort(reshaped.begin(), reshaped.end());
    return reshaped;
  }
  void reshaped_done() { reshaped.clear(); }

  /* fix fractum/fracture to fix fractum/dt: this step split grains (`now`), grains found failing
     at this step's end split in the next (`next`). */
  void splits(bool now, bool next)
  {
    split_now = now;
    split_next = next;
  }
  bool split_this_step() const { return split_now; }
  bool split_next_step() const { return split_next; }

  double memory_usage() const
  {
    return static_cast<double>(loads.capacity() * sizeof(FractumGrainLoad) +
                               shares.capacity() * sizeof(double) +
                               reshaped.capacity() * sizeof(tagint));
  }

 private:
  bool loads_on = false, shares_due = false, split_now = false, split_next = false;
  bool particle = false;
  double sigma_f = 0.0;
  std::vector<FractumGrainLoad> loads;
  std::vector<double> shares;
  std::vector<tagint> reshaped;
  double elastic_energy = 0.0, dissipated = 0.0;
};

/* The sums of pair fractum/granular (through Pair::extract), or one sentence naming `style`
   and what it needs. */
FractumSums *fractum_sums(LAMMPS *lmp, const char *style);

}    // namespace LAMMPS_NS

#endif
