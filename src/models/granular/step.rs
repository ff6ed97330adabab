//! One granular step's physics: the force evaluation, the worker team, and the stability
//! check with its step adaptation.

use super::*;

/// Spheres per thread from which a granular step runs on the worker team (see
/// `Physics::team_members` below).
pub(super) const TEAM_MIN_SPHERES_PER_THREAD: usize = 1500;

/// Steps between the stability checks and step adaptations of a granular run that adapts its
/// step (fracture with `time.dt = "auto"`; also after every split and at the last step); other
/// runs check after every step. A fixed cadence, so that what a run computes does not depend
/// on `output.every` (at output steps only, a flat grain's contacts stiffened unseen for the
/// scene's 50 steps and its step collapsed where `output.every = 1` finished). Checking a
/// fracture run after every step cost 1.6 times its time per step (the estimate takes an
/// eigenvalue per contact record); every 10 steps a tenth of that, and the adaptation keeps
/// its ω dt at `ADAPT_PER_SAFETY` × safety (1.2 at 0.4), below the limit of 2, in between.
/// `fractum export lammps --plugin` writes it as the plugin's `fix fractum/dt` EVERY.
pub const STABILITY_EVERY: u64 = 10;

/// A fracture run with `time.dt = "auto"` keeps the estimated `ω dt` of its stiffest body at
/// most this times `time.safety` (1.2 at the main job's 0.4): the safety that sets the first step
/// from the Rayleigh step also sets how close to the stiffest contact the step stays as pieces
/// appear (docs/performance.md: the main job's ensembles at each safety).
pub const ADAPT_PER_SAFETY: f64 = 3.0;

impl Granular {
    pub(super) fn evaluate_forces(&mut self, dt: f64, update_history: bool) {
        let st = &mut self.state;
        st.forces.clear();
        st.walls.clear_forces();
        let ctx = StepContext { dt, update_history };
        self.pipeline
            .accumulate(&ctx, &st.bodies, &mut st.walls, &mut st.forces);
        if let Some(f) = &mut st.fracture {
            f.add_spring_forces(&st.bodies, &mut st.forces);
        }
    }

    /// Breaking grains make pieces smaller than any grain of the sample, and contacts between
    /// them as stiff as their overlaps make them: with `fracture` and `time.dt = "auto"`, the
    /// step is shortened whenever the bound on the highest frequency (normal and tangential
    /// contact springs through their levers, `records_max_frequency`) gives `ω dt` above
    /// [`ADAPT_PER_SAFETY`] × `time.safety`; it never grows back. Checked every
    /// [`STABILITY_EVERY`] steps and after every split. Without it the pieces' spins went
    /// unstable (ω dt estimated 1.3, the rotational modes beyond 2) and fed energy to the
    /// contacts' damping: 91% energy-balance error in a 5×5×5 hcp SHPB sample at 0.2 strain.
    /// Returns the step to take from now on, `None` to keep `clock.dt`.
    pub(super) fn adapted_step(&mut self, clock: &Clock) -> Option<f64> {
        let omega = self
            .pipeline
            .max_frequency(&self.state.bodies, &self.state.walls);
        self.state
            .step_control
            .adapt(omega, clock.dt, clock.remaining())
    }

    /// Velocity Verlet is stable while `ω dt < 2` for the highest frequency ω of the system.
    /// Hertz contacts stiffen as they overlap, so a step chosen from the Rayleigh time can
    /// become too long under heavy compaction: then the results go wrong before anything turns
    /// infinite (SHPB to 10% strain: 1% off at an estimated ω dt of 1.7, 22% at 2.04). The
    /// estimate is checked after every step (every [`STABILITY_EVERY`] while the step adapts);
    /// above 2 the run stops, above 1.6 it warns. Returns the step to take from now on.
    pub(super) fn check_stability(
        &mut self,
        scene: &Scene,
        clock: &Clock,
        warnings: &mut Vec<String>,
    ) -> Result<Option<f64>> {
        let omega = self
            .pipeline
            .max_frequency(&self.state.bodies, &self.state.walls);
        let sc = &mut self.state.step_control;
        let new = sc.adapt(omega, clock.dt, clock.remaining());
        sc.judge(
            omega,
            new.unwrap_or(clock.dt),
            clock.step,
            clock.time,
            scene.time.safety,
            warnings,
        )
        .map_err(Error::run)?;
        Ok(new)
    }
}
