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
  const char *usage = "FACE POS [FACE POS ...] [vel FACE SPEED|v_name ...] [friction MU] with "
                      "FACE one of xlo xhi ylo yhi zlo zhi";
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
    } else {
      error->all(FLERR, "{}: unknown argument {}; allowed: {}", STYLE, key, usage);
    }
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
  size_vector = 3 * FACES;
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
  if ((law.friction || shapes))
    fractum_array(lmp, STYLE, "fr_walls", 6 * WALL_SLOT,
                  "declare `fix ID all property/atom d2_fr_walls 42` (the faces' contact "
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
  double **x = atom->x, *radius = atom->radius;
  if (near_stale()) near_atoms(walls);
  for (const int i : near) {
    bool placed = false;
    for (int w = 0; w < FACES; w++) {
      if (!active[w]) continue;
      // hist (3), unused (3), held radius: the pair memory layout, kept as the pair keeps its.
      FractumPairMemory *stored =
          walls ? reinterpret_cast<FractumPairMemory *>(&walls[i][WALL_SLOT * w]) : nullptr;
      // An atom whose bounding sphere is clear of the face by more than round-off, with
      // nothing remembered of it: the kernel would find no contact and change nothing (its
      // own test is this one without the margin).
      const double clear = (x[i][0] - point[w][0]) * normal[w][0] +
          (x[i][1] - point[w][1]) * normal[w][1] + (x[i][2] - point[w][2]) * normal[w][2];
      if (clear >= radius[i] * (1.0 + 1e-9) &&
          (!stored ||
           (stored->hist[0] == 0.0 && stored->hist[1] == 0.0 && stored->hist[2] == 0.0 &&
            stored->radius == 0.0)))
        continue;
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
  }
  reduced_at = -1;
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
  double **x = atom->x, *radius = atom->radius;
  const double reach = 2.0 * neighbor->skin;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    for (int w = 0; w < FACES; w++) {
      if (!active[w]) continue;
      const double clear = (x[i][0] - point[w][0]) * normal[w][0] +
          (x[i][1] - point[w][1]) * normal[w][1] + (x[i][2] - point[w][2]) * normal[w][2];
      const auto *stored =
          walls ? reinterpret_cast<const FractumPairMemory *>(&walls[i][WALL_SLOT * w]) : nullptr;
      const bool remembers = stored &&
          (stored->hist[0] != 0.0 || stored->hist[1] != 0.0 || stored->hist[2] != 0.0 ||
           stored->radius != 0.0);
      if (clear < radius[i] + reach || remembers) {
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
    MPI_Allreduce(local, global, 2 * FACES, MPI_DOUBLE, MPI_SUM, world);
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
