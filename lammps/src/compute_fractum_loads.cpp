#include "compute_fractum_loads.h"

#include "atom.h"
#include "error.h"
#include "fractum_sums.h"
#include "memory.h"
#include "update.h"

using namespace LAMMPS_NS;

static const char *STYLE = "compute fractum/loads";

ComputeFractumLoads::ComputeFractumLoads(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg)
{
  if (narg != 3)
    error->all(FLERR, "{} takes no arguments (compute ID group fractum/loads)", STYLE);
  peratom_flag = 1;
  size_peratom_cols = COLUMNS;
}

ComputeFractumLoads::~ComputeFractumLoads()
{
  memory->destroy(loads);
}

void ComputeFractumLoads::init()
{
  sums = fractum_sums(lmp, STYLE);
}

void ComputeFractumLoads::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (!sums->loads_wanted())
    error->all(FLERR,
               "{} {} needs fix fractum/fracture: the pair sums the grain loads for its check",
               STYLE, id);
  if (atom->nmax > nmax) {
    memory->destroy(loads);
    nmax = atom->nmax;
    memory->create(loads, nmax, COLUMNS, "fractum/loads:loads");
    array_atom = loads;
  }
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  for (int i = 0; i < nlocal; i++) {
    double *row = loads[i];
    for (int k = 0; k < COLUMNS; k++) row[k] = 0.0;
    const FractumGrainLoad *g = sums->load(i);
    if (!g || !(mask[i] & groupbit)) continue;
    for (int k = 0; k < 9; k++) row[k] = g->moment[k];
    row[9] = static_cast<double>(g->count);
    for (int k = 0; k < 3; k++) {
      row[10 + k] = g->stress[k];
      for (int d = 0; d < 3; d++) row[13 + 3 * k + d] = g->point[k][d];
    }
  }
}

double ComputeFractumLoads::memory_usage()
{
  return static_cast<double>(nmax) * COLUMNS * sizeof(double);
}
