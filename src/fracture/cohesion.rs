//! Cohesive springs between the two sub-particles of a split (granular paper,
//! Section 3.4): their initial forces keep the split kinematically invisible (Eq. 39–43), and
//! their softening law dissipates the fracture energy G_c A (Eq. 35–38).
//!
//! A spring joins a point of sub-particle A and the same point of B, so it starts with zero
//! length. It carries the force `f = f_i − k Δd` (Eq. 35) along the direction of its initial
//! force (which turns with A), where Δd is the largest elongation (distance between its two
//! ends) it has reached: closing again does not restore the force. With `k = f_i² / (2 G_c A)`
//! (Eq. 37) the area under the law is G_c A (Eq. 36), and the force falls continuously to zero,
//! where the spring breaks for good: breaking releases no force and injects no energy.

use nalgebra::{DMatrix, DVector, Matrix6, UnitQuaternion, Vector6};
use serde::{Deserialize, Serialize};

use crate::state::Vec3;

/// The cohesive energy G_c = K_Ic² / E' (J/m²), E' = E / (1 − ν²) (Eq. 38, Irwin).
pub fn cohesive_energy(toughness: f64, young: f64, poisson: f64) -> f64 {
    toughness * toughness * (1.0 - poisson * poisson) / young
}

/// One cohesive spring.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Spring {
    pub a: u32,
    pub b: u32,
    /// The spring's end on A and on B, in each body's own frame (m).
    pub on_a: Vec3,
    pub on_b: Vec3,
    /// Unit direction of the force on A, in A's body frame.
    pub direction: Vec3,
    /// Initial force f_i (N), stiffness k (N/m).
    pub f0: f64,
    pub k: f64,
    /// Largest elongation reached (m).
    pub opening: f64,
    /// Ends' separation vector (A's end minus B's, world) and the force on A at the last
    /// evaluation, for the work the spring does.
    pub last_gap: Vec3,
    pub last_force: Vec3,
    pub broken: bool,
}

impl Spring {
    /// The elongation at which the force has fallen to zero: f_i / k = 2 G_c A / f_i.
    pub fn critical_opening(&self) -> f64 {
        self.f0 / self.k
    }

    /// The force magnitude (N) at the largest elongation `opening`.
    pub fn force_at(&self, opening: f64) -> f64 {
        (self.f0 - self.k * opening).max(0.0)
    }

    /// One evaluation of the spring between A at `pos_a` turned by `qa` and B at `pos_b` turned
    /// by `qb` (m, body to world): the largest elongation grows to the ends' distance, the
    /// force (Eq. 35) acts along the initial direction turned with A, and the work it did on
    /// the pair since the last evaluation (trapezoid rule with the last force) is counted.
    /// When the force has fallen to zero the spring breaks for good and acts no more.
    #[inline]
    pub fn act(
        &mut self,
        pos_a: &Vec3,
        qa: &UnitQuaternion<f64>,
        pos_b: &Vec3,
        qb: &UnitQuaternion<f64>,
    ) -> SpringAction {
        let (la, lb) = (qa * self.on_a, qb * self.on_b);
        let gap = (pos_a + la) - (pos_b + lb);
        self.opening = self.opening.max(gap.norm());
        let f = self.force_at(self.opening);
        let force = (qa * self.direction) * f;
        // Work on the pair over the step: the force on A times A's end's motion relative
        // to B's (trapezoid with the last force).
        let work = 0.5 * (force + self.last_force).dot(&(gap - self.last_gap));
        self.last_gap = gap;
        self.last_force = force;
        if f <= 0.0 {
            self.broken = true;
            return SpringAction {
                work,
                broke: true,
                ..SpringAction::default()
            };
        }
        SpringAction {
            force,
            torque_a: la.cross(&force),
            torque_b: -lb.cross(&force),
            work,
            broke: false,
        }
    }

    /// The energy the spring holds, f²/(2k) (J): G_c A when new, 0 when broken.
    pub fn stored_energy(&self) -> f64 {
        if self.broken {
            0.0
        } else {
            let f = self.force_at(self.opening);
            f * f / (2.0 * self.k)
        }
    }
}

/// What one evaluation of a spring ([`Spring::act`]) does: the force on A (N; B gets the
/// opposite), the torques on A and on B about their centres of mass (N·m), the work done on
/// the pair since the last evaluation (J), and whether the spring broke (then no force).
#[derive(Debug, Clone, Copy, Default)]
pub struct SpringAction {
    pub force: Vec3,
    pub torque_a: Vec3,
    pub torque_b: Vec3,
    pub work: f64,
    pub broke: bool,
}

/// What the springs of one split must do, world frame, relative to A's centre of mass:
/// A needs `force_a` and `torque_a` (about its centre) from B, B needs `force_b` and
/// `torque_b` (about its own centre, at `b_offset` from A's) from A (Eq. 40–41).
#[derive(Debug, Clone, Copy)]
pub struct Demand {
    pub force_a: Vec3,
    pub torque_a: Vec3,
    pub force_b: Vec3,
    pub torque_b: Vec3,
    pub b_offset: Vec3,
}

/// The initial force of each spring (on A; B receives the opposite), for springs at `points`
/// (world, relative to A's centre of mass). Newton's third law needs `f_A/B = −f_B/A`; when
/// the split loses contacts the two demands disagree, and as in Eq. 43 each spring takes the
/// mean `(f_A/B − f_B/A)/2`, and likewise for the moments. Among the spring forces with that
/// resultant and moment, the smallest (least squares) is taken.
pub fn initial_forces(points: &[Vec3], demand: &Demand) -> Vec<Vec3> {
    let force = (demand.force_a - demand.force_b) * 0.5;
    // On B the springs act with −f at the same points: their moment about B's centre is
    // −τ_A + c_B × F, which must equal torque_b.
    let torque = (demand.torque_a + demand.b_offset.cross(&force) - demand.torque_b) * 0.5;
    let n = points.len();
    let mut a = DMatrix::<f64>::zeros(6, 3 * n);
    for (k, p) in points.iter().enumerate() {
        for d in 0..3 {
            a[(d, 3 * k + d)] = 1.0;
        }
        a.view_mut((3, 3 * k), (3, 3)).copy_from(&p.cross_matrix());
    }
    let b = Vector6::new(force.x, force.y, force.z, torque.x, torque.y, torque.z);
    let aat: Matrix6<f64> = (&a * a.transpose()).fixed_view::<6, 6>(0, 0).into_owned();
    // A blowing-up run hands non-finite forces here, where the SVD of the fallback iterated
    // for ever: NaN forces instead, which the run's finiteness check stops at this step.
    let unsolved = || vec![Vec3::repeat(f64::NAN); n];
    if !(b.iter().all(|v| v.is_finite()) && aat.iter().all(|v| v.is_finite())) {
        return unsolved();
    }
    let y = match aat.cholesky() {
        Some(c) => c.solve(&b),
        None => match nalgebra::SVD::try_new(aat, true, true, f64::EPSILON, 1000)
            .and_then(|svd| svd.pseudo_inverse(1e-30).ok())
        {
            Some(pinv) => pinv * b,
            None => return unsolved(),
        },
    };
    let x: DVector<f64> = a.transpose() * DVector::from_column_slice(y.as_slice());
    (0..n)
        .map(|k| Vec3::new(x[3 * k], x[3 * k + 1], x[3 * k + 2]))
        .collect()
}

/// The resultant force and moment (about the origin) of forces at points.
pub fn resultant(points: &[Vec3], forces: &[Vec3]) -> (Vec3, Vec3) {
    let mut f = Vec3::zeros();
    let mut m = Vec3::zeros();
    for (p, q) in points.iter().zip(forces) {
        f += q;
        m += p.cross(q);
    }
    (f, m)
}

/// The ns spring points on a break plane, in the parent's shape frame: on the section
/// through the octant origin normal to axis `k`, at half the section's radius in each of ns
/// evenly spaced directions (so each spring sits near the centre of its share of the
/// section), and the area of that share (m²), A_total / ns.
pub fn spring_layout(semi: &[f64; 6], k: usize, ns: usize) -> (Vec<Vec3>, f64) {
    let (u, v) = ((k + 1) % 3, (k + 2) % 3);
    let points = (0..ns)
        .map(|j| {
            let t = std::f64::consts::TAU * (j as f64 + 0.5) / ns as f64;
            let (s, c) = t.sin_cos();
            let su = if c >= 0.0 {
                semi[2 * u]
            } else {
                semi[2 * u + 1]
            };
            let sv = if s >= 0.0 {
                semi[2 * v]
            } else {
                semi[2 * v + 1]
            };
            let mut p = Vec3::zeros();
            p[u] = 0.5 * su * c;
            p[v] = 0.5 * sv * s;
            p
        })
        .collect();
    (points, section_area(semi, k) / ns as f64)
}

/// Area (m²) of the section through the octant origin normal to axis `k`: four quarter
/// ellipses, π/4 (u+ + u−)(v+ + v−).
pub fn section_area(semi: &[f64; 6], k: usize) -> f64 {
    let (u, v) = ((k + 1) % 3, (k + 2) % 3);
    std::f64::consts::FRAC_PI_4 * (semi[2 * u] + semi[2 * u + 1]) * (semi[2 * v] + semi[2 * v + 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Non-finite demands (a run blowing up) give NaN forces at once; the SVD fallback used to
    /// iterate for ever on them. Collinear points (no Cholesky) with a
    /// finite demand still give the resultant.
    #[test]
    fn initial_forces_never_loop_on_non_finite_input() {
        let points = [Vec3::new(1e-4, 0.0, 0.0), Vec3::new(-1e-4, 0.0, 0.0)];
        for bad in [f64::NAN, f64::INFINITY, -1e308 * 10.0] {
            let demand = Demand {
                force_a: Vec3::new(0.0, 0.0, bad),
                torque_a: Vec3::zeros(),
                force_b: Vec3::zeros(),
                torque_b: Vec3::zeros(),
                b_offset: Vec3::zeros(),
            };
            let f = initial_forces(&points, &demand);
            assert!(
                f.iter().all(|v| v.iter().all(|x| x.is_nan())),
                "{bad}: {f:?}"
            );
        }
        let demand = Demand {
            force_a: Vec3::new(0.0, 0.0, 2.0),
            torque_a: Vec3::zeros(),
            force_b: Vec3::zeros(),
            torque_b: Vec3::zeros(),
            b_offset: Vec3::zeros(),
        };
        let f = initial_forces(&points, &demand);
        let (total, _) = resultant(&points, &f);
        assert!((total - Vec3::new(0.0, 0.0, 1.0)).norm() < 1e-12, "{total}");
    }

    #[test]
    fn irwin_energy_of_silica() {
        // K_Ic = 1.77 MPa m^0.5, E = 60 GPa, ν = 0.17: G_c = 3.1329e12 · 0.9711 / 6e10.
        let g = cohesive_energy(1.77e6, 60e9, 0.17);
        assert!((g - 1.77e6f64.powi(2) * (1.0 - 0.0289) / 60e9).abs() < 1e-12);
        assert!((g - 50.705).abs() < 1e-2, "{g}");
    }

    #[test]
    fn spring_law_dissipates_gc_a() {
        // Fig. 21: f_i = 10 N, r = 0.3 mm, n_s = 4 -> the largest elongation 7.16e-4 mm for
        // the paper's G_c (the figure's value follows from G_c A = f_i δc / 2).
        let (f0, gc, area) = (10.0, 50.705, std::f64::consts::PI * 0.09e-6 / 4.0);
        let k = f0 * f0 / (2.0 * gc * area);
        let s = Spring {
            a: 0,
            b: 1,
            on_a: Vec3::zeros(),
            on_b: Vec3::zeros(),
            direction: Vec3::x(),
            f0,
            k,
            opening: 0.0,
            last_gap: Vec3::zeros(),
            last_force: Vec3::zeros(),
            broken: false,
        };
        assert!((s.stored_energy() - gc * area).abs() < 1e-12 * gc * area);
        // Integrate the law: the area under it is G_c A.
        let dc = s.critical_opening();
        assert!((dc / 7.16e-7 - 1.0).abs() < 5e-3, "Fig. 21: {dc}");
        let n = 100_000;
        let work: f64 = (0..n)
            .map(|i| s.force_at((i as f64 + 0.5) * dc / n as f64) * dc / n as f64)
            .sum();
        assert!((work / (gc * area) - 1.0).abs() < 1e-9);
        assert_eq!(s.force_at(dc * 1.0001), 0.0);
    }

    #[test]
    fn initial_forces_meet_the_demand_with_least_norm() {
        let semi = [1e-3, 0.8e-3, 1.1e-3, 0.9e-3, 1.0e-3, 0.7e-3];
        let (local, area) = spring_layout(&semi, 0, 4);
        assert!((area * 4.0 - section_area(&semi, 0)).abs() < 1e-20);
        assert!(local.iter().all(|p| p.x == 0.0));
        let shift = Vec3::new(-0.2e-3, 0.05e-3, 0.0);
        let points: Vec<Vec3> = local.iter().map(|p| p + shift).collect();
        let demand = Demand {
            force_a: Vec3::new(3.0, -1.0, 2.0),
            torque_a: Vec3::new(1e-3, 2e-3, -1e-3),
            force_b: Vec3::new(-3.0, 1.0, -2.0),
            torque_b: Vec3::zeros(),
            b_offset: Vec3::new(-0.6e-3, 0.0, 0.0),
        };
        // A consistent pair of demands (no lost contact): B's moment follows from A's.
        let force = demand.force_a;
        let tb = -demand.torque_a + demand.b_offset.cross(&force);
        let demand = Demand {
            torque_b: tb,
            ..demand
        };
        let f = initial_forces(&points, &demand);
        let (rf, rm) = resultant(&points, &f);
        assert!((rf - demand.force_a).norm() < 1e-12);
        assert!((rm - demand.torque_a).norm() < 1e-15);
        // On B: −f at the same points, about B's centre.
        let on_b: Vec<Vec3> = points.iter().map(|p| p - demand.b_offset).collect();
        let neg: Vec<Vec3> = f.iter().map(|x| -x).collect();
        let (bf, bm) = resultant(&on_b, &neg);
        assert!((bf - demand.force_b).norm() < 1e-12);
        assert!((bm - demand.torque_b).norm() < 1e-15);
    }
}
