/* Per-atom data of Fractum grains on top of atom_style sphere, and the one place that turns a
   LAMMPS atom into the FractumBody the kernels of libfractum take.

   The arrays are `fix property/atom` arrays that the input script declares (fix property/atom
   migrates them with their atoms, sends them to ghosts when declared `ghost yes`, and writes
   them to restart files). Each has at most 7 columns: read_data reads a section's lines into
   256-character buffers, which 7 numbers at full precision fit.

     fix frshape all property/atom d2_fr_shape 7 ghost yes      [sphere flag, a+ a- b+ b- c+ c-]
     fix frorient all property/atom d2_fr_orient 7 ghost yes    [body-to-world quaternion w x y z,
                                                                 octant origin in the body frame]
     fix frinertia all property/atom d2_fr_inertia 7 ghost yes  [principal moments (kg m^2),
                                                                 shape-to-body quaternion w x y z]
     fix frgrain all property/atom d2_fr_grain 5 ghost yes      [Weibull factor, sample grain tag,
                                                                 splits so far, intact springs,
                                                                 tag split from (0: sample grain)]
     fix frtravel all property/atom d2_fr_travel 1 ghost yes    [travel (m), optional: summed by
                                                                 fix fractum/nve/polyell, read
                                                                 by the pair's skip]
     fix frstate all property/atom d2_fr_springs N d2_fr_walls 42 d2_fr_last 7
       (fracture, platens, integrator)
       fr_springs 21 doubles per spring slot (see fix_fractum_fracture.h)
       fr_walls   7 doubles per box face: tangential displacement (3), unused (3), held Hertz
                  radius
       fr_last    the force and torque of the last step (flag 1, force, torque): a later run
                  (after `run` or a restart) starts from them, as the uninterrupted run would
*/
#ifndef FRACTUM_ATOMS_H
#define FRACTUM_ATOMS_H

#include "atom.h"
#include "error.h"
#include "pointers.h"

#include <mpi.h>

#include <string>
#include <vector>

extern "C" {
#include "fractum.h"
}

namespace LAMMPS_NS {

/* A per-atom double array of fix property/atom by name (without the d2_ prefix); stops with one
   sentence naming the style and the missing array when it is absent or too narrow. */
double **fractum_array(LAMMPS *lmp, const char *style, const char *name, int min_cols,
                       const char *hint);
/* The grain arrays the fracture styles read (d2_fr_shape, _orient, _inertia, _grain), each as
   fractum_array gives it: one sentence naming `style` and the first one missing. */
void fractum_grain_arrays(LAMMPS *lmp, const char *style, double **&shape, double **&quat,
                          double **&inertia, double **&grain);
/* The same, nullptr when absent. */
double **fractum_array_if(LAMMPS *lmp, const char *name, int *cols = nullptr);

enum { SHAPE_COLS = 7, QUAT_COLS = 7, INERTIA_COLS = 7, GRAIN_COLS = 5, WALL_SLOT = 7 };

/* Fills b from atom i (owned or ghost). Without the shape arrays (shape == nullptr: a scene of
   spheres without fracture) the atom is a sphere with inertia 2/5 m r^2. */
inline void fractum_body(Atom *atom, double **shape, double **quat, double **inertia, int i,
                         FractumBody &b)
{
  // Built in a local and copied once: as far as the compiler knows b's stores could alias
  // LAMMPS's arrays, and it would reload what it reads after each (this runs for every atom
  // at every evaluation of the pair, the fracture check and the springs).
  const double *x = atom->x[i], *v = atom->v[i], *omega = atom->omega[i];
  const double mass = atom->rmass[i], radius = atom->radius[i];
  FractumBody out;
  for (int k = 0; k < 3; k++) {
    out.pos[k] = x[k];
    out.vel[k] = v[k];
    out.omega[k] = omega[k];
  }
  out.mass = mass;
  out.radius = radius;
  if (!shape) {
    const double moment = 0.4 * mass * radius * radius;
    for (int k = 0; k < 3; k++) {
      out.inertia[k] = moment;
      out.origin[k] = 0.0;
    }
    for (int k = 0; k < 4; k++) out.quat[k] = out.to_body[k] = k == 0 ? 1.0 : 0.0;
    for (int k = 0; k < 6; k++) out.semi[k] = radius;
    out.sphere = 1;
  } else {
    const double *s = shape[i], *q = quat[i], *in = inertia[i];
    for (int k = 0; k < 3; k++) {
      out.inertia[k] = in[k];
      out.origin[k] = q[4 + k];
    }
    for (int k = 0; k < 4; k++) {
      out.quat[k] = q[k];
      out.to_body[k] = in[3 + k];
    }
    for (int k = 0; k < 6; k++) out.semi[k] = s[1 + k];
    out.sphere = s[0] != 0.0 ? 1 : 0;
  }
  b = out;
}

/* Writes b's shape, orientation, inertia, mass, radius, velocities and position into atom i. */
inline void fractum_store_body(Atom *atom, double **shape, double **quat, double **inertia, int i,
                               const FractumBody &b)
{
  for (int k = 0; k < 3; k++) {
    atom->x[i][k] = b.pos[k];
    atom->v[i][k] = b.vel[k];
    atom->omega[i][k] = b.omega[k];
    inertia[i][k] = b.inertia[k];
    quat[i][4 + k] = b.origin[k];
  }
  for (int k = 0; k < 4; k++) {
    quat[i][k] = b.quat[k];
    inertia[i][3 + k] = b.to_body[k];
  }
  for (int k = 0; k < 6; k++) shape[i][1 + k] = b.semi[k];
  shape[i][0] = b.sphere ? 1.0 : 0.0;
  atom->rmass[i] = b.mass;
  atom->radius[i] = b.radius;
}

/* Whether an evaluation may change the stored contact memory (held radius, normal, tangential
   displacement): at every step, and at the setup before the first step (Fractum's first
   evaluation sets the held radii and normals), but not at the setup of a later run (a second
   `run` or after `read_restart`), so that a continued run is the uninterrupted one. */
inline bool fractum_keep_memory(int setup, bigint step)
{
  return !setup || step == 0;
}

/* The memory a contact's kernel call works on: `stored` itself when `keep`, else `scratch`
   holding a copy of it (zeros without one), thrown away after the call. */
inline FractumPairMemory *fractum_memory(FractumPairMemory *stored, bool keep,
                                         FractumPairMemory &scratch)
{
  if (stored && keep) return stored;
  if (stored)
    scratch = *stored;
  else
    scratch = FractumPairMemory{};
  return &scratch;
}

/* The contact material of pair_coeff: Young's modulus (Pa), Poisson's ratio, the coefficient
   of restitution (-1: no damping) and friction (-1: none). */
struct FractumMaterial {
  double young = 0.0, poisson = 0.0, restitution = -1.0, friction = -1.0;
};

/* The contact law of `m` with the Coulomb coefficient `mu` (the walls may take their own), as
   libfractum's fractum_kernel_contact_law builds it; `style` names the caller in an error. */
FractumContactLaw fractum_contact_law(LAMMPS *lmp, const char *style, const FractumMaterial &m,
                                      double mu);

/* Every rank's `mine`, concatenated in rank order, on every rank (plain structs of one build:
   sent as bytes). */
template <class T>
inline std::vector<T> fractum_gather_all(const std::vector<T> &mine, MPI_Comm world, int nprocs)
{
  std::vector<int> bytes_of(nprocs), displs(nprocs);
  int bytes = static_cast<int>(mine.size() * sizeof(T));
  MPI_Allgather(&bytes, 1, MPI_INT, bytes_of.data(), 1, MPI_INT, world);
  int total = 0;
  for (int r = 0; r < nprocs; r++) {
    displs[r] = total;
    total += bytes_of[r];
  }
  std::vector<T> all(total / sizeof(T));
  MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), bytes_of.data(), displs.data(),
                 MPI_BYTE, world);
  return all;
}

/* One sentence for a failed kernel call (never expected: the arguments come from checked
   state). */
void fractum_kernel_failed(LAMMPS *lmp, const char *style, const char *kernel, int status);

}    // namespace LAMMPS_NS

#endif
