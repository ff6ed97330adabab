//! Velocity Verlet for rigid spheres:
//!
//! ```text
//! v(t + dt/2) = v(t) + dt/2 · F(t) / m          ω likewise with T / I
//! x(t + dt)   = x(t) + dt · v(t + dt/2)
//! F(t + dt)   = forces at x(t + dt), with velocities v(t + dt/2)
//! v(t + dt)   = v(t + dt/2) + dt/2 · F(t + dt) / m
//! ```
//!
//! Rotation: for bodies with isotropic inertia (spheres) `ω += dt/2 · T / I`. Bodies with
//! unequal principal moments (poly-ellipsoids) are kicked in angular momentum instead,
//! `L += dt/2 · T` with `L = R I Rᵀ ω`, and their angular velocity is read back from `L` through
//! the current orientation (`ω = R I⁻¹ Rᵀ L`); the drift turns the orientation by `ω dt`, with
//! `ω` read from `L` at the half-turned orientation (midpoint rule), and reads `ω` from the
//! same `L` through the new orientation. A torque-free body so keeps its
//! angular momentum exactly, and its kinetic energy to second order in `dt`.
//! Orientations are advanced only when something reads them (`track_orientation`: shapes
//! other than spheres, break planes); spheres' forces never do.
//!
//! [`half_kick`] and [`drift`] are the formula itself, shared with the flat arrays of degrees
//! of freedom of the 2D polygon model ([`kick_drift_dofs`], [`kick_dofs`]).

use std::ops::{AddAssign, Mul};

use nalgebra::UnitQuaternion;

use crate::state::{Bodies, Forces, Vec3};

#[derive(Debug, Clone, Copy, Default)]
pub struct VelocityVerlet {
    /// Advance orientation quaternions (needed by non-spherical shapes and break planes;
    /// spheres' forces never read them).
    pub track_orientation: bool,
}

impl VelocityVerlet {
    /// First half kick and drift: velocities to t + dt/2, positions to t + dt.
    pub fn kick_drift(&self, b: &mut Bodies, f: &Forces, dt: f64) {
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
                kick_drift_body(
                    x,
                    v,
                    w,
                    q,
                    &f.force[i],
                    &f.torque[i],
                    inv_mass[i],
                    &inv_inertia[i],
                    dt,
                    track,
                );
            };
        super::each_body(pos, vel, omega, orientation, update);
    }

    /// Second half kick: velocities to t + dt with the new forces.
    pub fn kick(&self, b: &mut Bodies, f: &Forces, dt: f64) {
        let track = self.track_orientation;
        let Bodies {
            vel,
            omega,
            orientation,
            inv_mass,
            inv_inertia,
            ..
        } = b;
        let orientation = &*orientation;
        let update = |(i, (v, w)): (usize, (&mut Vec3, &mut Vec3))| {
            kick_body(
                v,
                w,
                &orientation[i],
                &f.force[i],
                &f.torque[i],
                inv_mass[i],
                &inv_inertia[i],
                dt,
                track,
            );
        };
        super::each_velocity(vel, omega, update);
    }
}

/// One body's first half kick and drift (what [`VelocityVerlet::kick_drift`] does to each
/// body): position `x`, velocity `v`, angular velocity `w` and orientation `q` (body frame to
/// world) under `force` and `torque`, with inverse mass and inverse principal moments.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn kick_drift_body(
    x: &mut Vec3,
    v: &mut Vec3,
    w: &mut Vec3,
    q: &mut UnitQuaternion<f64>,
    force: &Vec3,
    torque: &Vec3,
    inv_mass: f64,
    inv_i: &Vec3,
    dt: f64,
    track: bool,
) {
    let half = 0.5 * dt;
    half_kick(v, *force, inv_mass, dt);
    drift(x, *v, dt);
    if !track {
        *w += torque.component_mul(inv_i) * half;
    } else if is_isotropic(inv_i) {
        *w += torque.component_mul(inv_i) * half;
        *q = advance_orientation(q, w, dt);
    } else {
        let l = angular_momentum(q, w, inv_i) + torque * half;
        // Turn by the angular velocity at the half-turned orientation (midpoint rule): second
        // order in dt for the orientation, hence the energy.
        let w_start = angular_velocity(q, &l, inv_i);
        let q_half = advance_orientation(q, &w_start, half);
        let w_mid = angular_velocity(&q_half, &l, inv_i);
        *q = advance_orientation(q, &w_mid, dt);
        *w = angular_velocity(q, &l, inv_i);
    }
}

/// One body's second half kick (what [`VelocityVerlet::kick`] does to each body).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn kick_body(
    v: &mut Vec3,
    w: &mut Vec3,
    q: &UnitQuaternion<f64>,
    force: &Vec3,
    torque: &Vec3,
    inv_mass: f64,
    inv_i: &Vec3,
    dt: f64,
    track: bool,
) {
    half_kick(v, *force, inv_mass, dt);
    if track && !is_isotropic(inv_i) {
        let l = angular_momentum(q, w, inv_i) + torque * (0.5 * dt);
        *w = angular_velocity(q, &l, inv_i);
    } else {
        *w += torque.component_mul(inv_i) * (0.5 * dt);
    }
}

/// True for a body whose three principal moments are equal (a sphere): its angular momentum
/// is parallel to its angular velocity whatever its orientation.
#[inline]
fn is_isotropic(inv_inertia: &Vec3) -> bool {
    inv_inertia.x == inv_inertia.y && inv_inertia.y == inv_inertia.z
}

/// Angular momentum `R I Rᵀ ω` (world frame) of a body with principal inverse moments
/// `inv_inertia` in its body frame, orientation `q` (body to world).
#[inline]
pub fn angular_momentum(q: &UnitQuaternion<f64>, w: &Vec3, inv_inertia: &Vec3) -> Vec3 {
    q * (q.inverse_transform_vector(w).component_div(inv_inertia))
}

/// Angular velocity `R I⁻¹ Rᵀ L` (world frame) for the angular momentum `l`.
#[inline]
pub fn angular_velocity(q: &UnitQuaternion<f64>, l: &Vec3, inv_inertia: &Vec3) -> Vec3 {
    q * q.inverse_transform_vector(l).component_mul(inv_inertia)
}

/// Half a kick: `v += dt/2 · F / m`.
#[inline(always)]
pub fn half_kick<T: Copy + AddAssign + Mul<f64, Output = T>>(
    v: &mut T,
    force: T,
    inv_mass: f64,
    dt: f64,
) {
    *v += force * (0.5 * dt * inv_mass);
}

/// A drift: `x += dt · v`.
#[inline(always)]
pub fn drift<T: Copy + AddAssign + Mul<f64, Output = T>>(x: &mut T, v: T, dt: f64) {
    *x += v * dt;
}

/// Velocity Verlet's first half kick and drift on flat arrays of degrees of freedom (a body's
/// coordinates and angles side by side); `inv_m` holds 1/m or 1/I per degree of freedom, 0
/// for prescribed ones.
pub fn kick_drift_dofs(x: &mut [f64], v: &mut [f64], f: &[f64], inv_m: &[f64], dt: f64) {
    for k in 0..x.len() {
        half_kick(&mut v[k], f[k], inv_m[k], dt);
        drift(&mut x[k], v[k], dt);
    }
}

/// Velocity Verlet's second half kick on flat arrays of degrees of freedom.
pub fn kick_dofs(v: &mut [f64], f: &[f64], inv_m: &[f64], dt: f64) {
    for k in 0..v.len() {
        half_kick(&mut v[k], f[k], inv_m[k], dt);
    }
}

/// Rotates `q` by the angular velocity `w` (world frame) over `dt`.
pub(crate) fn advance_orientation(
    q: &UnitQuaternion<f64>,
    w: &Vec3,
    dt: f64,
) -> UnitQuaternion<f64> {
    // Renormalised: products of unit quaternions drift off unit length by round-off, and an
    // off-unit q would scale every vector it turns (angular momentum drifted 1e-10 per 1000
    // steps without it).
    UnitQuaternion::new_normalize((UnitQuaternion::from_scaled_axis(w * dt) * q).into_inner())
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

    /// A torque-free asymmetric top (moments 1 : 2 : 3) spinning mostly about its
    /// intermediate axis tumbles (Dzhanibekov), yet its angular momentum is constant and its
    /// kinetic energy is conserved to second order in the step.
    #[test]
    fn free_asymmetric_top_keeps_angular_momentum_and_energy() {
        let mut b = Bodies::default();
        b.push_sphere(Vec3::zeros(), 0.01, 1000.0, UnitQuaternion::identity());
        let moments = Vec3::new(1.0, 2.0, 3.0) * 1e-6;
        b.inertia[0] = moments;
        b.inv_inertia[0] = moments.map(|m| 1.0 / m);
        b.omega[0] = Vec3::new(0.01, 10.0, 0.01);
        let f = Forces::new(1);
        let vv = VelocityVerlet {
            track_orientation: true,
        };
        let l0 = angular_momentum(&b.orientation[0], &b.omega[0], &b.inv_inertia[0]);
        let e0 = b.kinetic_energy();
        let energy_error = |dt: f64, b: &mut Bodies| {
            let mut worst: f64 = 0.0;
            let mut body_y_min: f64 = 1.0;
            for _ in 0..(2.0 / dt) as usize {
                vv.kick_drift(b, &f, dt);
                vv.kick(b, &f, dt);
                let l = angular_momentum(&b.orientation[0], &b.omega[0], &b.inv_inertia[0]);
                let drift = (l - l0).norm() / l0.norm();
                assert!(drift < 1e-10, "L drifts by {drift:e} (relative)");
                worst = worst.max((b.kinetic_energy() / e0 - 1.0).abs());
                // The body's y axis, along L at the start, turns over (the tumbling).
                let y = b.orientation[0] * Vec3::y();
                body_y_min = body_y_min.min(y.dot(&l0.normalize()));
            }
            (worst, body_y_min)
        };
        let mut b2 = b.clone();
        let (coarse, flip) = energy_error(1e-3, &mut b);
        let (fine, _) = energy_error(5e-4, &mut b2);
        assert!(flip < -0.9, "the intermediate axis flips over: {flip}");
        assert!(coarse < 1e-4, "energy error {coarse}");
        // Second order: halving the step divides the error by about four.
        assert!(
            coarse / fine > 3.0 && coarse / fine < 5.0,
            "{coarse} {fine}"
        );
    }
}
