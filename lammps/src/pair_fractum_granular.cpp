#include "pair_fractum_granular.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix_neigh_history_layout.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

static const char *STYLE = "pair fractum/granular";
static const char *ARRAYS_HINT =
    "declare the fix property/atom arrays d2_fr_shape 7, d2_fr_orient 7, d2_fr_inertia 7 "
    "and d2_fr_grain 5 (ghost yes) before read_data (fractum export lammps --plugin writes them)";

PairFractumGranular::PairFractumGranular(LAMMPS *lmp) : Pair(lmp)
{
  single_enable = 0;
  no_virial_fdotr_compute = 1;
  finitecutflag = 1;
  one_coeff = 1;
  restartinfo = 0;
  beyond_contact = 0;
  // Histories are stored in the canonical order (lower tag first) and copied, not negated,
  // when FixNeighHistory hands a pair from one atom to the other.
  nondefault_history_transfer = 1;
  // A placeholder that keeps the history fix where the pair style was defined in the fix list.
  dummy = modify->add_fix("NEIGH_HISTORY_FRACTUM_DUMMY all DUMMY");
}

PairFractumGranular::~PairFractumGranular()
{
  if (modify->nfix) {
    if (history)
      modify->delete_fix("NEIGH_HISTORY_FRACTUM");
    else if (dummy)
      modify->delete_fix("NEIGH_HISTORY_FRACTUM_DUMMY");
  }
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
}

void PairFractumGranular::settings(int narg, char **arg)
{
  if (narg != 0)
    error->all(FLERR, "{} takes no arguments (the contact law goes in pair_coeff * *), got {}",
               STYLE, arg[0]);
}

void PairFractumGranular::coeff(int narg, char **arg)
{
  const char *usage = "pair_coeff * * young E poisson NU [restitution e] [friction MU]";
  if (narg < 2 || std::strcmp(arg[0], "*") != 0 || std::strcmp(arg[1], "*") != 0)
    error->all(FLERR, "{}: one material for all atom types: {}", STYLE, usage);
  double young = NAN, poisson = NAN, restitution = -1.0, friction = -1.0;
  for (int k = 2; k < narg; k += 2) {
    if (k + 1 >= narg) error->all(FLERR, "{}: keyword {} needs a value: {}", STYLE, arg[k], usage);
    double v = utils::numeric(FLERR, arg[k + 1], false, lmp);
    std::string key = arg[k];
    if (key == "young") {
      if (!(v > 0.0)) error->all(FLERR, "{}: young = {} must be > 0 (Pa)", STYLE, v);
      young = v;
    } else if (key == "poisson") {
      if (!(v > -1.0 && v < 0.5)) error->all(FLERR, "{}: poisson = {} must lie in (-1, 0.5)", STYLE, v);
      poisson = v;
    } else if (key == "restitution") {
      if (!(v > 0.0 && v <= 1.0)) error->all(FLERR, "{}: restitution = {} must lie in (0, 1]", STYLE, v);
      restitution = v;
    } else if (key == "friction") {
      if (!(v >= 0.0)) error->all(FLERR, "{}: friction = {} must be >= 0", STYLE, v);
      friction = v;
    } else {
      error->all(FLERR, "{}: unknown keyword {}; allowed: young, poisson, restitution, friction",
                 STYLE, key);
    }
  }
  if (std::isnan(young) || std::isnan(poisson))
    error->all(FLERR, "{}: young and poisson are required: {}", STYLE, usage);
  material = FractumMaterial{young, poisson, restitution, friction};
  law = fractum_contact_law(lmp, STYLE, material, friction >= 0 ? friction : 0.0);

  if (!allocated) {
    allocated = 1;
    int n = atom->ntypes;
    memory->create(setflag, n + 1, n + 1, "pair:setflag");
    memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  }
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) setflag[i][j] = 1;
}

void *PairFractumGranular::extract(const char *name, int &dim)
{
  dim = 0;
  if (std::strcmp(name, "fractum/sums") == 0) return &sums;
  if (std::strcmp(name, "fractum/material") == 0) return &material;
  if (std::strcmp(name, "fractum/shapes") == 0) return &shapes;
  return nullptr;
}

void PairFractumGranular::init_style()
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, "{} needs atom_style sphere (per-atom radius, rmass, omega and torque)",
               STYLE);
  if (force->newton_pair)
    error->all(FLERR, "{} needs newton_pair off (`newton off`): each rank computes the contacts "
               "of its own atoms", STYLE);
  if (!comm->ghost_velocity)
    error->all(FLERR, "{} needs `comm_modify vel yes`: the contact law reads the partners' "
               "velocities", STYLE);
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "{} needs an atom map (`atom_modify map array`)", STYLE);

  shape_arr = fractum_array_if(lmp, "fr_shape");
  shapes = shape_arr ? 1 : 0;
  if (shapes) {
    shape_arr = fractum_array(lmp, STYLE, "fr_shape", SHAPE_COLS, ARRAYS_HINT);
    quat_arr = fractum_array(lmp, STYLE, "fr_orient", QUAT_COLS, ARRAYS_HINT);
    inertia_arr = fractum_array(lmp, STYLE, "fr_inertia", INERTIA_COLS, ARRAYS_HINT);
    grain_arr = fractum_array(lmp, STYLE, "fr_grain", GRAIN_COLS, ARRAYS_HINT);
  }

  int use_history = law.friction || shapes;
  neighbor->add_request(this, use_history ? NeighConst::REQ_SIZE | NeighConst::REQ_HISTORY
                                          : NeighConst::REQ_SIZE);
  if (use_history && history == nullptr) {
    Fix *f = modify->replace_fix("NEIGH_HISTORY_FRACTUM_DUMMY",
                                 "NEIGH_HISTORY_FRACTUM all NEIGH_HISTORY " + std::to_string(HISTORY), 1);
    history = static_cast<FractumNeighHistoryView *>(f);
    history->pair = this;
    dummy = nullptr;
  }

  double local = 0.0;
  for (int i = 0; i < atom->nlocal; i++) local = std::max(local, atom->radius[i]);
  MPI_Allreduce(&local, &maxrad, 1, MPI_DOUBLE, MPI_MAX, world);
}

double PairFractumGranular::init_one(int, int)
{
  return 2.0 * maxrad;
}

void PairFractumGranular::transfer_history(double *source, double *target, int, int)
{
  for (int k = 0; k < HISTORY; k++) target[k] = source[k];
}

void PairFractumGranular::check_history()
{
  if (!history) return;
  int nall = atom->nlocal + atom->nghost;
  if (history->pair != this || history->dnum != HISTORY || history->nlocal_neigh != atom->nlocal ||
      history->nall_neigh != nall || history->newton_pair != force->newton_pair)
    error->one(FLERR,
               "{}: LAMMPS's neighbour-history fix does not have the layout this plugin was built "
               "for (dnum {} for {}, nlocal {} for {}): rebuild the plugin against this LAMMPS",
               STYLE, history->dnum, HISTORY, history->nlocal_neigh, atom->nlocal);
}

void PairFractumGranular::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  double **f = atom->f, **torque = atom->torque;
  tagint *tag = atom->tag;

  if (shapes) {
    shape_arr = fractum_array(lmp, STYLE, "fr_shape", SHAPE_COLS, ARRAYS_HINT);
    quat_arr = fractum_array(lmp, STYLE, "fr_orient", QUAT_COLS, ARRAYS_HINT);
    inertia_arr = fractum_array(lmp, STYLE, "fr_inertia", INERTIA_COLS, ARRAYS_HINT);
    grain_arr = fractum_array(lmp, STYLE, "fr_grain", GRAIN_COLS, ARRAYS_HINT);
  }
  bodies.resize(nall);
  for (int i = 0; i < nall; i++)
    fractum_body(atom, shape_arr, quat_arr, inertia_arr, i, bodies[i]);
  // Each body placed once per evaluation, as Fractum's own contact loop places them (a few
  // pairs per body would otherwise place it a few times).
  if (shapes) {
    places.resize(nall);
    for (int i = 0; i < nall; i++) {
      int status = fractum_kernel_placement(&bodies[i], &places[i]);
      if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "placement", status);
    }
  }
  if (history && neighbor->ago == 0) check_history();
  sums.begin(nlocal);
  const bool frequency_due = sums.shares_wanted();
  const std::vector<tagint> &reshaped = sums.reshaped_sorted();
  const int update_history = update->setupflag ? 0 : 1;
  const bool keep_memory = fractum_keep_memory(update->setupflag, update->ntimestep);

  // The partners' tags order each pair (the lower tag is body A), and with shapes the
  // bodies' travels (d2_fr_travel, summed by fix fractum/nve/polyell) let the kernel skip
  // the pairs found apart that cannot have closed since, as Fractum's own loop does.
  keys.resize(nall);
  for (int i = 0; i < nall; i++) keys[i] = tag[i];
  double **travel_arr = shapes ? fractum_array_if(lmp, "fr_travel") : nullptr;
  if (travel_arr) {
    travel.resize(nall);
    for (int i = 0; i < nall; i++) travel[i] = travel_arr[i][0];
  }
  reshaped_keys.assign(reshaped.begin(), reshaped.end());

  // Every row of the list in one call: the contacts (their records as LAMMPS's history fix
  // keeps them, where it keeps them), their energies and frequency shares, and each owned
  // atom's sides in the order of its partners' tags (the same bits on any rank count: the
  // lists' order depends on the decomposition, and a sum's rounding on its order).
  FractumNeighbours rows{};
  rows.inum = list->inum;
  rows.ilist = list->ilist;
  rows.numneigh = list->numneigh;
  rows.firstneigh = list->firstneigh;
  rows.index_mask = NEIGHMASK;
  rows.firsttouch = history ? history->firstflag : nullptr;
  rows.firstvalue = history ? history->firstvalue : nullptr;
  rows.stride = HISTORY;
  size_t candidates = 0;
  for (int ii = 0; ii < list->inum; ii++) candidates += list->numneigh[list->ilist[ii]];
  if (touching.size() < candidates) touching.resize(candidates);
  if (codes.size() < 2 * candidates) codes.resize(2 * candidates);
  size_t n_touching = 0, n_sides = 0;
  double energy[2] = {0.0, 0.0};
  int status = fractum_kernel_pair_list(
      &law, bodies.data(), shapes ? places.data() : nullptr, keys.data(),
      travel_arr ? travel.data() : nullptr, nall, nlocal, &rows, keep_memory ? 1 : 0,
      reshaped_keys.data(), reshaped_keys.size(), update->dt,
      update_history, shapes, frequency_due ? 1 : 0, touching.data(), candidates, &n_touching,
      codes.data(), &n_sides, energy);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "pair_list", status);
  sums.add_energy(energy[0], energy[1]);
  const bool loads = grain_arr && sums.loads_wanted();
  status = fractum_kernel_sum_contacts(
      touching.data(), n_touching, codes.data(), n_sides, nlocal, f, torque, atom->x,
      loads ? grain_arr : nullptr, material.poisson, sums.threshold(),
      sums.particle_strength() ? 1 : 0,
      frequency_due ? sums.shares_data() : nullptr, loads ? sums.loads_data() : nullptr);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "sum_contacts", status);
  sums.reshaped_done();
}

double PairFractumGranular::memory_usage()
{
  return (double) bodies.capacity() * sizeof(FractumBody) +
      (double) places.capacity() * sizeof(FractumPlacement) +
      sums.memory_usage() +
      (double) touching.capacity() * sizeof(FractumTouching) +
      (double) codes.capacity() * sizeof(int32_t) +
      (double) (keys.capacity() + reshaped_keys.capacity()) * sizeof(int64_t) +
      (double) travel.capacity() * sizeof(double);
}
