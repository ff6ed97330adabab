//! The policy of a run's step and what it has done: how often the bound on the highest
//! frequency is checked, the `ω dt` a shortened step aims at, the verdict on each estimate, the
//! shortenings, the largest `ω dt` seen and a step that collapsed. A model supplies the bound
//! (ω, rad/s); the control answers with the step to take from now on, which the runner alone
//! writes into its clock.

use serde::{Deserialize, Serialize};

use super::stability::{StepVerdict, adapted_step, step_verdict};

/// The most steps a run may plan to its end: at a microsecond per step (a tiny scene) that is
/// 17 minutes, at the main job's milliseconds weeks. A scene that asks for more (a step of
/// 1e-300 s, or a Young's modulus of 1e308 Pa under `time.dt = "auto"`) used to plan
/// 18446744073709551615 steps and run forever.
/// A shortened step is held to it too (see [`StepControl::adapt`]).
pub const MAX_STEPS: f64 = 1e9;

/// A run's step control (see the module's docs). Saved with the model's state: the counters
/// go on across a checkpoint.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StepControl {
    /// Steps between checks (1: after every step); the last step is checked too.
    pub every: u64,
    /// The `ω dt` a shortened step aims at; `None`: the step is never shortened.
    pub target: Option<f64>,
    /// The run's first step (s), which the collapse message starts from.
    pub first_dt: f64,
    /// The largest `ω dt` seen at a check.
    pub max_omega_dt: f64,
    /// Times the step was shortened.
    pub shortened: u32,
    /// Why the step collapsed, once it has (more steps left than the limit); the run stops at
    /// the next check saying so.
    pub collapsed: Option<String>,
}

impl StepControl {
    /// A control that checks every `every` steps and, with `target`, shortens the step to
    /// that `ω dt`; `first_dt` (s) is the run's first step.
    pub fn new(every: u64, target: Option<f64>, first_dt: f64) -> Self {
        StepControl {
            every: every.max(1),
            target,
            first_dt,
            max_omega_dt: 0.0,
            shortened: 0,
            collapsed: None,
        }
    }

    /// Whether the check is due after step `step` of a run that ends at `end_step`.
    pub fn due(&self, step: u64, end_step: u64) -> bool {
        self.every == 1 || step % self.every == 0 || step == end_step
    }

    /// The step (s) to take from now on after an estimate `omega` (rad/s) at steps of `dt`
    /// (s) with `remaining` seconds to the end (infinite: driven from outside): shortened to
    /// give [`StepControl::target`] when `ω dt` is above it, else `None` (keep `dt`). Notes a
    /// collapse: a step so short that the time left takes more than 1e9 steps (stiffening
    /// contacts the step cannot follow used to leave a run that went on for ever without a
    /// word).
    pub fn adapt(&mut self, omega: f64, dt: f64, remaining: f64) -> Option<f64> {
        let new = adapted_step(omega, dt, self.target?)?;
        self.shortened += 1;
        let left = remaining / new;
        if self.collapsed.is_none() && (left.is_nan() || (left.is_finite() && left > MAX_STEPS)) {
            self.collapsed = Some(format!(
                "the time step collapsed from {:.3e} s (the first) to {new:.3e} s ({} shortenings, the last from {dt:.3e} s): contacts stiffen faster than the step can follow (highest contact frequency {omega:.3e} rad/s), and the {remaining:.3e} s left to the end of the loading would take {left:.2e} steps, more than the limit of 1e9; the grains or pieces are crushed beyond what the contact law describes: check the sample's shapes and the loading (loading.speed, loading.end_displacement), or give time.dt in seconds",
                self.first_dt, self.shortened
            ));
        }
        Some(new)
    }

    /// The verdict on an estimate `omega` (rad/s) at the step now in force `dt` (s), at step
    /// `step` and time `time` (s): the largest `ω dt` is kept; a collapsed step or an unstable
    /// one (velocity Verlet needs `ω dt < 2`) is the error sentence, a coarse one a warning,
    /// once, in `warnings`. `safety` is the scene's `time.safety`, which the advice names.
    pub fn judge(
        &mut self,
        omega: f64,
        dt: f64,
        step: u64,
        time: f64,
        safety: f64,
        warnings: &mut Vec<String>,
    ) -> Result<(), String> {
        if let Some(why) = &self.collapsed {
            return Err(format!(
                "the run stopped at step {step} (t = {time:e} s): {why}"
            ));
        }
        let omega_dt = omega * dt;
        self.max_omega_dt = self.max_omega_dt.max(omega_dt);
        match step_verdict(omega_dt) {
            StepVerdict::Unstable => Err(format!(
                "the time step is too long for the contacts at step {step} (t = {time:e} s): the stiffest body oscillates with omega dt = {omega_dt:.2}, and velocity Verlet needs less than 2; lower time.safety (now {safety}) or time.dt"
            )),
            StepVerdict::Coarse => {
                if !warnings.iter().any(|w| w.starts_with("omega dt")) {
                    warnings.push(format!(
                        "omega dt reached {omega_dt:.2} at step {step} (t = {time:e} s): contacts are resolved by few steps and results lose accuracy (two spheres meeting at 0.9 of the critical step, omega dt 1.93, rebound 48% too fast); consider a lower time.safety"
                    ));
                }
                Ok(())
            }
            StepVerdict::Fine => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_is_shortened_to_the_target_and_never_without_one() {
        let mut c = StepControl::new(10, Some(1.2), 1e-7);
        // omega dt = 2.4 at dt = 1e-7: half the step gives the target 1.2.
        let new = c.adapt(2.4e7, 1e-7, 1e-3).unwrap();
        assert!((new - 0.5e-7).abs() < 1e-21, "{new}");
        assert_eq!(c.shortened, 1);
        assert!(c.adapt(1.0e7, 1e-7, 1e-3).is_none());
        let mut fixed = StepControl::new(1, None, 1e-7);
        assert!(fixed.adapt(2.4e7, 1e-7, 1e-3).is_none());
        assert_eq!(fixed.shortened, 0);
    }

    #[test]
    fn a_collapsed_step_stops_the_run_at_the_next_check() {
        let mut c = StepControl::new(10, Some(1.2), 1e-7);
        // 1 s left at a step of 1.2e-12 s: 8.3e11 steps.
        let new = c.adapt(1e12, 1e-7, 1.0).unwrap();
        assert!(c.collapsed.is_some());
        let err = c
            .judge(1e12, new, 7, 0.1, 0.4, &mut Vec::new())
            .unwrap_err();
        assert!(err.contains("collapsed") && err.contains("step 7"), "{err}");
        // A run driven from outside (no end) never collapses.
        let mut open = StepControl::new(10, Some(1.2), 1e-7);
        open.adapt(1e12, 1e-7, f64::INFINITY).unwrap();
        assert!(open.collapsed.is_none());
    }

    #[test]
    fn the_verdict_follows_omega_dt_and_warns_once() {
        let mut c = StepControl::new(1, None, 1e-7);
        let mut w = Vec::new();
        assert!(c.judge(1.0e7, 1e-7, 1, 0.0, 0.4, &mut w).is_ok());
        assert!(w.is_empty());
        assert!(c.judge(1.8e7, 1e-7, 2, 0.0, 0.4, &mut w).is_ok());
        assert!(c.judge(1.9e7, 1e-7, 3, 0.0, 0.4, &mut w).is_ok());
        assert_eq!(w.len(), 1);
        assert!(c.judge(2.1e7, 1e-7, 4, 0.0, 0.4, &mut w).is_err());
        assert!((c.max_omega_dt - 2.1).abs() < 1e-12);
        assert!(c.due(20, 100) && c.due(5, 5) && !StepControl::new(10, None, 1.0).due(5, 100));
    }
}
