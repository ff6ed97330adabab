#include "fix_fractum_platens.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "input.h"
#include "neighbor.h"
#include "fractum_sums.h"
#include "pair.h"
#include "update.h"
#include "utils.h"
#include "variable.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

static const char *STYLE = "fix fractum/platens";
static const char *FACE_NAMES[6] = {"xlo", "xhi", "ylo", "yhi", "zlo", "zhi"};

static int face_index(const char *name)
{
  for (int k = 0; k < 6; k++)
    if (std::strcmp(name, FACE_NAMES[k]) == 0) return k;
  return -1;
}

FixFractumPlatens::FixFractumPlatens(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const char *usage = "FACE POS [FACE POS ...] [vel FACE SPEED|v_name ...] [friction MU] "
                      "[sleeve CX CY R [sleeve_friction MU]] with FACE one of xlo xhi ylo yhi zlo zhi";
  int iarg = 3;
  while (iarg < narg) {
    std::string key = arg[iarg];
    int face = face_index(arg[iarg]);
    if (face >= 0) {
      if (iarg + 1 >= narg) error->all(FLERR, "{}: face {} needs a position (m)", STYLE, key);
      double pos = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      active[face] = true;
      int axis = face / 2;
      point[face][axis] = pos;
      normal[face][axis] = face % 2 == 0 ? 1.0 : -1.0;
      iarg += 2;
    } else if (key == "vel") {
      if (iarg + 2 >= narg) error->all(FLERR, "{}: vel needs a face and a speed: {}", STYLE, usage);
      int f = face_index(arg[iarg + 1]);
      if (f < 0)
        error->all(FLERR, "{}: vel {}: the face must be one of xlo xhi ylo yhi zlo zhi", STYLE,
                   arg[iarg + 1]);
      if (std::strncmp(arg[iarg + 2], "v_", 2) == 0)
        speed_var[f] = arg[iarg + 2] + 2;
      else
        speed[f] = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      iarg += 3;
    } else if (key == "friction") {
      if (iarg + 1 >= narg) error->all(FLERR, "{}: friction needs a value", STYLE);
      wall_friction = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(wall_friction >= 0.0))
        error->all(FLERR, "{}: friction = {} must be >= 0", STYLE, wall_friction);
      iarg += 2;
    } else if (key == "sleeve") {
      if (iarg + 3 >= narg)
        error->all(FLERR, "{}: sleeve needs its axis's x and y and its radius (m): {}", STYLE, usage);
      sleeve = true;
      sleeve_centre[0] = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      sleeve_centre[1] = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      sleeve_radius = utils::numeric(FLERR, arg[iarg + 3], false, lmp);
      if (!(sleeve_radius > 0.0) || !std::isfinite(sleeve_radius))
        error->all(FLERR, "{}: sleeve radius = {} must be > 0 (m)", STYLE, sleeve_radius);
      iarg += 4;
    } else if (key == "sleeve_friction") {
      if (iarg + 1 >= narg) error->all(FLERR, "{}: sleeve_friction needs a value", STYLE);
      sleeve_friction = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(sleeve_friction >= 0.0))
        error->all(FLERR, "{}: sleeve_friction = {} must be >= 0", STYLE, sleeve_friction);
      iarg += 2;
    } else {
      error->all(FLERR, "{}: unknown argument {}; allowed: {}", STYLE, key, usage);
    }
  }
  if (sleeve_friction >= 0.0 && !sleeve)
    error->all(FLERR, "{}: sleeve_friction applies with a sleeve only (sleeve CX CY R)", STYLE);
  if (sleeve) {
    for (int k = 0; k < 4; k++)
      if (active[k])
        error->all(FLERR, "{}: the sleeve stands in place of the side faces: leave out {}", STYLE,
                   FACE_NAMES[k]);
    if (!active[4] || !active[5])
      error->all(FLERR, "{}: the sleeve needs the faces zlo and zhi, which close it", STYLE);
  }
  bool any = false;
  for (int k = 0; k < FACES; k++) any |= active[k];
  if (!any) error->all(FLERR, "{} needs at least one face: {}", STYLE, usage);
  for (int axis = 0; axis < 3; axis++) {
    const int lo = 2 * axis, hi = lo + 1;
    if (active[lo] && active[hi] && !(point[lo][axis] < point[hi][axis]))
      error->all(FLERR, "{}: {} = {} m must lie below {} = {} m (the grains are between them)",
                 STYLE, FACE_NAMES[lo], point[lo][axis], FACE_NAMES[hi], point[hi][axis]);
  }
  for (int k = 0; k < FACES; k++)
    if (!active[k] && (speed[k] != 0.0 || !speed_var[k].empty()))
      error->all(FLERR, "{}: vel {} names a face that is not defined", STYLE, FACE_NAMES[k]);
  vector_flag = 1;
  size_vector = 3 * FACES + 3 + SLICES;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
}

int FixFractumPlatens::setmask()
{
  return INITIAL_INTEGRATE | POST_FORCE;
}

void FixFractumPlatens::init()
{
  // The pair's law (its material, the faces' own friction when given) and sums.
  sums = fractum_sums(lmp, STYLE);
  int dim = 0;
  Pair *pair = force->pair_match("fractum/granular", 1);
  const auto *material = static_cast<const FractumMaterial *>(pair->extract("fractum/material", dim));
  shapes = *static_cast<const int *>(pair->extract("fractum/shapes", dim));
  law = fractum_contact_law(lmp, STYLE, *material,
                            wall_friction >= 0 ? wall_friction
                                               : (material->friction >= 0 ? material->friction : 0.0));
  poisson = material->poisson;
  if (sleeve)
    sleeve_law = fractum_contact_law(lmp, STYLE, *material,
                                     sleeve_friction >= 0 ? sleeve_friction
                                     : wall_friction >= 0 ? wall_friction
                                     : (material->friction >= 0 ? material->friction : 0.0));
  if ((law.friction || shapes))
    fractum_array(lmp, STYLE, "fr_walls", (FACES + (sleeve ? 1 : 0)) * WALL_SLOT,
                  sleeve ? "declare `fix ID all property/atom d2_fr_walls 49` (the faces' and "
                           "the sleeve's contact histories) before read_data"
                         : "declare `fix ID all property/atom d2_fr_walls 42` (the faces' contact "
                           "histories) before read_data");
  for (int k = 0; k < FACES; k++)
    if (!speed_var[k].empty()) {
      int v = input->variable->find(speed_var[k].c_str());
      if (v < 0 || !input->variable->equalstyle(v))
        error->all(FLERR, "{}: vel {} v_{}: no equal-style variable of that name", STYLE,
                   FACE_NAMES[k], speed_var[k]);
    }
}

void FixFractumPlatens::speeds()
{
  for (int k = 0; k < FACES; k++) {
    if (!active[k]) continue;
    double s = speed[k];
    if (!speed_var[k].empty()) {
      int v = input->variable->find(speed_var[k].c_str());
      s = input->variable->compute_equal(v);
    }
    int axis = k / 2;
    velocity[k][0] = velocity[k][1] = velocity[k][2] = 0.0;
    velocity[k][axis] = s;
  }
}

void FixFractumPlatens::setup(int vflag)
{
  // The faces keep the speeds of the last step (zero before the first): as in Fractum, a
  // speed is set at the start of a step.
  post_force(vflag);
}

void FixFractumPlatens::initial_integrate(int)
{
  // As Fractum's walls: the speed is set at the start of the step and the face moves by v dt
  // before the forces are evaluated.
  speeds();
  for (int k = 0; k < FACES; k++)
    for (int d = 0; d < 3; d++) point[k][d] += velocity[k][d] * update->dt;
}

void FixFractumPlatens::post_force(int)
{
  std::memset(local, 0, sizeof local);
  double **walls = fractum_array_if(lmp, "fr_walls");
  double **shape = nullptr, **quat = nullptr, **inertia = nullptr, **grain = nullptr;
  if (shapes) {
    shape = fractum_array_if(lmp, "fr_shape");
    quat = fractum_array_if(lmp, "fr_orient");
    inertia = fractum_array_if(lmp, "fr_inertia");
    grain = fractum_array_if(lmp, "fr_grain");
  }
  const bool frequency_due = sums->shares_wanted();
  const int update_history = update->setupflag ? 0 : 1;
  const bool keep_memory = fractum_keep_memory(update->setupflag, update->ntimestep);
  FractumBody b;
  FractumPairMemory scratch;
  FractumContact out;
  double **f = atom->f, **torque = atom->torque;
  double **x = atom->x;
  if (near_stale()) near_atoms(walls);
  for (const int i : near) {
    bool placed = false;
    for (int w = 0; w < FACES; w++) {
      if (!active[w]) continue;
      if (!reaches(walls, i, w)) continue;
      // hist (3), unused (3), held radius: the pair memory layout, kept as the pair keeps its.
      FractumPairMemory *stored =
          walls ? reinterpret_cast<FractumPairMemory *>(&walls[i][WALL_SLOT * w]) : nullptr;
      if (!placed) {
        fractum_body(atom, shape, quat, inertia, i, b);
        placed = true;
      }
      FractumPairMemory *mem = fractum_memory(stored, keep_memory, scratch);
      int status = fractum_kernel_wall(&law, &b, normal[w], point[w], velocity[w], mem,
                                       update->dt, update_history, shapes, &out);
      if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "wall", status);
      if (!out.touching) continue;
      for (int k = 0; k < 3; k++) {
        f[i][k] += out.force[k];
        torque[i][k] += out.torque_a[k];
      }
      local[w] -= out.force[w / 2];
      local[FACES + w] += 1.0;
      sums->add_energy(out.energy, out.dissipated);
      if (frequency_due) sums->add_share(lmp, STYLE, law, i, out, b, nullptr);
      if (grain && grain[i][3] == 0.0)
        sums->add_load(lmp, STYLE, i, x[i], out.force, out.point, out.hertz_force, out.radius,
                       poisson, grain[i][0]);
    }
    // The sleeve after the faces, as Fractum adds its walls' contacts.
    if (sleeve && reaches(walls, i, FACES)) {
      if (!placed) fractum_body(atom, shape, quat, inertia, i, b);
      sleeve_contact(i, walls, b, frequency_due, keep_memory, update_history, grain);
    }
  }
  reduced_at = -1;
}

/* How far atom i's centre is from surface w (a face, or with w = FACES the sleeve), measured
   into the box (m). */
double FixFractumPlatens::clearance(int i, int w) const
{
  const double *x = atom->x[i];
  if (w == FACES) {
    const double dx = x[0] - sleeve_centre[0], dy = x[1] - sleeve_centre[1];
    return sleeve_radius - std::sqrt(dx * dx + dy * dy);
  }
  return (x[0] - point[w][0]) * normal[w][0] + (x[1] - point[w][1]) * normal[w][1] +
      (x[2] - point[w][2]) * normal[w][2];
}

/* Whether atom i's contact history with surface w (hist (3), unused (3), held radius: the pair
   memory layout) holds anything. */
static bool remembers(double **walls, int i, int w)
{
  if (!walls) return false;
  const auto *m = reinterpret_cast<const FractumPairMemory *>(&walls[i][WALL_SLOT * w]);
  return m->hist[0] != 0.0 || m->hist[1] != 0.0 || m->hist[2] != 0.0 || m->radius != 0.0;
}

/* Whether atom i's bounding sphere reaches surface w (by more than round-off) or its memory
   holds a contact: else the kernel would find no contact and change nothing (its own test is
   this one without the margin). */
bool FixFractumPlatens::reaches(double **walls, int i, int w) const
{
  return clearance(i, w) < atom->radius[i] * (1.0 + 1e-9) || remembers(walls, i, w);
}

/* Atom i's contact with the sleeve (b its body): its force, torque, energy, frequency share and
   grain load as a face's, and the sleeve's sums. */
void FixFractumPlatens::sleeve_contact(int i, double **walls, const FractumBody &b,
                                       bool frequency_due, bool keep_memory, int update_history,
                                       double **grain)
{
  double **x = atom->x;
  FractumPairMemory *stored =
      walls ? reinterpret_cast<FractumPairMemory *>(&walls[i][WALL_SLOT * FACES]) : nullptr;
  FractumPairMemory scratch;
  FractumContact out;
  FractumPairMemory *mem = fractum_memory(stored, keep_memory, scratch);
  int status = fractum_kernel_sleeve(&sleeve_law, &b, sleeve_centre, sleeve_radius, mem,
                                     update->dt, update_history, shapes, &out);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "sleeve", status);
  if (!out.touching) return;
  for (int k = 0; k < 3; k++) {
    atom->f[i][k] += out.force[k];
    atom->torque[i][k] += out.torque_a[k];
  }
  const double load =
      out.force[0] * out.normal[0] + out.force[1] * out.normal[1] + out.force[2] * out.normal[2];
  // The slices of the span between the two z faces (the bars' faces); a contact point beyond
  // either face counts in the end slice.
  const double z0 = point[4][2], height = point[5][2] - point[4][2];
  double slice = std::floor((out.point[2] - z0) / height * SLICES);
  int at = std::isnan(slice) ? 0 : static_cast<int>(std::min(std::max(slice, 0.0), SLICES - 1.0));
  local[2 * FACES] += load;
  local[2 * FACES + 1] -= out.force[2];
  local[2 * FACES + 2] += 1.0;
  local[2 * FACES + 3 + at] += load;
  sums->add_energy(out.energy, out.dissipated);
  if (frequency_due) sums->add_share(lmp, STYLE, sleeve_law, i, out, b, nullptr);
  if (grain && grain[i][3] == 0.0)
    sums->add_load(lmp, STYLE, i, x[i], out.force, out.point, out.hertz_force, out.radius, poisson,
                   grain[i][0]);
}

/* The atoms near the faces are listed again when LAMMPS rebuilt its neighbour lists in this
   step (atoms were exchanged, sorted, created or reshaped by splits), the owned count
   changed, or a face moved half a skin since; always when LAMMPS does not check at every
   step that no atom moved half a skin (the bound the list relies on). */
bool FixFractumPlatens::near_stale() const
{
  if (!(neighbor->dist_check && neighbor->every == 1 && neighbor->delay == 0)) return true;
  if (neighbor->ago == 0 || atom->nlocal != near_nlocal) return true;
  const double half_skin2 = 0.25 * neighbor->skin * neighbor->skin;
  for (int w = 0; w < FACES; w++) {
    if (!active[w]) continue;
    double d2 = 0.0;
    for (int d = 0; d < 3; d++) d2 += (point[w][d] - near_point[w][d]) * (point[w][d] - near_point[w][d]);
    if (d2 > half_skin2) return true;
  }
  return false;
}

/* The owned atoms of the group within their radius and two skins of an active face, or
   remembering a contact with one. Until the list is built again an atom moves at most a
   skin from where it was listed (half a skin either side of LAMMPS's last rebuild) and a
   face at most half a skin, so an atom left out stays half a skin clear of every face: the
   loop over the listed atoms calls the wall kernel for the same atoms, in the same order, as
   a loop over all atoms would. */
void FixFractumPlatens::near_atoms(double **walls)
{
  near.clear();
  const double reach = 2.0 * neighbor->skin;
  const int surfaces = FACES + (sleeve ? 1 : 0);
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    for (int w = 0; w < surfaces; w++) {
      if (w < FACES && !active[w]) continue;
      if (clearance(i, w) < atom->radius[i] + reach || remembers(walls, i, w)) {
        near.push_back(i);
        break;
      }
    }
  }
  for (int w = 0; w < FACES; w++)
    for (int d = 0; d < 3; d++) near_point[w][d] = point[w][d];
  near_nlocal = atom->nlocal;
}

double FixFractumPlatens::compute_vector(int n)
{
  if (reduced_at != update->ntimestep) {
    MPI_Allreduce(local, global, SUMS, MPI_DOUBLE, MPI_SUM, world);
    reduced_at = update->ntimestep;
  }
  if (n < FACES) return global[n];
  if (n < 2 * FACES) {
    int k = n - FACES;
    return point[k][k / 2];
  }
  return global[n - FACES];
}

void FixFractumPlatens::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  double buf[1 + 6 * FACES];
  buf[0] = 6 * FACES;
  for (int k = 0; k < FACES; k++)
    for (int d = 0; d < 3; d++) {
      buf[1 + 6 * k + d] = point[k][d];
      buf[1 + 6 * k + 3 + d] = velocity[k][d];
    }
  int size = sizeof buf;
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(buf, sizeof buf, 1, fp);
}

void FixFractumPlatens::restart(char *raw)
{
  auto *buf = reinterpret_cast<double *>(raw);
  if (static_cast<int>(buf[0]) != 6 * FACES)
    error->all(FLERR, "{}: the restart file's platen state is not this plugin's", STYLE);
  for (int k = 0; k < FACES; k++)
    for (int d = 0; d < 3; d++) {
      point[k][d] = buf[1 + 6 * k + d];
      velocity[k][d] = buf[1 + 6 * k + 3 + d];
    }
}
