//! Velocity Verlet for rigid spheres:
//!
//! ```text
//! v(t + dt/2) = v(t) + dt/2 · F(t) / m          ω likewise with T / I
//! x(t + dt)   = x(t) + dt · v(t + dt/2)
//! F(t + dt)   = forces at x(t + dt), with velocities v(t + dt/2)
//! v(t + dt)   = v(t + dt/2) + dt/2 · F(t + dt) / m
//! ```
//!
//! The angular update `ω += dt/2 · T / I` holds for bodies whose inertia is isotropic
//! (spheres); orientations are advanced only when something reads them.

use nalgebra::UnitQuaternion;
use rayon::prelude::*;

use crate::parallel::threads_here;
use crate::state::{Bodies, Forces, Vec3};

#[derive(Debug, Clone, Copy, Default)]
pub struct VelocityVerlet {
    /// Advance orientation quaternions (needed by non-spherical shapes and break planes;
    /// spheres' forces never read them).
    pub track_orientation: bool,
}

/// Bodies below which the update runs on one thread whatever the pool.
const PAR_MIN: usize = 8192;

impl VelocityVerlet {
    /// First half kick and drift: velocities to t + dt/2, positions to t + dt.
    pub fn kick_drift(&self, b: &mut Bodies, f: &Forces, dt: f64) {
        let half = 0.5 * dt;
        let track = self.track_orientation;
        let Bodies {
            pos,
            vel,
            omega,
            orientation,
            inv_mass,
            inv_inertia,
            ..
        } = b;
        let update =
            |i: usize, x: &mut Vec3, v: &mut Vec3, w: &mut Vec3, q: &mut UnitQuaternion<f64>| {
                *v += f.force[i] * (half * inv_mass[i]);
                *x += *v * dt;
                *w += f.torque[i].component_mul(&inv_inertia[i]) * half;
                if track {
                    *q = advance_orientation(q, w, dt);
                }
            };
        if pos.len() >= PAR_MIN && threads_here() > 1 {
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

    /// Second half kick: velocities to t + dt with the new forces.
    pub fn kick(&self, b: &mut Bodies, f: &Forces, dt: f64) {
        let half = 0.5 * dt;
        let Bodies {
            vel,
            omega,
            inv_mass,
            inv_inertia,
            ..
        } = b;
        let update = |(i, (v, w)): (usize, (&mut Vec3, &mut Vec3))| {
            *v += f.force[i] * (half * inv_mass[i]);
            *w += f.torque[i].component_mul(&inv_inertia[i]) * half;
        };
        if vel.len() >= PAR_MIN && threads_here() > 1 {
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
}

/// Rotates `q` by the angular velocity `w` (world frame) over `dt`.
pub(crate) fn advance_orientation(
    q: &UnitQuaternion<f64>,
    w: &Vec3,
    dt: f64,
) -> UnitQuaternion<f64> {
    UnitQuaternion::from_scaled_axis(w * dt) * q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_fall_is_exact_for_constant_force() {
        let mut b = Bodies::default();
        b.push_sphere(Vec3::zeros(), 0.01, 1000.0, UnitQuaternion::identity());
        let m = b.mass[0];
        let mut f = Forces::new(1);
        f.force[0] = Vec3::new(0.0, 0.0, -9.81 * m);
        let vv = VelocityVerlet::default();
        let dt = 1e-3;
        for _ in 0..1000 {
            vv.kick_drift(&mut b, &f, dt);
            vv.kick(&mut b, &f, dt);
        }
        // Velocity Verlet integrates constant acceleration exactly: z = -g t^2 / 2 at t = 1 s.
        assert!((b.pos[0].z + 0.5 * 9.81).abs() < 1e-9);
        assert!((b.vel[0].z + 9.81).abs() < 1e-9);
    }
}
