//! Time integration and the critical time step.

mod stability;
mod step_control;
mod tchamwa_wielgosz;
pub mod velocity_verlet;
// beam2d: Gear's predictor-corrector and velocity Verlet on flat arrays of degrees of freedom.
pub mod gear5;

pub use gear5::Gear5;
pub use stability::{StepVerdict, adapted_step, step_verdict};
pub use step_control::{MAX_STEPS, StepControl};
pub use tchamwa_wielgosz::TchamwaWielgosz;
pub use velocity_verlet::{VelocityVerlet, drift, half_kick, kick_dofs, kick_drift_dofs};

use nalgebra::UnitQuaternion;
use rayon::prelude::*;

use crate::parallel::{on_team, split_ranges, team_blocks, threads_here};
use crate::state::Vec3;

/// Bodies below which an update runs on one thread in a rayon pool without a team.
const PAR_MIN: usize = 8192;

/// Runs `update(i, x, v, ω, q)` on every body: in blocks dealt across the run's team, across
/// the rayon pool for large systems of models that use no team, in index order on this thread
/// otherwise (each body's update is independent, so all give the same bits).
fn each_body(
    pos: &mut [Vec3],
    vel: &mut [Vec3],
    omega: &mut [Vec3],
    orientation: &mut [UnitQuaternion<f64>],
    update: impl Fn(usize, &mut Vec3, &mut Vec3, &mut Vec3, &mut UnitQuaternion<f64>) + Sync + Send,
) {
    if let Some(ranges) = team_blocks(pos.len()) {
        let parts: Vec<_> = ranges
            .iter()
            .zip(split_ranges(pos, &ranges))
            .zip(split_ranges(vel, &ranges))
            .zip(split_ranges(omega, &ranges))
            .zip(split_ranges(orientation, &ranges))
            .collect();
        on_team(parts, |_, ((((r, x), v), w), q)| {
            for k in 0..r.len() {
                update(r.start + k, &mut x[k], &mut v[k], &mut w[k], &mut q[k]);
            }
        });
    } else if pos.len() >= PAR_MIN && threads_here() > 1 {
        pos.par_iter_mut()
            .zip(vel.par_iter_mut())
            .zip(omega.par_iter_mut())
            .zip(orientation.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_MIN / 2)
            .for_each(|(i, (((x, v), w), q))| update(i, x, v, w, q));
    } else {
        pos.iter_mut()
            .zip(vel.iter_mut())
            .zip(omega.iter_mut())
            .zip(orientation.iter_mut())
            .enumerate()
            .for_each(|(i, (((x, v), w), q))| update(i, x, v, w, q));
    }
}

/// Runs `update((i, (v, ω)))` on every body's velocities, like [`each_body`].
fn each_velocity(
    vel: &mut [Vec3],
    omega: &mut [Vec3],
    update: impl Fn((usize, (&mut Vec3, &mut Vec3))) + Sync + Send,
) {
    if let Some(ranges) = team_blocks(vel.len()) {
        let parts: Vec<_> = ranges
            .iter()
            .zip(split_ranges(vel, &ranges))
            .zip(split_ranges(omega, &ranges))
            .collect();
        on_team(parts, |_, ((r, v), w)| {
            for (k, (v, w)) in v.iter_mut().zip(w.iter_mut()).enumerate() {
                update((r.start + k, (v, w)));
            }
        });
    } else if vel.len() >= PAR_MIN && threads_here() > 1 {
        vel.par_iter_mut()
            .zip(omega.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_MIN / 2)
            .for_each(update);
    } else {
        vel.iter_mut()
            .zip(omega.iter_mut())
            .enumerate()
            .for_each(update);
    }
}

/// Rayleigh critical time step (s) of a sphere of radius `r` (m):
/// `π r sqrt(ρ / G) / (0.1631 ν + 0.8766)`, the time a Rayleigh wave takes to cross it.
pub fn rayleigh_time_step(r: f64, density: f64, young: f64, poisson: f64) -> f64 {
    let g = young / (2.0 * (1.0 + poisson));
    std::f64::consts::PI * r * (density / g).sqrt() / (0.1631 * poisson + 0.8766)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rayleigh_step_of_quartz_grain() {
        // r = 0.3 mm, E = 60 GPa, nu = 0.17, rho = 2650: G = 25.64 GPa,
        // pi * 3e-4 * sqrt(2650 / 2.564e10) / 0.904327 = 3.3503e-7 s.
        let dt = rayleigh_time_step(0.3e-3, 2650.0, 60e9, 0.17);
        assert!((dt - 3.3503e-7).abs() < 1e-10, "{dt}");
    }
}
