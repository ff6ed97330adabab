#include "fix_fractum_dt.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "fractum_sums.h"
#include "modify.h"
#include "output.h"
#include "pair.h"
#include "update.h"
#include "utils.h"

#include <cmath>

using namespace LAMMPS_NS;
using namespace FixConst;

static const char *STYLE = "fix fractum/dt";
static const char *USAGE = "EVERY [omega_dt X] (EVERY: steps between adaptations, 0: check only)";

FixFractumDt::FixFractumDt(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg < 4) error->all(FLERR, "{} needs EVERY: {}", STYLE, USAGE);
  double n = utils::numeric(FLERR, arg[3], false, lmp);
  // Bounded where a double still holds every integer: from 2^63 on the conversion to bigint
  // is undefined.
  if (!(n >= 0 && n <= 9007199254740992.0 && n == std::floor(n)))
    error->all(FLERR,
               "{}: EVERY = {} must be an integer >= 0 and <= 2^53 (steps; 0: check only)",
               STYLE, n);
  every = static_cast<bigint>(n);
  int iarg = 4;
  while (iarg < narg) {
    std::string key = arg[iarg];
    if (key == "omega_dt") {
      if (iarg + 1 >= narg) error->all(FLERR, "{}: omega_dt needs a value", STYLE);
      double x = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      // Below 0.001 the step is cut a thousandfold below what the contacts need: omega_dt
      // 1e-300 ended its run at the step cap at 1% of the loading. Fractum's own X is 3 x
      // time.safety.
      if (!(x >= 0.001 && x < 2.0))
        error->all(FLERR,
                   "{}: omega_dt = {} must lie in [0.001, 2) (above: velocity Verlet's limit; "
                   "below: a step far shorter than the contacts need)",
                   STYLE, x);
      omega_dt = x;
      iarg += 2;
    } else {
      error->all(FLERR, "{}: unknown argument {}; allowed: {}", STYLE, key, USAGE);
    }
  }
  nevery = 1;
  vector_flag = 1;
  size_vector = 2;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
}

int FixFractumDt::setmask()
{
  return END_OF_STEP;
}

void FixFractumDt::init()
{
  sums = fractum_sums(lmp, STYLE);
  // Two would each shorten the step on their own schedule; a second one was taken silently.
  for (auto &f : modify->get_fix_list())
    if (f != this && utils::strmatch(f->style, "^fractum/dt$"))
      error->all(FLERR,
                 "{} {}: a second fix fractum/dt besides {}; one fix adapts the step, so unfix "
                 "one of them",
                 STYLE, id, f->id);
  // It reads the splits of the step: fix fractum/fracture's end of step must come first.
  bool seen_self = false;
  for (auto &f : modify->get_fix_list()) {
    if (f == this)
      seen_self = true;
    else if (seen_self && utils::strmatch(f->style, "^fractum/fracture$"))
      error->all(FLERR,
                 "{} {} must be defined after fix fractum/fracture {} (it adapts the step to the "
                 "splits that fix makes in the same step)",
                 STYLE, id, f->id);
  }
  // The setup's evaluation sums the shares: setup() checks the step against them.
  sums->want_shares(true);
}

void FixFractumDt::setup(int)
{
  check();
  schedule();
}

/* The next evaluation sums shares when the step is to be adapted then (every EVERY steps, or
   the step that splits the grains found failing) or checked (every step without adaptation). */
void FixFractumDt::schedule()
{
  if (every > 0)
    sums->want_shares((update->ntimestep + 1) % every == 0 || sums->split_next_step());
  else
    // Without the adaptation the step is still checked, at every step (a contact closes within
    // a few steps: a check at output steps came after a run had already lost grains).
    sums->want_shares(true);
}

void FixFractumDt::end_of_step()
{
  if (every > 0) {
    // Fractum adapts after a split on the forces at the new shapes, and at its output steps;
    // here the halves' first evaluation is in the step after the decision.
    const bigint step = update->ntimestep;
    if (sums->split_this_step())
      adapt(sums->largest_share(world, atom->nlocal));
    else if (step % every == 0 && !sums->split_next_step() && sums->shares_wanted()) {
      // The contacts of the steps just taken: above omega dt 2 some of those steps were
      // unstable, which the adaptation alone shortened without a word (a step 28 times too
      // long ran unchecked between adaptations). Said once, with the step to set; the run
      // goes on at the shortened step. (After a split the halves' contacts are new: their step
      // is shortened before any is taken.)
      const double sum = sums->largest_share(world, atom->nlocal);
      unstable_since_last(sum);
      adapt(sum);
    }
  } else if (sums->shares_wanted()) {
    check();
  }
  schedule();
}

/* The step against the stiffest body's contacts, as Fractum's run checks it
   (fractum_kernel_step_check): velocity Verlet is unstable above omega dt = 2 (the run stops
   here) and resolves a contact by few steps above 1.6 (a warning, once). */
void FixFractumDt::check()
{
  double wdt = 0.0;
  const int verdict = step_verdict(sums->largest_share(world, atom->nlocal), wdt);
  const double omega = wdt / update->dt;
  if (verdict == 2)
    error->all(FLERR,
               "{}: the time step {} s is too long for the contacts at step {}: the stiffest body "
               "oscillates with omega dt = {:.3f}, and velocity Verlet needs less than 2; "
               "set timestep below {:.4g} s ({:.4g} s gives omega dt 0.6)",
               STYLE, update->dt, update->ntimestep, wdt, 2.0 / omega, 0.6 / omega);
  if (verdict == 1 && !warned && comm->me == 0)
    error->warning(FLERR,
                   "{}: omega dt = {:.3f} at step {}: contacts are resolved by few steps and "
                   "results lose accuracy; consider timestep {:.4g} s (omega dt 0.6)",
                   STYLE, wdt, update->ntimestep, 0.6 / omega);
  if (verdict == 1) warned = true;
}

/* fractum_kernel_step_check of the present step against the largest frequency share `sum`:
   the verdict (0 fine, 1 few steps per contact, 2 unstable), omega dt into `wdt`. */
int FixFractumDt::step_verdict(double sum, double &wdt)
{
  int verdict = 0;
  wdt = 0.0;
  int status = fractum_kernel_step_check(sum, update->dt, &wdt, &verdict);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "step_check", status);
  return verdict;
}

/* At a scheduled adaptation, on the largest share `sum` of this step: whether the steps since
   the last one ran above omega dt 2, a warning (once) naming the step and the timestep to
   set. */
void FixFractumDt::unstable_since_last(double sum)
{
  if (unstable_warned) return;
  double wdt = 0.0;
  if (step_verdict(sum, wdt) != 2) return;
  unstable_warned = true;
  if (comm->me == 0)
    error->warning(FLERR,
                   "{}: omega dt = {:.3f} at step {}, the adaptation every {} steps: steps since "
                   "the last one ran above velocity Verlet's limit of 2, where a contact's "
                   "energy grows at every step; the step is shortened now, but those steps "
                   "were not resolved: set timestep below {:.4g} s or adapt more often",
                   STYLE, wdt, update->ntimestep, every, 2.0 * update->dt / wdt);
}

/* Shortens the step when the largest frequency estimate of this step's contacts (the largest
   share `sum`) asks. */
void FixFractumDt::adapt(double sum)
{
  double next = update->dt;
  int status = fractum_kernel_adapted_step(sum, update->dt, omega_dt, &next);
  if (status != FRACTUM_OK) fractum_kernel_failed(lmp, STYLE, "adapted_step", status);
  if (next == update->dt) return;
  // As fix dt/reset: everything that depends on the step learns it.
  update->update_time();
  update->dt = next;
  update->dt_default = 0;
  if (force->pair) force->pair->reset_dt();
  for (auto &ifix : modify->get_fix_list()) ifix->reset_dt();
  output->reset_dt();
  shortened += 1.0;
}

double FixFractumDt::compute_vector(int n)
{
  return n == 0 ? shortened : update->dt;
}

void FixFractumDt::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  double buf[3] = {1.0, shortened, warned ? 1.0 : 0.0};
  int size = sizeof buf;
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(buf, sizeof buf, 1, fp);
}

void FixFractumDt::restart(char *raw)
{
  auto *buf = reinterpret_cast<double *>(raw);
  if (static_cast<int>(buf[0]) != 1)
    error->all(FLERR, "{}: the restart file's step state is not this plugin's", STYLE);
  shortened = buf[1];
  warned = buf[2] != 0.0;
}
