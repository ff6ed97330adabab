//! Where a run is in time, and the limits its plan is held to: at most [`MAX_STEPS`] steps to
//! its end, at least [`MIN_STEPS`] under an automatic step, and a restored clock that agrees
//! with its end.

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::scene::Scene;

/// Where a run is in time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Clock {
    /// Time (s).
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// Time step (s).
    pub dt: f64,
    /// The step at which the run ends (`u64::MAX`: driven from outside, no end of its own).
    pub end_step: u64,
    /// The time (s) at which the run ends (infinite: driven from outside): a new step keeps
    /// it ([`Clock::set_dt`]).
    pub end_time: f64,
}

impl Clock {
    /// Steps of `dt` (s) from now on: the run still ends at its end time, in steps of the new
    /// length, none once the end time is reached (a shortening at the last step used to add
    /// one step, and another at that one another: runs overran their end strain).
    pub fn set_dt(&mut self, dt: f64) {
        self.dt = dt;
        if self.end_step == u64::MAX {
            return;
        }
        let remaining = self.end_time - self.time;
        self.end_step = if remaining > 1e-9 * dt {
            self.step.saturating_add(end_step(remaining, dt))
        } else {
            self.step
        };
    }

    /// The clock a run starts from: t = 0 at step 0, steps of `dt` (s) to `end_time` (s;
    /// infinite: driven from outside), the end step from them. Refused, naming the key at
    /// fault, when that plan needs more than [`MAX_STEPS`] steps or, under `time.dt = "auto"`,
    /// fewer than [`MIN_STEPS`] (the sentences of `check_planned_steps`; `young` is the model's
    /// `material.young`, Pa). Every model starts its run from this.
    pub fn planned(scene: &Scene, young: f64, dt: f64, end_time: f64) -> Result<Clock> {
        check_planned_steps(scene, young, end_time, dt)?;
        Ok(Clock {
            time: 0.0,
            step: 0,
            dt,
            end_step: end_step(end_time, dt),
            end_time,
        })
    }

    /// The time (s) left to the end.
    pub fn remaining(&self) -> f64 {
        self.end_time - self.time
    }
}

pub use crate::integrate::MAX_STEPS;

/// Below this Young's modulus (Pa) a step too long for the loading is the material's fault
/// (softer than any solid that breaks); above it the loading is too short (a strain rate of
/// 1e308/s) or the grains or elements too large (a DLSM bar 1e9 m long), and the message says
/// so instead of asking for a stiffer material.
const YOUNG_SOFTEST: f64 = 1e6;

/// The fewest steps a run under `time.dt = "auto"` may plan to its end: its step may be at most
/// half the loading, so that the end is overshot by at most half of it.
pub const MIN_STEPS: f64 = 2.0;

/// Refuses a loading of `end_time` seconds at steps of `dt` seconds that needs more than
/// [`MAX_STEPS`] steps, naming `time.dt`; an endless loading (driven from outside) passes.
/// `young` is the model's `material.young` (Pa), which the critical step scales with as
/// 1/√young in every model: the messages name it when it is at fault.
fn check_planned_steps(scene: &Scene, young: f64, end_time: f64, dt: f64) -> Result<()> {
    if end_time.is_infinite() && end_time > 0.0 {
        return Ok(());
    }
    let steps = end_time / dt;
    let auto = matches!(scene.time.dt, crate::scene::DtSpec::Auto);
    if auto && steps.is_finite() && steps < MIN_STEPS && end_time > 0.0 {
        // A step across most of the loading is no run: shpb_sand with a Young's modulus of
        // 1e3 Pa and a short loading took one step to 7 times its end strain and exited 0
        // with a 72% energy error, and the advice named time.safety where the modulus was at
        // fault. Under "auto" the user did not choose the step: the material (or the
        // loading) is at fault. A step given in seconds is the user's own, and tests give a
        // long one on purpose to see a run go unstable.
        let longest = end_time / MIN_STEPS;
        // The critical step grows as 1/√young: the modulus that gives `longest`.
        let young_needed = (dt * young.sqrt() / longest).powi(2);
        return Err(if young >= YOUNG_SOFTEST {
            scene.key_error(
                "time.dt",
                format!(
                    "= \"auto\" gives a step of {dt:.3e} s (time.safety x the critical step of the \
                     material, material.young = {young:e} Pa, and the sample's grains or \
                     elements), and the loading ends at {end_time:.3e} s: {steps:.2} steps, fewer \
                     than {MIN_STEPS}; the loading is too short or the grains or elements too large \
                     for this material: allowed: a loading that lasts at least {:.3e} s (check its \
                     rate and its end), or time.dt in seconds of at most {longest:.3e} s",
                    dt * MIN_STEPS
                ),
            )
        } else if !dt.is_finite() || !young_needed.is_finite() {
            // A modulus such as 5e-324 Pa gives an infinite step: "material.young >= inf
            // Pa" said nothing.
            scene.key_error(
                "material.young",
                format!(
                    "= {young:e} Pa is too soft for time.dt = \"auto\": the step comes out as \
                     {dt:e} s (it grows as 1/√young), and the loading ends at {end_time:.3e} s; \
                     allowed: a material.young for which the step is at most half the loading \
                     (a solid's modulus, 1e6 Pa and up)"
                ),
            )
        } else {
            scene.key_error(
                "material.young",
                format!(
                    "= {young:e} Pa is too soft for this loading under time.dt = \"auto\": the step comes out as {dt:.3e} s, and the loading (its end at {end_time:.3e} s) would take {steps:.2} steps, fewer than {MIN_STEPS}; allowed: material.young >= {young_needed:.3e} Pa at this loading and time.safety, or a loading that lasts at least {:.3e} s",
                    dt * MIN_STEPS
                ),
            )
        });
    }
    if steps.is_finite() && steps <= MAX_STEPS {
        return Ok(());
    }
    if auto && !dt.is_normal() {
        // The critical step scales as 1/sqrt(young): a modulus near the largest double gives a
        // zero or denormal step, and "time.dt = 0 s needs inf steps" blamed the wrong key.
        return Err(scene.key_error(
            "material.young",
            format!(
                "= {young:e} Pa is too stiff for time.dt = \"auto\": the critical step of the material and sample comes out as {dt:e} s (zero or denormal), which cannot reach the end of the loading at {end_time:.4e} s within the limit of 1e9 steps; lower material.young"
            ),
        ));
    }
    let how = match scene.time.dt {
        crate::scene::DtSpec::Auto => {
            " (auto: time.safety x the critical step of the material and sample)"
        }
        crate::scene::DtSpec::Seconds(_) => "",
    };
    Err(scene.key_error(
        "time.dt",
        format!(
            "= {dt:.4e} s{how} needs {steps:.2e} steps to reach the end of the loading at {end_time:.4e} s, more than the limit of 1e9 steps: check time.dt, the material's stiffness and the loading"
        ),
    ))
}

/// A restored clock against the limits a built run is held to: a run with an end ends within
/// [`MAX_STEPS`] steps of its step and at the step its end time gives (to 1% and two steps:
/// a variable step moves both); one without an end (driven from outside) has neither. A
/// re-sealed checkpoint with `end_step = 2^64 − 1` resumed past the limit, `step > end_step`
/// printed a wrapped step count, and `dt = 1e-300` exited 0 without advancing.
pub(super) fn check_restored_clock(c: &Clock) -> std::result::Result<(), String> {
    let endless = c.end_time.is_infinite() && c.end_time > 0.0;
    if endless != (c.end_step == u64::MAX) {
        return Err(format!(
            "ends at step {} but at t = {:e} s (a run driven from outside has neither end, any \
             other both)",
            c.end_step, c.end_time
        ));
    }
    if endless {
        return Ok(());
    }
    if !c.end_time.is_finite() {
        return Err(format!("ends at t = {:e} s", c.end_time));
    }
    if c.step > c.end_step {
        return Err(format!(
            "is at step {}, past the run's end at step {}",
            c.step, c.end_step
        ));
    }
    let left = (c.end_step - c.step) as f64;
    let planned = (c.remaining() / c.dt).max(0.0);
    if left > MAX_STEPS || planned > MAX_STEPS {
        return Err(format!(
            "has {left:.4e} steps of {:e} s left to its end at t = {:e} s, more than the limit \
             of 1e9 steps",
            c.dt, c.end_time
        ));
    }
    if (left - planned).abs() > 2.0 + 0.01 * left.max(planned) {
        return Err(format!(
            "has {left} steps left to its end at step {}, but {planned:.4e} steps of {:e} s to \
             its end at t = {:e} s",
            c.end_step, c.dt, c.end_time
        ));
    }
    Ok(())
}

/// The step at which a loading of `end_time` seconds ends (unbounded for an endless one).
pub fn end_step(end_time: f64, dt: f64) -> u64 {
    if end_time.is_finite() {
        (end_time / dt - 1e-9).ceil().max(1.0) as u64
    } else {
        u64::MAX
    }
}
