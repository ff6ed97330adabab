//! The highest vibration frequency of a linearised system of rigid bodies, computed rather than
//! bounded: the largest eigenvalue of `M^-1/2 K M^-1/2` by power iteration, over every body's
//! three translations and three rotations (principal moments turned to the world). Its
//! Rayleigh quotient approaches the largest eigenvalue from below, so a step it calls unstable
//! is unstable. Used for diagnosis (granular: what sets the step) and for the dlsm lattice's
//! stability check at build.

use nalgebra::{Matrix3, UnitQuaternion};

use crate::state::{Bodies, Vec3};

/// One body's coordinates in mass-scaled form: `M^½` times (translation, rotation vector).
pub type Dof = [Vec3; 2];

/// `M^-1/2` of every body: `1/√m` for translation, `R diag(1/√I) Rᵀ` for rotation.
pub struct MassScale {
    pub lin: Vec<f64>,
    pub rot: Vec<Matrix3<f64>>,
}

impl MassScale {
    pub fn of(bodies: &Bodies) -> Self {
        let rot = (0..bodies.len())
            .map(|i| {
                let r = bodies.orientation[i].to_rotation_matrix().into_inner();
                r * Matrix3::from_diagonal(&bodies.inv_inertia[i].map(f64::sqrt)) * r.transpose()
            })
            .collect();
        MassScale {
            lin: bodies.inv_mass.iter().map(|m| m.sqrt()).collect(),
            rot,
        }
    }

    /// Body `i`'s displacement (m) and rotation vector (rad) for mass-scaled `w`.
    pub fn motion(&self, i: usize, w: &Dof) -> (Vec3, Vec3) {
        (w[0] * self.lin[i], self.rot[i] * w[1])
    }

    /// Body `i`'s force (N) and torque (N m) in mass-scaled form.
    pub fn load(&self, i: usize, force: &Vec3, torque: &Vec3) -> Dof {
        [force * self.lin[i], self.rot[i] * torque]
    }
}

/// The largest eigenvalue (rad²/s²) of the symmetric positive semi-definite operator `apply`
/// (`w` in, `out` overwritten, both mass-scaled) after `iterations` power iterations from a
/// deterministic start that touches every body and direction, and the last iterate (the
/// approximate mode, unit length). The value is a Rayleigh quotient: never above the true
/// largest eigenvalue, closer with more iterations.
pub fn highest_eigenvalue(
    n: usize,
    iterations: usize,
    mut apply: impl FnMut(&[Dof], &mut [Dof]),
) -> (f64, Vec<Dof>) {
    let mut w: Vec<Dof> = (0..n)
        .map(|i| {
            let x = (i as f64 + 1.0) * 0.618_033_988_749_895;
            let c = |k: f64| (x * k).fract() - 0.5;
            [
                Vec3::new(c(1.0), c(3.0), c(7.0)),
                Vec3::new(c(11.0), c(13.0), c(17.0)),
            ]
        })
        .collect();
    let mut next = vec![[Vec3::zeros(); 2]; n];
    let norm = |v: &[Dof]| {
        v.iter()
            .map(|b| b[0].norm_squared() + b[1].norm_squared())
            .sum::<f64>()
            .sqrt()
    };
    let mut lambda = 0.0;
    for _ in 0..iterations {
        let s = norm(&w);
        if s.is_nan() || s <= 0.0 {
            break;
        }
        for b in w.iter_mut() {
            b[0] /= s;
            b[1] /= s;
        }
        apply(&w, &mut next);
        lambda = w
            .iter()
            .zip(&next)
            .map(|(a, b)| a[0].dot(&b[0]) + a[1].dot(&b[1]))
            .sum::<f64>();
        std::mem::swap(&mut w, &mut next);
    }
    let s = norm(&w);
    if s > 0.0 && s.is_finite() {
        w.iter_mut().for_each(|b| {
            b[0] /= s;
            b[1] /= s;
        });
    }
    (lambda.max(0.0), w)
}

/// The body that moves most in mode `w`, and the translational share of its motion.
pub fn largest_motion(w: &[Dof]) -> (usize, f64) {
    let (mut top, mut at, mut lin) = (0.0, 0, 0.0);
    for (i, b) in w.iter().enumerate() {
        let e = b[0].norm_squared() + b[1].norm_squared();
        if e > top {
            (top, at, lin) = (e, i, b[0].norm_squared() / e);
        }
    }
    (at, lin)
}

/// `K w` by a forward difference of a force function: `forces(bodies)` writes every body's
/// force and torque at the given configuration; `base` holds them at `bodies`. The bodies are
/// displaced by `eps` times the motion of `w` (rotations turn the orientations), a fraction
/// `1e-7` of `length` (m) at most, so the springs stay linear and the difference above
/// round-off. `trial` is scratch with the layout of `bodies`.
#[allow(clippy::too_many_arguments)]
pub fn stiffness_by_difference(
    bodies: &Bodies,
    scale: &MassScale,
    length: f64,
    base: &[(Vec3, Vec3)],
    trial: &mut Bodies,
    w: &[Dof],
    out: &mut [Dof],
    mut forces: impl FnMut(&Bodies) -> Vec<(Vec3, Vec3)>,
) {
    let reach = (0..bodies.len())
        .map(|i| {
            let (u, th) = scale.motion(i, &w[i]);
            u.norm().max(th.norm() * length)
        })
        .fold(0.0, f64::max);
    if reach <= 0.0 || !reach.is_finite() {
        out.iter_mut().for_each(|o| *o = [Vec3::zeros(); 2]);
        return;
    }
    let eps = 1e-7 * length / reach;
    for (i, wi) in w.iter().enumerate() {
        let (u, th) = scale.motion(i, wi);
        trial.pos[i] = bodies.pos[i] + u * eps;
        trial.orientation[i] = UnitQuaternion::from_scaled_axis(th * eps) * bodies.orientation[i];
    }
    let moved = forces(trial);
    for (i, o) in out.iter_mut().enumerate() {
        let df = (base[i].0 - moved[i].0) / eps;
        let dt = (base[i].1 - moved[i].1) / eps;
        *o = scale.load(i, &df, &dt);
    }
}
