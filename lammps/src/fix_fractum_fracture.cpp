#include "fix_fractum_fracture.h"

#include "fix_fractum_cohesion.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "library.h"
#include "modify.h"
#include "fractum_sums.h"
#include "pair.h"
#include "update.h"
#include "utils.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

static const char *STYLE = "fix fractum/fracture";
static const char *USAGE = "mi M sigma_c S sigma_f S [weibull W XM] "
                           "[weibull_on contact|both|particle] [size_exponent B] "
                           "[comminution_limit L] [critical_contacts N] [ideal_plane yes|no] "
                           "[plane_jitter yes|no] [seed N]";

FixFractumFracture::FixFractumFracture(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  bool have_mi = false, have_sc = false, have_sf = false;
  auto yesno = [&](int k) -> int {
    std::string v = k < narg ? arg[k] : "";
    if (v == "yes") return 1;
    if (v == "no") return 0;
    error->all(FLERR, "{}: {} takes yes or no, not '{}'", STYLE, arg[k - 1], v);
    return 0;
  };
  auto num = [&](int k, const char *what) -> double {
    if (k >= narg) error->all(FLERR, "{}: {} needs a value: {}", STYLE, what, USAGE);
    return utils::numeric(FLERR, arg[k], false, lmp);
  };
  int iarg = 3;
  while (iarg < narg) {
    std::string key = arg[iarg];
    if (key == "mi") {
      mi = num(iarg + 1, "mi");
      if (!(mi > 0)) error->all(FLERR, "{}: mi = {} must be > 0", STYLE, mi);
      have_mi = true;
      iarg += 2;
    } else if (key == "sigma_c") {
      sigma_c = num(iarg + 1, "sigma_c");
      if (!(sigma_c > 0)) error->all(FLERR, "{}: sigma_c = {} must be > 0 (Pa)", STYLE, sigma_c);
      have_sc = true;
      iarg += 2;
    } else if (key == "sigma_f") {
      sigma_f = num(iarg + 1, "sigma_f");
      if (!(sigma_f > 0)) error->all(FLERR, "{}: sigma_f = {} must be > 0 (Pa)", STYLE, sigma_f);
      have_sf = true;
      iarg += 2;
    } else if (key == "weibull") {
      weibull_w = num(iarg + 1, "weibull");
      weibull_xm = num(iarg + 2, "weibull");
      if (!(weibull_w > 0) || !(weibull_xm > 0))
        error->all(FLERR, "{}: weibull W XM need W > 0 and XM > 0 (m), got {} {}", STYLE,
                   weibull_w, weibull_xm);
      weibull = 1;
      iarg += 3;
    } else if (key == "weibull_on") {
      if (iarg + 1 >= narg)
        error->all(FLERR, "{}: weibull_on needs contact, both or particle", STYLE);
      std::string on = arg[iarg + 1];
      particle = 0;
      if (on == "contact")
        weibull_sigma_c = 0;
      else if (on == "both")
        weibull_sigma_c = 1;
      else if (on == "particle")
        weibull_sigma_c = particle = 1;
      else
        error->all(FLERR, "{}: weibull_on = {} must be contact, both or particle", STYLE, on);
      iarg += 2;
    } else if (key == "size_exponent") {
      // fracture.size_exponent's range (docs/scenes.md).
      size_exponent = num(iarg + 1, "size_exponent");
      if (!(size_exponent >= 0.0 && size_exponent <= 6.0))
        error->all(FLERR, "{}: size_exponent = {} must lie in [0, 6]", STYLE, size_exponent);
      iarg += 2;
    } else if (key == "comminution_limit") {
      comminution_limit = num(iarg + 1, "comminution_limit");
      if (!(comminution_limit > 0.0) || !std::isfinite(comminution_limit))
        error->all(FLERR, "{}: comminution_limit = {} must be > 0 (m)", STYLE, comminution_limit);
      iarg += 2;
    } else if (key == "cohesion") {
      error->all(FLERR,
                 "{}: cohesion is not an argument of this fix: the cohesive springs are fix "
                 "fractum/cohesion, `fix ID all fractum/cohesion KIC N` after this fix",
                 STYLE);
    } else if (key == "critical_contacts") {
      double n = num(iarg + 1, "critical_contacts");
      double lo = 0.0, hi = 0.0;
      fractum_kernel_fracture_range("critical_contacts", &lo, &hi);
      if (!(n >= lo && n <= hi && n == std::floor(n)))
        error->all(FLERR, "{}: critical_contacts = {} must be an integer in {}..{}", STYLE, n, lo,
                   hi);
      critical_contacts = static_cast<int>(n);
      iarg += 2;
    } else if (key == "ideal_plane") {
      ideal_plane = yesno(iarg + 1);
      iarg += 2;
    } else if (key == "plane_jitter") {
      plane_jitter = yesno(iarg + 1);
      iarg += 2;
    } else if (key == "seed") {
      double s = num(iarg + 1, "seed");
      if (!(s >= 0 && s == std::floor(s)))
        error->all(FLERR, "{}: seed = {} must be an integer >= 0", STYLE, s);
      seed = static_cast<bigint>(s);
      iarg += 2;
    } else if (key == "adapt_dt" || key == "adapt_omega_dt") {
      error->all(FLERR,
                 "{}: {} is not an argument of this fix: the step adaptation is fix fractum/dt, "
                 "`fix ID all fractum/dt EVERY omega_dt X` after this fix",
                 STYLE, key);
    } else {
      error->all(FLERR, "{}: unknown argument {}; allowed: {}", STYLE, key, USAGE);
    }
  }
  if (!have_mi || !have_sc || !have_sf)
    error->all(FLERR, "{}: mi, sigma_c and sigma_f are required: {}", STYLE, USAGE);
  if ((particle || size_exponent >= 0.0) && !weibull)
    error->all(FLERR, "{}: weibull_on particle and size_exponent scale the Weibull factor: give "
               "weibull W XM", STYLE);
  force_reneighbor = 1;
  next_reneighbor = -1;
  nevery = 1;
  vector_flag = 1;
  size_vector = 11;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
}

int FixFractumFracture::setmask()
{
  return PRE_EXCHANGE | END_OF_STEP;
}

void FixFractumFracture::arrays()
{
  fractum_grain_arrays(lmp, STYLE, shape, quat, inertia, grain);
  walls = fractum_array_if(lmp, "fr_walls", &walls_cols);
  travel = fractum_array_if(lmp, "fr_travel");
}

/* The fix fractum/cohesion that bonds the halves, nullptr without one. */
FixFractumCohesion *FixFractumFracture::find_cohesion() const
{
  for (auto &f : modify->get_fix_list())
    if (utils::strmatch(f->style, "^fractum/cohesion$")) return static_cast<FixFractumCohesion *>(f);
  return nullptr;
}

void FixFractumFracture::init()
{
  sums = fractum_sums(lmp, STYLE);
  int dim = 0;
  const auto *material = static_cast<const FractumMaterial *>(
      force->pair_match("fractum/granular", 1)->extract("fractum/material", dim));
  // The step against the contacts is fix fractum/dt's: a run that breaks grains has one.
  bool dt_fix = false;
  for (auto &f : modify->get_fix_list()) dt_fix |= utils::strmatch(f->style, "^fractum/dt$");
  if (!dt_fix)
    error->all(FLERR,
               "{} needs fix fractum/dt after it (the step against the contacts, which splits "
               "stiffen): `fix dt all fractum/dt 10` adapts it every 10 steps as Fractum's "
               "time.dt = \"auto\", `fix dt all fractum/dt 0` only checks it at every step",
               STYLE);
  arrays();    // stops with the first missing array named
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "{} needs an atom map (`atom_modify map array`)", STYLE);
  law.mi = mi;
  law.sigma_c = sigma_c;
  law.sigma_f = sigma_f;
  law.poisson = material->poisson;
  law.critical_contacts = critical_contacts;
  law.ideal_plane = ideal_plane;
  law.plane_jitter = plane_jitter;
  law.weibull_sigma_c = weibull ? weibull_sigma_c : 0;
  law.particle_strength = weibull ? particle : 0;
  law.comminution_limit = comminution_limit;
  // The cohesive springs, when a fix fractum/cohesion bonds the halves: the split places its
  // springs' points, and that fix bonds with this law.
  cohesion = find_cohesion();
  law.springs = cohesion ? cohesion->springs_per_plane() : 0;
  law.gc = cohesion ? cohesion->cohesive_energy(*material) : 0.0;
  if (cohesion) cohesion->use_law(law);
  sums->want_loads(sigma_f, law.particle_strength != 0);
}

/* The Weibull factor of grain `tag` after `generation` splits, drawn as Fractum's run draws it
   (fractum_kernel_grain_strength_sized: keyed by seed, grain and generation, the size exponent
   given or Eq. 18's 2/w; 1 without weibull). */
double FixFractumFracture::draw_strength(tagint tag, int generation, const FractumBody &b)
{
  if (!weibull) return 1.0;
  double factor = 0.0;
  const double beta = size_exponent >= 0.0 ? size_exponent : 2.0 / weibull_w;
  int status = fractum_kernel_grain_strength_sized(
      static_cast<uint64_t>(seed), static_cast<uint64_t>(tag), static_cast<uint32_t>(generation),
      &b, weibull_w, beta, weibull_xm, &factor);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "grain_strength", status);
  return factor;
}

void FixFractumFracture::setup(int)
{
  arrays();
  // Grains the data file gave no strength (0) draw theirs; the sample grain is the atom itself.
  FractumBody b;
  for (int i = 0; i < atom->nlocal; i++) {
    if (grain[i][1] == 0.0) grain[i][1] = static_cast<double>(atom->tag[i]);
    if (grain[i][0] <= 0.0) {
      fractum_body(atom, shape, quat, inertia, i, b);
      grain[i][0] = draw_strength(atom->tag[i], static_cast<int>(grain[i][2]), b);
    }
  }
  // Splits restored from a restart file are made at the first step (fix fractum/dt schedules
  // its shares for them).
  sums->splits(false, !decisions.empty());
}

void FixFractumFracture::end_of_step()
{
  arrays();
  std::vector<Decision> mine;
  FractumBody b;
  FractumTrigger t;
  const int nlocal = atom->nlocal;
  if (nlocal > 0 && !sums->load(nlocal - 1)) return;    // no force evaluation yet
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit) || grain[i][3] != 0.0) continue;
    const FractumGrainLoad &load = *sums->load(i);
    bool any = false;
    for (int k = 0; k < 9; k++) any |= load.moment[k] != 0.0;
    if (!any) continue;
    fractum_body(atom, shape, quat, inertia, i, b);
    int status = fractum_kernel_check(&law, &b, grain[i][0], load.moment, atom->torque[i],
                                      static_cast<size_t>(load.count), load.point,
                                      load.count > 0 ? load.stress[0] : 0.0, &t);
    if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "check", status);
    if (t.kind == 0) continue;
    // A grain whose shape forbids breaking fails without a split (as in Fractum): no decision,
    // so no reneighbouring for it (in the main job such pieces failed at most steps late in the
    // run, and each decision cost a neighbour build).
    int can = 1;
    status = fractum_kernel_can_break(&b, &can);
    if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "can_break", status);
    if (!can) continue;
    Decision d;
    d.tag = atom->tag[i];
    d.trigger = t;
    for (int k = 0; k < 3; k++) {
      d.force[k] = atom->f[i][k];
      d.torque[k] = atom->torque[i][k];
    }
    mine.push_back(d);
  }
  decisions = fractum_gather_all(mine, world, comm->nprocs);
  if (!decisions.empty()) {
    std::sort(decisions.begin(), decisions.end(),
              [](const Decision &x, const Decision &y) { return x.tag < y.tag; });
    next_reneighbor = update->ntimestep + 1;
    failed_at = static_cast<double>(update->ntimestep);
  }
  // For fix fractum/dt (its end of step comes next): the halves of this step's splits had
  // their first evaluation, and the grains found failing split in the next step.
  sums->splits(split_evaluated, !decisions.empty());
  split_evaluated = false;
}

/* What a split must keep: the parent's mass exactly, its momentum (to rounding), and the halves
   apart (vector entries 11-13: maxima over the splits, reduced over the ranks at the end of
   each pre_exchange that split). */
void FixFractumFracture::audit(const FractumBody &parent, const FractumBody &plus,
                               const FractumBody &minus)
{
  const double mass_error = std::fabs((plus.mass + minus.mass) - parent.mass) / parent.mass;
  double dp = 0.0, speed = 0.0, spin = 0.0;
  for (int d = 0; d < 3; d++) {
    const double p = plus.mass * plus.vel[d] + minus.mass * minus.vel[d];
    dp += (p - parent.mass * parent.vel[d]) * (p - parent.mass * parent.vel[d]);
    speed += parent.vel[d] * parent.vel[d];
    spin += parent.omega[d] * parent.omega[d];
  }
  // Relative to the largest speed of a point of the parent.
  const double scale = parent.mass * (std::sqrt(speed) + std::sqrt(spin) * parent.radius);
  const double momentum_error = scale > 0.0 ? std::sqrt(dp) / scale : std::sqrt(dp);
  FractumGeometry g;
  const double guess[3] = {0.0, 0.0, 0.0};
  int status = fractum_kernel_convex_contact(&plus, &minus, guess, &g);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "convex_contact", status);
  const double overlap = g.touching ? g.depth : 0.0;
  split_audit[0] = std::max(split_audit[0], mass_error);
  split_audit[1] = std::max(split_audit[1], momentum_error);
  split_audit[2] = std::max(split_audit[2], overlap);
}

void FixFractumFracture::pre_exchange()
{
  if (next_reneighbor != update->ntimestep || decisions.empty()) return;
  arrays();
  // The splits of the owned parents, in tag order.
  struct Made {
    tagint parent;
    int criterion;     // 1 Hoek-Brown, 2 contacts
    int first_split;   // the parent was a grain of the sample
    FractumBody minus;
    double grain[4];
    FractumPending p;
  };
  std::vector<Made> mine;
  FractumBody b;
  FractumSplit out;
  for (const Decision &d : decisions) {
    int i = atom->map(d.tag);
    if (i < 0 || i >= atom->nlocal) continue;
    fractum_body(atom, shape, quat, inertia, i, b);
    const int generation = static_cast<int>(grain[i][2]);
    double angles[3];
    const double *jitter = nullptr;
    if (b.sphere && plane_jitter) {
      int js = fractum_kernel_grain_jitter(static_cast<uint64_t>(seed),
                                           static_cast<uint64_t>(d.tag),
                                           static_cast<uint32_t>(generation), angles);
      if (js != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "grain_jitter", js);
      jitter = angles;
    }
    int status = fractum_kernel_split(&law, &b, d.force, d.torque, &d.trigger, jitter, &out);
    if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "split", status);
    if (out.axis < 0) continue;    // the shape forbids breaking (Section 3.3.3)
    audit(b, out.plus, out.minus);
    Made m;
    std::memset(&m, 0, sizeof m);
    m.parent = d.tag;
    m.criterion = d.trigger.kind;
    m.first_split = generation == 0;
    m.minus = out.minus;
    m.p = out.pending;
    // The parent becomes the + half in place.
    fractum_store_body(atom, shape, quat, inertia, i, out.plus);
    grain[i][2] = generation + 1;
    grain[i][0] = draw_strength(d.tag, generation + 1, out.plus);
    grain[i][3] = 0.0;
    // Every face's and the sleeve's held Hertz radius starts afresh for the new shape.
    if (walls)
      for (int w = 0; w < walls_cols / WALL_SLOT; w++) walls[i][WALL_SLOT * w + 6] = 0.0;
    if (cohesion) cohesion->clear(i);
    m.grain[1] = grain[i][1];
    m.grain[2] = generation + 1;
    mine.push_back(m);
  }
  // Every rank learns every split; the new halves get tags after the largest one, in parent
  // tag order, so that the tags do not depend on the rank count.
  std::vector<Made> all = fractum_gather_all(mine, world, comm->nprocs);
  std::sort(all.begin(), all.end(), [](const Made &x, const Made &y) { return x.parent < y.parent; });
  tagint maxtag_local = 0, maxtag = 0;
  for (int i = 0; i < atom->nlocal; i++) maxtag_local = std::max(maxtag_local, atom->tag[i]);
  MPI_Allreduce(&maxtag_local, &maxtag, 1, MPI_LMP_TAGINT, MPI_MAX, world);
  const int n = static_cast<int>(all.size());
  std::vector<tagint> ids(n);
  std::vector<int> types(n);
  std::vector<double> xs(3 * n), vs(3 * n);
  for (int k = 0; k < n; k++) {
    ids[k] = maxtag + 1 + k;
    int parent = atom->map(all[k].parent);
    // The half takes the parent's type; only the parent's owner knows it, so types travel as
    // the parent's in a second pass below when the owner differs (all grains share a type in
    // Fractum's exports).
    types[k] = parent >= 0 ? atom->type[parent] : 1;
    for (int d = 0; d < 3; d++) {
      xs[3 * k + d] = all[k].minus.pos[d];
      vs[3 * k + d] = all[k].minus.vel[d];
    }
  }
  std::vector<int> type_all(n);
  MPI_Allreduce(types.data(), type_all.data(), n, MPI_INT, MPI_MAX, world);
  if (n > 0) {
    // A half at a position or speed that is not a finite number comes from a grain the run
    // had already lost: named by grain and step before LAMMPS is asked to place it.
    for (int k = 0; k < n; k++)
      for (int d = 0; d < 3; d++)
        if (!std::isfinite(xs[3 * k + d]) || !std::isfinite(vs[3 * k + d]))
          error->all(FLERR,
                     "{}: at step {} grain {} splits into a half at position ({}, {}, {}) m "
                     "moving at ({}, {}, {}) m/s, which is not a finite state: the run had "
                     "lost the grain before it broke (a velocity or force beyond any contact's, "
                     "as from a data file's Velocities line or a time step too long for the "
                     "contacts)",
                     STYLE, update->ntimestep, all[k].parent, xs[3 * k], xs[3 * k + 1],
                     xs[3 * k + 2], vs[3 * k], vs[3 * k + 1], vs[3 * k + 2]);
    // A half outside a non-periodic box would be dropped by lammps_create_atoms, and the run
    // stopped with a count of halves only: the grain, where it is and how fast, and the box,
    // before anything is created.
    for (int k = 0; k < n; k++) {
      bool outside = false;
      for (int d = 0; d < 3; d++)
        if (!domain->periodicity[d] &&
            (xs[3 * k + d] < domain->boxlo[d] || xs[3 * k + d] >= domain->boxhi[d]))
          outside = true;
      if (outside)
        error->all(FLERR,
                   "{}: at step {} grain {} splits into a half at ({:.4g}, {:.4g}, {:.4g}) m, "
                   "outside the simulation box ({:.4g} to {:.4g}, {:.4g} to {:.4g}, {:.4g} to "
                   "{:.4g} m), moving at ({:.4g}, {:.4g}, {:.4g}) m/s: the grain had left the box "
                   "already, faster than its contacts could hold it; a velocity beyond any "
                   "contact's (the data file's Velocities) or a time step too long for the "
                   "contacts (timestep {:.4g} s; fix fractum/dt 0 checks it at every step, with "
                   "EVERY > 0 only at its adaptations) does that",
                   STYLE, update->ntimestep, all[k].parent, xs[3 * k], xs[3 * k + 1],
                   xs[3 * k + 2], domain->boxlo[0], domain->boxhi[0], domain->boxlo[1],
                   domain->boxhi[1], domain->boxlo[2], domain->boxhi[2], vs[3 * k], vs[3 * k + 1],
                   vs[3 * k + 2], update->dt);
    }
    // Drop the ghosts first, as Comm::exchange (next in this step) would, and as fix deposit
    // and fix pour do before they insert atoms: a created atom goes to slot nlocal, which a
    // ghost still occupies here, and lammps_create_atoms then maps nlocal + nghost slots, as
    // many past the ghosts as it created, whose stale or never-written tags it reads and
    // writes the atom map at (the 2-rank crush_grain crash: the half lands on a rank that holds
    // ghosts of its parent). Nothing reads ghosts between here and the exchange's borders.
    if (atom->map_style != Atom::MAP_NONE) atom->map_clear();
    atom->nghost = 0;
    // Counted by the ranks' own atoms: atom->natoms still counts atoms lost since the last
    // thermo output (a grain thrown out of the box), and lammps_create_atoms recounts without
    // them, which read as halves not created (a Velocities line of 1e20 m/s stopped the run at
    // a split as "a half lies outside the simulation box"), and the recount would hide the loss
    // from thermo's check: natoms is put back to the count with the lost atoms, so that thermo
    // reports them as thermo_modify lost says.
    const bigint before = atom->nlocal;
    const bigint natoms_before = atom->natoms;
    // Its return value is no verdict: it is the recounted atoms less atom->natoms, negative
    // when atoms were lost since the last thermo output (a grain thrown out of the box by a
    // Velocities line of 1e20 m/s: "could not create" was reported, pointing at a message
    // there was none of). A failure it caught is kept as the library's last error.
    lammps_create_atoms(lmp, n, ids.data(), type_all.data(), xs.data(), vs.data(), nullptr, 0);
    if (lammps_has_error(lmp)) {
      char why[1024] = "";
      lammps_get_last_error_message(lmp, why, sizeof why);
      error->all(FLERR, "{}: LAMMPS could not create the {} halves of split grains at step {}: "
                 "{}", STYLE, n, update->ntimestep, utils::trim(why));
    }
    bigint created_here = atom->nlocal - before, created = 0;
    MPI_Allreduce(&created_here, &created, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    atom->natoms = natoms_before + created;
    if (created != n)
      error->all(FLERR, "{}: at step {} {} halves of split grains were to be created and {} "
                 "were: LAMMPS dropped the others (a half at the box's edge, or a box "
                 "shrink-wrapped about its grains)",
                 STYLE, update->ntimestep, n, created);
    arrays();
    for (int k = 0; k < n; k++) {
      int i = atom->map(ids[k]);
      if (i < 0 || i >= atom->nlocal) continue;
      fractum_store_body(atom, shape, quat, inertia, i, all[k].minus);
      // A created atom's custom arrays hold whatever the slot held before (an atom that
      // left): the half starts with no springs and no face contacts.
      if (cohesion) cohesion->clear(i);
      if (walls)
        for (int s = 0; s < walls_cols; s++) walls[i][s] = 0.0;
      // Its travel starts at 0: any start would do for the skip (its pairs are new), but a
      // stale one would differ with the rank count, and a large one would eat the margins.
      if (travel) travel[i][0] = 0.0;
      grain[i][0] = draw_strength(ids[k], static_cast<int>(all[k].grain[2]), all[k].minus);
      grain[i][1] = all[k].grain[1];
      grain[i][2] = all[k].grain[2];
      grain[i][3] = 0.0;
      grain[i][4] = static_cast<double>(all[k].parent);
    }
  }
  split_evaluated = n > 0;
  for (int k = 0; k < n; k++) {
    // Every rank that computes a contact of the parent starts its held Hertz radius afresh.
    sums->reshape(all[k].parent);
    counts[0] += 1;
    counts[1] += all[k].first_split;
    counts[2] += all[k].criterion == 1;
    counts[3] += all[k].criterion == 2;
    if (cohesion) cohesion->bond_next(all[k].parent, ids[k], all[k].p);
  }
  // Every rank holds the maxima over all splits so far: a restart file (written by rank 0)
  // carries them.
  double worst[3];
  MPI_Allreduce(split_audit, worst, 3, MPI_DOUBLE, MPI_MAX, world);
  for (int k = 0; k < 3; k++) split_audit[k] = worst[k];
  decisions.clear();
}

double FixFractumFracture::compute_vector(int n)
{
  if (n < 4) return counts[n];
  if (n == 7) return failed_at;
  // Reduced over the ranks after every step with splits (pre_exchange).
  if (n >= 8) return split_audit[n - 8];
  double local = 0.0, global = 0.0;
  if (n == 4) {
    // Fix fractum/cohesion's count (its global scalar), kept here so that a script's columns
    // stay where they were; looked up now, as the fix may have been removed since the run.
    FixFractumCohesion *springs = find_cohesion();
    return springs ? springs->compute_scalar() : 0.0;
  } else if (n == 5) {
    local = sums->energy();
  } else {
    local = sums->dissipation();
  }
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_SUM, world);
  return global;
}

void FixFractumFracture::write_restart(FILE *fp)
{
  // Counters, the split audit's maxima and the decisions waiting for the next step (every rank
  // holds all of them).
  if (comm->me != 0) return;
  std::vector<double> buf;
  buf.push_back(7.0);
  for (double c : counts) buf.push_back(c);
  buf.push_back(failed_at);
  for (double a : split_audit) buf.push_back(a);
  buf.push_back(static_cast<double>(decisions.size()));
  buf.push_back(static_cast<double>(sizeof(Decision)));
  const size_t doubles = (sizeof(Decision) + sizeof(double) - 1) / sizeof(double);
  size_t at = buf.size();
  buf.resize(at + doubles * decisions.size());
  if (!decisions.empty())
    std::memcpy(&buf[at], decisions.data(), sizeof(Decision) * decisions.size());
  int size = static_cast<int>(buf.size() * sizeof(double));
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(buf.data(), sizeof(double), buf.size(), fp);
}

void FixFractumFracture::restart(char *raw)
{
  auto *buf = reinterpret_cast<double *>(raw);
  if (static_cast<int>(buf[0]) != 7)
    error->all(FLERR, "{}: the restart file's fracture state is not this plugin's", STYLE);
  for (int k = 0; k < 4; k++) counts[k] = buf[1 + k];
  failed_at = buf[5];
  for (int k = 0; k < 3; k++) split_audit[k] = buf[6 + k];
  size_t n = static_cast<size_t>(buf[9]);
  if (static_cast<size_t>(buf[10]) != sizeof(Decision))
    error->all(FLERR, "{}: the restart file's pending splits come from another build", STYLE);
  decisions.resize(n);
  if (n) std::memcpy(decisions.data(), &buf[11], sizeof(Decision) * n);
  if (n) next_reneighbor = update->ntimestep + 1;
}
