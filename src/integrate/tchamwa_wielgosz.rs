//! The Tchamwa–Wielgosz dissipative explicit scheme in velocity-Verlet form
//! (dlsm paper, Eq. 37–38; Mahéo, Grolleau & Rio 2009).
//!
//! ```text
//! x(t+dt) = x(t) + dt v(t) + dt²/2 a(t)                      (positions as velocity Verlet)
//! v(t+dt) = v(t) + dt [(1 − φ) a(t) + φ a(t+dt)]             (Eq. 37, φ-weighted)
//! ```
//!
//! φ = ½ is velocity Verlet, bit for bit. The paper prints Eq. 37 as
//! `v(t+dt) = v(t) + φ dt (a(t) + a(t+dt))`, whose weights sum to 2φ: for φ ≠ ½ a body under
//! a constant force would gain 2φ times the right velocity (gravity would pull at 2φ g and
//! every frequency would grow by √(2φ)), which cannot be what the paper ran with its
//! 1 ≤ φ ≤ 1.3 and wave frequencies within 1% of theory. The weights above sum to one and
//! keep "only the velocity equation is modified" and "φ = 0.5 is velocity Verlet". Eliminating
//! the velocities gives `x(n+1) − 2x(n) + x(n−1) = dt² [(φ + ½) a(n) + (½ − φ) a(n−1)]`: the
//! Tchamwa–Wielgosz recurrence with its parameter equal to φ + ½ (theirs is 1 for central
//! differences). Each mode of angular frequency ω is damped with the ratio ≈ (φ − ½) ω dt / 2,
//! so high frequencies are damped and low ones barely; the scheme is stable for
//! ω dt < √(2/φ) (φ ≥ ½).
//!
//! Rotations (Eq. 38 applies the same φ to the quaternion): the angular velocity is advanced
//! the same way with the angular acceleration `I⁻¹ T` (world inertia from the body's principal
//! moments and orientation); during the drift the orientation turns by `dt ω(t+dt/2)` and is
//! renormalised, and the angular velocity is carried across the turn at constant angular
//! momentum (torque-free precession of a non-spherical body). Spheres take exactly the
//! arithmetic of [`super::VelocityVerlet`].

use nalgebra::{Matrix3, UnitQuaternion};

use super::velocity_verlet::advance_orientation;
use crate::shape::Shape;
use crate::state::{Bodies, Forces, Vec3};

#[derive(Debug, Clone, Copy)]
pub struct TchamwaWielgosz {
    /// φ ≥ ½; ½ is velocity Verlet.
    pub phi: f64,
    /// Advance the orientations of spheres too (polyhedra always turn).
    pub track_orientation: bool,
}

impl TchamwaWielgosz {
    pub fn new(phi: f64) -> Self {
        TchamwaWielgosz {
            phi,
            track_orientation: false,
        }
    }

    /// First stage: positions to t + dt, velocities to v(t) + (1 − φ) dt a(t).
    pub fn kick_drift(&self, b: &mut Bodies, f: &Forces, dt: f64) {
        let first = (1.0 - self.phi) * dt;
        // The drift velocity is v(t) + dt/2 a(t); the stored one lacks (φ − ½) dt a(t).
        let lag = (self.phi - 0.5) * dt;
        let corrected = self.phi != 0.5;
        let track = self.track_orientation;
        let Bodies {
            pos,
            vel,
            omega,
            orientation,
            inv_mass,
            inertia,
            inv_inertia,
            shape,
            ..
        } = b;
        let update =
            |i: usize, x: &mut Vec3, v: &mut Vec3, w: &mut Vec3, q: &mut UnitQuaternion<f64>| {
                *v += f.force[i] * (first * inv_mass[i]);
                if corrected {
                    *x += (*v + f.force[i] * (lag * inv_mass[i])) * dt;
                } else {
                    *x += *v * dt;
                }
                match shape[i] {
                    Shape::Sphere => {
                        *w += f.torque[i].component_mul(&inv_inertia[i]) * first;
                        if track {
                            *q = advance_orientation(q, w, dt);
                        }
                    }
                    Shape::Polyhedron | Shape::PolyEllipsoid { .. } => {
                        let r = *q.to_rotation_matrix().matrix();
                        let alpha = world_apply(&r, &inv_inertia[i], &f.torque[i]);
                        *w += alpha * first;
                        let drift = if corrected { *w + alpha * lag } else { *w };
                        let moment = world_apply(&r, &inertia[i], w);
                        let turned = advance_orientation(q, &drift, dt);
                        *q = UnitQuaternion::new_normalize(turned.into_inner());
                        let r = *q.to_rotation_matrix().matrix();
                        *w = world_apply(&r, &inv_inertia[i], &moment);
                    }
                }
            };
        super::each_body(pos, vel, omega, orientation, update);
    }

    /// Second stage: velocities to t + dt with the new forces, `+ φ dt a(t+dt)`.
    pub fn kick(&self, b: &mut Bodies, f: &Forces, dt: f64) {
        let second = self.phi * dt;
        let Bodies {
            vel,
            omega,
            orientation,
            inv_mass,
            inv_inertia,
            shape,
            ..
        } = b;
        let update = |(i, (v, w)): (usize, (&mut Vec3, &mut Vec3))| {
            *v += f.force[i] * (second * inv_mass[i]);
            match shape[i] {
                Shape::Sphere => *w += f.torque[i].component_mul(&inv_inertia[i]) * second,
                Shape::Polyhedron | Shape::PolyEllipsoid { .. } => {
                    let r = *orientation[i].to_rotation_matrix().matrix();
                    *w += world_apply(&r, &inv_inertia[i], &f.torque[i]) * second;
                }
            }
        };
        super::each_velocity(vel, omega, update);
    }
}

/// `R diag(d) Rᵀ v`: a principal-frame diagonal tensor applied to a world vector.
#[inline]
fn world_apply(r: &Matrix3<f64>, d: &Vec3, v: &Vec3) -> Vec3 {
    r * (r.tr_mul(v).component_mul(d))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::VelocityVerlet;

    /// Two bodies on a spring of stiffness k: returns the total energy after `steps`.
    fn oscillator(phi: f64, omega_dt: f64, steps: usize) -> (f64, f64) {
        let mut b = Bodies::default();
        b.push_sphere(Vec3::zeros(), 0.01, 1000.0, UnitQuaternion::identity());
        let m = b.mass[0];
        let k = m * (omega_dt / 1e-3).powi(2);
        b.pos[0].x = 1e-3;
        let tw = TchamwaWielgosz::new(phi);
        let mut f = Forces::new(1);
        f.force[0].x = -k * b.pos[0].x;
        let e0 = 0.5 * k * 1e-6;
        for _ in 0..steps {
            tw.kick_drift(&mut b, &f, 1e-3);
            f.force[0].x = -k * b.pos[0].x;
            tw.kick(&mut b, &f, 1e-3);
        }
        let e = 0.5 * m * b.vel[0].norm_squared() + 0.5 * k * b.pos[0].x.powi(2);
        (e / e0, k)
    }

    #[test]
    fn constant_force_is_integrated_exactly_for_any_phi() {
        for phi in [0.5, 1.0, 1.3] {
            let mut b = Bodies::default();
            b.push_sphere(Vec3::zeros(), 0.01, 1000.0, UnitQuaternion::identity());
            let mut f = Forces::new(1);
            f.force[0] = Vec3::new(0.0, 0.0, -9.81 * b.mass[0]);
            let tw = TchamwaWielgosz::new(phi);
            for _ in 0..1000 {
                tw.kick_drift(&mut b, &f, 1e-3);
                tw.kick(&mut b, &f, 1e-3);
            }
            // Weights that sum to one: free fall at g whatever φ (the printed Eq. 37 would
            // fall at 2φ g).
            assert!(
                (b.pos[0].z + 0.5 * 9.81).abs() < 1e-9,
                "phi {phi}: {}",
                b.pos[0].z
            );
            assert!((b.vel[0].z + 9.81).abs() < 1e-9);
        }
    }

    #[test]
    fn phi_above_half_damps_high_frequencies_only() {
        // ω dt = 1: strongly damped over 200 steps with φ = 1; ω dt = 0.01 barely.
        let (e_high, _) = oscillator(1.0, 1.0, 200);
        let (e_low, _) = oscillator(1.0, 0.01, 200);
        let (e_vv, _) = oscillator(0.5, 0.1, 200);
        assert!(e_high < 1e-4, "{e_high}");
        // Damping ratio (φ − ½) ω dt / 2 = 0.0025 over 2 rad of phase: 1% of the energy.
        assert!((e_low - 1.0).abs() < 0.02 && e_low < 1.0, "{e_low}");
        assert!(
            (e_vv - 1.0).abs() < 0.01,
            "velocity Verlet keeps its energy: {e_vv}"
        );
    }

    #[test]
    fn torque_free_polyhedron_keeps_its_angular_momentum() {
        let mut b = Bodies::default();
        b.push_sphere(Vec3::zeros(), 0.01, 1000.0, UnitQuaternion::identity());
        b.shape[0] = Shape::Polyhedron;
        b.inertia[0] = Vec3::new(1.0, 2.0, 3.0);
        b.inv_inertia[0] = Vec3::new(1.0, 0.5, 1.0 / 3.0);
        b.omega[0] = Vec3::new(0.3, 1.0, 0.2);
        let l0 = b.inertia[0].component_mul(&b.omega[0]);
        let e0 = b.kinetic_energy();
        let f = Forces::new(1);
        let tw = TchamwaWielgosz::new(0.5);
        for _ in 0..2000 {
            tw.kick_drift(&mut b, &f, 1e-3);
            tw.kick(&mut b, &f, 1e-3);
        }
        let r = *b.orientation[0].to_rotation_matrix().matrix();
        let l = world_apply(&r, &b.inertia[0], &b.omega[0]);
        assert!((l - l0).norm() < 1e-10 * l0.norm(), "{l} vs {l0}");
        assert!((b.kinetic_energy() / e0 - 1.0).abs() < 1e-3);
        assert!((b.orientation[0].into_inner().norm() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn phi_one_half_is_velocity_verlet_bit_for_bit() {
        // Spheres on springs to a fixed point and to each other, with torques, through the
        // project's velocity Verlet and through Tchamwa–Wielgosz at φ = 0.5.
        let n = 5;
        let mut a = Bodies::default();
        for k in 0..n {
            a.push_sphere(
                Vec3::new(0.013 * k as f64, 0.002 * (k * k) as f64, -0.001 * k as f64),
                0.004 + 0.001 * k as f64,
                2650.0,
                UnitQuaternion::identity(),
            );
            a.vel[k] = Vec3::new(0.1, -0.2 * k as f64, 0.05);
        }
        let mut b = a.clone();
        let forces = |bodies: &Bodies| {
            let mut f = Forces::new(n);
            for i in 0..n {
                f.force[i] = -3.0e3 * bodies.pos[i];
                let j = (i + 1) % n;
                let d = bodies.pos[j] - bodies.pos[i];
                f.force[i] += d * 1.7e3;
                f.torque[i] = d.cross(&bodies.vel[j]) * 0.31;
            }
            f
        };
        let vv = VelocityVerlet::default();
        let tw = TchamwaWielgosz::new(0.5);
        let (mut fa, mut fb) = (forces(&a), forces(&b));
        for _ in 0..500 {
            vv.kick_drift(&mut a, &fa, 1e-4);
            fa = forces(&a);
            vv.kick(&mut a, &fa, 1e-4);
            tw.kick_drift(&mut b, &fb, 1e-4);
            fb = forces(&b);
            tw.kick(&mut b, &fb, 1e-4);
        }
        let bits = |v: &[Vec3]| -> Vec<u64> {
            v.iter()
                .flat_map(|x| x.iter().map(|c| c.to_bits()))
                .collect()
        };
        assert_eq!(bits(&a.pos), bits(&b.pos));
        assert_eq!(bits(&a.vel), bits(&b.vel));
        assert_eq!(bits(&a.omega), bits(&b.omega));
        assert!(a.omega.iter().any(|w| w.norm() > 0.0), "torques acted");
    }
}
