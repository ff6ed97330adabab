#include "fix_fractum_nve_polyell.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "update.h"


using namespace LAMMPS_NS;
using namespace FixConst;

static const char *STYLE = "fix fractum/nve/polyell";

FixFractumNvePolyell::FixFractumNvePolyell(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg)
{
  if (narg != 3)
    error->all(FLERR, "{} takes no arguments after the group (got {})", STYLE, arg[3]);
  time_integrate = 1;
  comm_forward = 5;
}

int FixFractumNvePolyell::setmask()
{
  return INITIAL_INTEGRATE | POST_INTEGRATE | FINAL_INTEGRATE;
}

void FixFractumNvePolyell::init()
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, "{} needs atom_style sphere (per-atom radius, rmass, omega and torque)",
               STYLE);
  arrays();
}

void FixFractumNvePolyell::arrays()
{
  travel = fractum_array_if(lmp, "fr_travel");
  last = fractum_array_if(lmp, "fr_last");
  if (last) last = fractum_array(lmp, STYLE, "fr_last", 7, "declare d2_fr_last 7");
  shape = fractum_array_if(lmp, "fr_shape");
  if (shape) {
    const char *hint = "declare them with the d2_fr_shape array in one fix property/atom";
    shape = fractum_array(lmp, STYLE, "fr_shape", SHAPE_COLS, hint);
    quat = fractum_array(lmp, STYLE, "fr_orient", QUAT_COLS, hint);
    inertia = fractum_array(lmp, STYLE, "fr_inertia", INERTIA_COLS, hint);
  } else {
    quat = inertia = nullptr;
  }
}

/* Advances every owned atom of the group by one bulk kernel over LAMMPS's arrays (a kick-drift
   or a kick: the bits of the per-atom kernels, without building a FractumBody per atom); a
   drift grows each moving atom's travel. */
void FixFractumNvePolyell::advance(Kernel step, const char *name)
{
  arrays();
  FractumAtomRows rows;
  rows.n = atom->nlocal;
  rows.groupbit = groupbit;
  rows.mask = atom->mask;
  rows.x = atom->x;
  rows.v = atom->v;
  rows.omega = atom->omega;
  rows.force = atom->f;
  rows.torque = atom->torque;
  rows.mass = atom->rmass;
  rows.radius = atom->radius;
  rows.quat = quat;
  rows.inertia = inertia;
  rows.travel = travel;
  int status = step(&rows, update->dt);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, name, status);
}

void FixFractumNvePolyell::setup(int)
{
  resume = true;
}

void FixFractumNvePolyell::initial_integrate(int)
{
  // The first step of a run that continues another (d2_fr_last holds the last step's forces)
  // kicks with those: the forces evaluated at the run's setup miss nothing, but are not the
  // same bits (contact searches start from other guesses, springs are not advanced).
  arrays();
  if (resume && last)
    for (int i = 0; i < atom->nlocal; i++)
      if (last[i][0] != 0.0)
        for (int k = 0; k < 3; k++) {
          atom->f[i][k] = last[i][1 + k];
          atom->torque[i][k] = last[i][4 + k];
        }
  resume = false;
  advance(fractum_kernel_kick_drift_atoms, "kick_drift_atoms");
}

void FixFractumNvePolyell::post_integrate()
{
  if (quat) comm->forward_comm(this);
}

void FixFractumNvePolyell::final_integrate()
{
  advance(fractum_kernel_kick_atoms, "kick_atoms");
  if (last)
    for (int i = 0; i < atom->nlocal; i++) {
      last[i][0] = 1.0;
      for (int k = 0; k < 3; k++) {
        last[i][1 + k] = atom->f[i][k];
        last[i][4 + k] = atom->torque[i][k];
      }
    }
}

int FixFractumNvePolyell::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  int m = 0;
  for (int k = 0; k < n; k++) {
    for (int d = 0; d < 4; d++) buf[m++] = quat[list[k]][d];
    buf[m++] = travel ? travel[list[k]][0] : 0.0;
  }
  return m;
}

void FixFractumNvePolyell::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    for (int d = 0; d < 4; d++) quat[i][d] = buf[m++];
    if (travel) travel[i][0] = buf[m];
    m++;
  }
}
