//! One granular step's physics: the force evaluation, the worker team, and the stability
//! check with its step adaptation.

use super::*;

/// Spheres per thread from which a granular step runs on the worker team (see
/// `Model::team_members` below).
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
    /// [`ADAPT_PER_SAFETY`] × `time.safety`; it never grows back. Checked after every step
    /// and every split. Without it the pieces' spins went unstable (ω dt estimated 1.3,
    /// the rotational modes beyond 2) and fed energy to the contacts' damping: 91%
    /// energy-balance error in a 5×5×5 hcp SHPB sample at 0.2 strain.
    /// `omega` is the current estimate of the highest frequency (rad/s).
    pub(super) fn adapt_time_step(&mut self, clock: &mut Clock, omega: f64) {
        if self.state.fracture.is_none() || !self.auto_dt {
            return;
        }
        let Some(dt) = adapted_step(omega, clock.dt, self.adapt_omega_dt) else {
            return;
        };
        let before = clock.dt;
        clock.set_dt(dt);
        self.state.dt_shortened += 1;
        let remaining = clock.remaining();
        // The limit of steps the build checks holds for the steps left after a shortening
        // too: a step that collapses (stiffening contacts the step cannot follow) used to leave
        // a run that went on for ever without a word.
        let left = remaining / clock.dt;
        if self.collapsed.is_none() && (left.is_nan() || left > crate::run::MAX_STEPS) {
            self.collapsed = Some(format!(
                "the time step collapsed from {:.3e} s (the first) to {dt:.3e} s ({} shortenings, the last from {before:.3e} s): contacts stiffen faster than the step can follow (highest contact frequency {omega:.3e} rad/s), and the {remaining:.3e} s left to the end of the loading would take {left:.2e} steps, more than the limit of 1e9; the grains or pieces are crushed beyond what the contact law describes: check the sample's shapes and the loading (loading.speed, loading.end_displacement), or give time.dt in seconds",
                self.state.dt_rayleigh * self.adapt_omega_dt / ADAPT_PER_SAFETY,
                self.state.dt_shortened
            ));
        }
    }

    /// Velocity Verlet is stable while `ω dt < 2` for the highest frequency ω of the system.
    /// Hertz contacts stiffen as they overlap, so a step chosen from the Rayleigh time can
    /// become too long under heavy compaction: then the results go wrong before anything turns
    /// infinite (SHPB to 10% strain: 1% off at an estimated ω dt of 1.7, 22% at 2.04). The
    /// estimate is checked after every step; above 2 the run stops, above 1.6 it warns.
    pub(super) fn check_stability(
        &mut self,
        scene: &Scene,
        clock: &mut Clock,
        warnings: &mut Vec<String>,
    ) -> Result<()> {
        let omega = self
            .pipeline
            .max_frequency(&self.state.bodies, &self.state.walls);
        self.adapt_time_step(clock, omega);
        if let Some(why) = &self.collapsed {
            return Err(Error::run(format!(
                "the run stopped at step {} (t = {:e} s): {why}",
                clock.step, clock.time
            )));
        }
        let omega_dt = omega * clock.dt;
        self.state.max_omega_dt = self.state.max_omega_dt.max(omega_dt);
        let verdict = step_verdict(omega_dt);
        if verdict == StepVerdict::Unstable {
            return Err(Error::run(format!(
                "the time step is too long for the contacts at step {} (t = {:e} s): the stiffest body oscillates with omega dt = {omega_dt:.2}, and velocity Verlet needs less than 2; lower time.safety (now {}) or time.dt",
                clock.step, clock.time, scene.time.safety
            )));
        }
        if verdict == StepVerdict::Coarse && !warnings.iter().any(|w| w.starts_with("omega dt")) {
            warnings.push(format!(
                "omega dt reached {omega_dt:.2} at step {} (t = {:e} s): contacts are resolved by few steps and results lose accuracy (two spheres meeting at 0.9 of the critical step, omega dt 1.93, rebound 48% too fast); consider a lower time.safety",
                clock.step, clock.time
            ));
        }
        Ok(())
    }
}
