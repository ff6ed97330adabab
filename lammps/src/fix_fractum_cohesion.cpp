#include "fix_fractum_cohesion.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "pair.h"
#include "utils.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

static const char *STYLE = "fix fractum/cohesion";
static const char *USAGE = "KIC N (the toughness in Pa m^0.5, the springs per break plane)";

static void cross(const double *a, const double *b, double *c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/* v turned by the unit quaternion q (w x y z). */
static void rotate(const double *q, const double *v, double *out)
{
  double u[3] = {q[1], q[2], q[3]}, t[3], ut[3];
  cross(u, v, t);
  for (int d = 0; d < 3; d++) t[d] *= 2.0;
  cross(u, t, ut);
  for (int d = 0; d < 3; d++) out[d] = v[d] + q[0] * t[d] + ut[d];
}

FixFractumCohesion::FixFractumCohesion(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg != 5) error->all(FLERR, "{} takes two arguments after the group: {}", STYLE, USAGE);
  kic = utils::numeric(FLERR, arg[3], false, lmp);
  if (!(kic > 0)) error->all(FLERR, "{}: KIC = {} must be > 0 (Pa m^0.5)", STYLE, kic);
  double n = utils::numeric(FLERR, arg[4], false, lmp);
  double lo = 0.0, hi = 0.0;
  fractum_kernel_fracture_range("springs", &lo, &hi);
  if (!(n >= lo && n <= hi && n == std::floor(n)))
    error->all(FLERR, "{}: springs = {} must be an integer in {}..{}", STYLE, n, lo, hi);
  springs = static_cast<int>(n);
  scalar_flag = 1;
  global_freq = 1;
  extscalar = 0;
}

int FixFractumCohesion::setmask()
{
  return POST_FORCE;
}

void FixFractumCohesion::arrays()
{
  fractum_grain_arrays(lmp, STYLE, shape, quat, inertia, grain);
  slots = fractum_array(lmp, STYLE, "fr_springs", SPRING_SLOT * springs,
                        "declare `fix ID all property/atom d2_fr_springs 21*N` "
                        "(N = the springs per break plane)");
}

double FixFractumCohesion::cohesive_energy(const FractumMaterial &m) const
{
  double gc = 0.0;
  int status = fractum_kernel_cohesive_energy(kic, m.young, m.poisson, &gc);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "cohesive_energy", status);
  return gc;
}

void FixFractumCohesion::init()
{
  bool fracture = false;
  int mine = 0;
  for (auto &f : modify->get_fix_list()) {
    fracture |= utils::strmatch(f->style, "^fractum/fracture$");
    mine += utils::strmatch(f->style, "^fractum/cohesion$") ? 1 : 0;
  }
  // Two would each apply every spring.
  if (mine > 1)
    error->all(FLERR, "{}: a second fix fractum/cohesion (ID {}) would apply every spring twice: "
               "keep one", STYLE, id);
  if (!fracture)
    error->all(FLERR, "{} needs fix fractum/fracture (the splits whose halves it bonds), "
               "defined before it", STYLE);
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "{} needs an atom map (`atom_modify map array`)", STYLE);
  arrays();    // stops with the first missing array named
}

void FixFractumCohesion::setup(int)
{
  arrays();
  // The forces of the run's first step include the springs' (not advanced here).
  spring_forces(false);
}

void FixFractumCohesion::clear(int i)
{
  arrays();
  for (int s = 0; s < springs * SPRING_SLOT; s++) slots[i][s] = 0.0;
  grain[i][3] = 0.0;
}

/* Whether slot s of owned atom a (its spring's end A) and slot s of owned atom b hold the two
   copies of one intact spring. Both ends of a spring store it at the same slot: the halves of
   a split are bonded at once, into slots cleared at the split (a grain with intact springs
   never breaks, so an atom holds springs to one partner only). */
static bool same_spring(const double *at_a, const double *at_b, tagint tag_a, tagint tag_b)
{
  return at_a[0] == static_cast<double>(tag_b) && at_a[1] > 0.0 && at_a[20] == 0.0 &&
      at_b[0] == static_cast<double>(tag_a) && at_b[1] < 0.0 && at_b[20] == 0.0;
}

/* The cohesive springs of the owned atoms. Both ends hold a copy, advanced identically; a
   spring whose ends are both owned here (the partner its own closest image) is evaluated once,
   by its end A, which applies it to both atoms and writes both copies: the bits of evaluating
   it from each end. A spring to a ghost is evaluated by each end's rank for its own atom.
   (`advance` false: their forces now, the springs left as they are.) */
void FixFractumCohesion::spring_forces(bool advance)
{
  double **f = atom->f, **torque = atom->torque;
  tagint *tag = atom->tag;
  const int nlocal = atom->nlocal;
  FractumBody bi, bj;
  for (int i = 0; i < nlocal; i++) {
    if (grain[i][3] == 0.0) continue;
    for (int s = 0; s < springs; s++) {
      double *slot = &slots[i][SPRING_SLOT * s];
      if (slot[0] == 0.0 || slot[20] != 0.0) continue;
      tagint partner = static_cast<tagint>(slot[0]);
      int j = atom->map(partner);
      if (j < 0)
        error->one(FLERR,
                   "{}: atom {} holds a cohesive spring to atom {}, which is neither owned nor a "
                   "ghost here: raise the communication cutoff (comm_modify cutoff)",
                   STYLE, tag[i], partner);
      const bool is_a = slot[1] > 0.0;
      // A spring evaluated once here: end A's closest image of B is B itself, owned here.
      double *other = nullptr;
      if (is_a) {
        j = domain->closest_image(i, j);
        if (j < nlocal && same_spring(slot, &slots[j][SPRING_SLOT * s], tag[i], partner))
          other = &slots[j][SPRING_SLOT * s];
      } else if (j < nlocal) {
        // End B: end A (owned here) evaluates it when its closest image of this atom is this
        // atom, the test end A makes.
        const int seen = domain->closest_image(j, i);
        if (seen < nlocal && same_spring(&slots[j][SPRING_SLOT * s], slot, partner, tag[i]))
          continue;
        j = domain->closest_image(i, j);
      } else {
        j = domain->closest_image(i, j);
      }
      fractum_body(atom, shape, quat, inertia, i, bi);
      fractum_body(atom, shape, quat, inertia, j, bj);
      FractumSpring sp;
      std::memcpy(sp.on_a, &slot[2], 3 * sizeof(double));
      std::memcpy(sp.on_b, &slot[5], 3 * sizeof(double));
      std::memcpy(sp.direction, &slot[8], 3 * sizeof(double));
      sp.f0 = slot[11];
      sp.k = slot[12];
      sp.opening = slot[13];
      std::memcpy(sp.last_gap, &slot[14], 3 * sizeof(double));
      std::memcpy(sp.last_force, &slot[17], 3 * sizeof(double));
      sp.broken = 0;
      double fa[3], ta[3], tb[3], work = 0.0;
      int broke = 0;
      int status = fractum_kernel_spring(&sp, is_a ? &bi : &bj, is_a ? &bj : &bi, fa, ta, tb,
                                         &work, &broke);
      if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "spring", status);
      if (!advance) {
        if (broke) continue;
      } else {
        for (double *copy : {slot, other}) {
          if (!copy) continue;
          copy[13] = sp.opening;
          std::memcpy(&copy[14], sp.last_gap, 3 * sizeof(double));
          std::memcpy(&copy[17], sp.last_force, 3 * sizeof(double));
        }
      }
      if (broke) {
        slot[20] = 1.0;
        grain[i][3] -= 1.0;
        if (other) {
          other[20] = 1.0;
          grain[j][3] -= 1.0;
        }
        continue;
      }
      for (int k = 0; k < 3; k++) {
        f[i][k] += is_a ? fa[k] : -fa[k];
        torque[i][k] += is_a ? ta[k] : tb[k];
      }
      if (other)
        for (int k = 0; k < 3; k++) {
          f[j][k] -= fa[k];
          torque[j][k] += tb[k];
        }
    }
  }
}

void FixFractumCohesion::post_force(int)
{
  arrays();
  spring_forces(true);
  if (!pending.empty()) bond();
}

/* The springs of this step's splits, from the halves' forces at their new shapes. */
void FixFractumCohesion::bond()
{
  // Each rank sends the body, force and torque of the halves it owns; every rank then sees
  // both halves of every split.
  struct Half {
    FractumBody body;
    double force[3], torque[3];
    tagint tag;
  };
  std::vector<Half> mine;
  for (const Pending &p : pending)
    for (tagint t : {p.a, p.b}) {
      int i = atom->map(t);
      if (i < 0 || i >= atom->nlocal) continue;
      Half h;
      std::memset(&h, 0, sizeof h);
      fractum_body(atom, shape, quat, inertia, i, h.body);
      for (int k = 0; k < 3; k++) {
        h.force[k] = atom->f[i][k];
        h.torque[k] = atom->torque[i][k];
      }
      h.tag = t;
      mine.push_back(h);
    }
  const std::vector<Half> all = fractum_gather_all(mine, world, comm->nprocs);
  auto find = [&](tagint t) -> const Half * {
    for (const Half &h : all)
      if (h.tag == t) return &h;
    return nullptr;
  };
  double **f = atom->f, **torque = atom->torque;
  for (const Pending &p : pending) {
    const Half *ha = find(p.a), *hb = find(p.b);
    if (!ha || !hb)
      error->all(FLERR, "{}: the halves {} and {} of a split were not found after the split",
                 STYLE, p.a, p.b);
    int ia = atom->map(p.a), ib = atom->map(p.b);
    const bool own_a = ia >= 0 && ia < atom->nlocal, own_b = ib >= 0 && ib < atom->nlocal;
    if (!own_a && !own_b) continue;
    FractumSpring made[16];
    int count = 0;
    int status = fractum_kernel_bond(&law, &ha->body, &hb->body, ha->force, ha->torque,
                                     hb->force, hb->torque, &p.p, made, &count);
    if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "bond", status);
    // Each spring's initial force at once, as Fractum applies it: on A at the spring's point
    // (lever from A's centre), the opposite on B (lever from B's centre).
    double fa_sum[3] = {0, 0, 0}, ta_sum[3] = {0, 0, 0}, tb_sum[3] = {0, 0, 0};
    for (int k = 0; k < count; k++) {
      const double *fk = made[k].last_force;
      double lever[3], world_b[3];
      if (count == p.p.count) {
        for (int d = 0; d < 3; d++) lever[d] = p.p.points[k][d] - ha->body.pos[d];
      } else {
        rotate(ha->body.quat, made[k].on_a, lever);
      }
      for (int d = 0; d < 3; d++) world_b[d] = lever[d] + ha->body.pos[d] - hb->body.pos[d];
      double tak[3], tbk[3];
      cross(lever, fk, tak);
      cross(world_b, fk, tbk);
      for (int d = 0; d < 3; d++) {
        fa_sum[d] += fk[d];
        ta_sum[d] += tak[d];
        tb_sum[d] -= tbk[d];
      }
    }
    auto store = [&](int i, tagint partner, double role) {
      int s = 0;
      for (int k = 0; k < count; k++) {
        while (s < springs && slots[i][SPRING_SLOT * s] != 0.0 &&
               slots[i][SPRING_SLOT * s + 20] == 0.0)
          s++;
        if (s >= springs)
          error->one(FLERR, "{}: atom {} has no free spring slot", STYLE, atom->tag[i]);
        double *slot = &slots[i][SPRING_SLOT * s];
        const FractumSpring &sp = made[k];
        slot[0] = static_cast<double>(partner);
        slot[1] = role;
        std::memcpy(&slot[2], sp.on_a, 3 * sizeof(double));
        std::memcpy(&slot[5], sp.on_b, 3 * sizeof(double));
        std::memcpy(&slot[8], sp.direction, 3 * sizeof(double));
        slot[11] = sp.f0;
        slot[12] = sp.k;
        slot[13] = sp.opening;
        std::memcpy(&slot[14], sp.last_gap, 3 * sizeof(double));
        std::memcpy(&slot[17], sp.last_force, 3 * sizeof(double));
        slot[20] = 0.0;
        s++;
      }
      grain[i][3] += count;
    };
    if (own_a) {
      store(ia, p.b, 1.0);
      for (int k = 0; k < 3; k++) {
        f[ia][k] += fa_sum[k];
        torque[ia][k] += ta_sum[k];
      }
    }
    if (own_b) {
      store(ib, p.a, -1.0);
      for (int k = 0; k < 3; k++) {
        f[ib][k] -= fa_sum[k];
        torque[ib][k] += tb_sum[k];
      }
    }
  }
  pending.clear();
}

double FixFractumCohesion::compute_scalar()
{
  arrays();
  // Each spring counted once, at its end A.
  double local = 0.0, global = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    for (int s = 0; s < springs; s++) {
      const double *slot = &slots[i][SPRING_SLOT * s];
      if (slot[0] != 0.0 && slot[20] == 0.0 && slot[1] > 0.0) local += 1.0;
    }
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_SUM, world);
  return global;
}
