//! What an estimated `ω dt` (the highest contact frequency, rad/s, times the step, s) says of
//! a velocity Verlet step, and the shorter step a run adapts to: shared by the granular run's
//! step check and the C ABI's step kernels, so that Fractum and a host judge alike.

/// Above this estimated `ω dt` a run stops, above the second it warns.
const OMEGA_DT_LIMIT: f64 = 2.0;
const OMEGA_DT_WARN: f64 = 1.6;

/// What an estimated `ω dt` says of a step: above `OMEGA_DT_LIMIT` velocity Verlet is
/// unstable (the run stops), above `OMEGA_DT_WARN` contacts are resolved by few steps (a
/// warning); Fractum's run and the LAMMPS plugin (`fractum_kernel_step_check`) judge alike.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepVerdict {
    Fine,
    Coarse,
    Unstable,
}

/// The verdict on an estimated `omega_dt` (see [`StepVerdict`]).
pub fn step_verdict(omega_dt: f64) -> StepVerdict {
    if omega_dt > OMEGA_DT_LIMIT {
        StepVerdict::Unstable
    } else if omega_dt > OMEGA_DT_WARN {
        StepVerdict::Coarse
    } else {
        StepVerdict::Fine
    }
}

/// The step a fracture run takes after `dt` (s) when the highest frequency of its contacts is
/// estimated at `omega` (rad/s): shortened to give `ω dt` = `target` when it is above that,
/// else `None` (keep `dt`).
pub fn adapted_step(omega: f64, dt: f64, target: f64) -> Option<f64> {
    let omega_dt = omega * dt;
    (omega_dt > target).then(|| dt * (target / omega_dt))
}
