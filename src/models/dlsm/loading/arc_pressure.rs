//! The arcs' pressure of the Brazilian test (`loading.load_by = "arc_pressure"`): its servo
//! and the support of the disc's free motions.

use nalgebra::{Matrix3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use crate::bond::dlsm::rotation_vector;
use crate::state::{Bodies, Forces, Vec3};

/// A uniform radial pressure over the two loading arcs of a Brazilian disc (the loading of
/// Eq. 47), set by a servo on the arcs' closure.
///
/// The pressure acts on the exact circle, not on the faceted surface of the sample: each arc
/// (2α wide, the disc's thickness deep) is sampled on a fine grid and each sample's share,
/// p R dθ dz along the inward radius, goes to the element whose seed is nearest (the cell
/// that holds that point), as a force at the seed and the moment of its offset. So each
/// arc's resultant is 2 p R t sin α along y, and the two arcs' loads cancel in force and in
/// moment. (On the faces' own areas they do not: at 3000 cells the top arc's faces had 16%
/// less area than the bottom's, and a dead pressure on them accelerated the disc as a whole.)
///
/// The servo: each arc carries P = K (c(t) − q), c the commanded closure of the two arcs
/// (`speed` each, ramped as the platens) and q their measured closure, the inward
/// displacements of the arcs' elements weighted by their shares of the load (rotations
/// through their moments) over the resultant per unit pressure. P derives from the potential
/// ½ K (c − q)²: the servo is a spring in series, so it cannot feed the lattice's
/// non-conservative modes, and it never pulls (P ≥ 0). Stiffer than the disc, it follows the
/// commanded rate and lets the load fall after the peak, as a displacement-controlled machine
/// does.
///
/// Nothing else holds the disc, and this model cannot be left free under a pressure alone:
/// its forces are not central (the contact force S σ n is not along the seeds' line), so the
/// lattice's internal forces have a net moment on the elements' positions and the opposite
/// one on their spins, which no configuration balances. Under the pressure the disc turned
/// as a whole and all its elements spun alike, at rates growing as t² under the ramp, until
/// the first break blew it apart. [`hold_free_motions`] takes those two accelerations (and the
/// rigid translation's) out at each evaluation, as a support that carries only what they
/// need; `held_moment` records its size.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ArcPressure {
    /// The elements under the arcs, the top arc's first.
    pub elements: Vec<u32>,
    /// How many of `elements` are under the top arc.
    pub top: usize,
    /// Per element, the force and the moment about its seed that a unit pressure applies (m²,
    /// m³).
    pub force: Vec<Vec3>,
    pub moment: Vec<Vec3>,
    /// The resultant of a unit pressure on one arc, 2 R t sin α (m²): each arc's load is
    /// the pressure times this.
    pub area: f64,
    /// Servo stiffness K (N/m).
    pub stiffness: f64,
    /// The elements' seeds and orientations at the start.
    pub start: Vec<Vec3>,
    pub start_orientation: Vec<UnitQuaternion<f64>>,
    /// Closure (m) of the top and bottom arcs, and the load on each arc (N), in the last
    /// evaluation.
    pub closure: [f64; 2],
    pub load: f64,
    /// The moment (N·m) that holding the disc's rotation took in the last evaluation.
    pub held_moment: f64,
}

impl ArcPressure {
    /// The loads of the arcs of half angle `alpha` about +y and −y of a disc of `radius` and
    /// `thickness` (z from −t/2 to t/2), shared among `candidates` (the elements whose seeds
    /// may be nearest to a point of the arcs) by nearest seed, the arcs sampled every
    /// `spacing` metres or finer.
    pub fn new(
        bodies: &Bodies,
        candidates: &[u32],
        [radius, thickness, alpha, spacing]: [f64; 4],
        stiffness: f64,
    ) -> Self {
        let n_theta = ((2.0 * alpha * radius / spacing).ceil() as usize).max(1);
        let n_z = ((thickness / spacing).ceil() as usize).max(1);
        let (d_theta, d_z) = (2.0 * alpha / n_theta as f64, thickness / n_z as f64);
        let (mut elements, mut force, mut moment) = (Vec::new(), Vec::new(), Vec::new());
        let mut top = 0;
        for side in [1.0, -1.0] {
            let mut share = vec![(Vec3::zeros(), Vec3::zeros()); candidates.len()];
            // Midpoints, symmetric about the vertical: the x components cancel.
            for a in 0..n_theta {
                let theta = -alpha + (a as f64 + 0.5) * d_theta;
                let outward = Vec3::new(theta.sin(), side * theta.cos(), 0.0);
                let f = -outward * (radius * d_theta * d_z);
                for b in 0..n_z {
                    let z = -0.5 * thickness + (b as f64 + 0.5) * d_z;
                    let point = outward * radius + Vec3::new(0.0, 0.0, z);
                    let Some(k) = (0..candidates.len()).min_by(|&p, &q| {
                        let d =
                            |k: usize| (bodies.pos[candidates[k] as usize] - point).norm_squared();
                        d(p).total_cmp(&d(q))
                    }) else {
                        continue;
                    };
                    share[k].0 += f;
                    share[k].1 += (point - bodies.pos[candidates[k] as usize]).cross(&f);
                }
            }
            for (&i, (f, m)) in candidates.iter().zip(share) {
                if f != Vec3::zeros() {
                    elements.push(i);
                    force.push(f);
                    moment.push(m);
                }
            }
            if side > 0.0 {
                top = elements.len();
            }
        }
        // The applied resultant, which is 2 R t sin α to the midpoint rule's (dθ)²/24.
        let area = -force[..top].iter().map(|f| f.y).sum::<f64>();
        ArcPressure {
            start: elements.iter().map(|&i| bodies.pos[i as usize]).collect(),
            start_orientation: elements
                .iter()
                .map(|&i| bodies.orientation[i as usize])
                .collect(),
            elements,
            top,
            force,
            moment,
            area,
            stiffness,
            closure: [0.0; 2],
            load: 0.0,
            held_moment: 0.0,
        }
    }

    /// The shortest period (over 2π, s) of the servo spring on the arcs' elements alone:
    /// 1/ω with ω² = K Σ (|f_i|²/m_i + |m_i|²/I_i) / A², I_i the least principal moment.
    pub fn step_bound(&self, bodies: &Bodies) -> f64 {
        let flexibility: f64 = self
            .elements
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                let i = i as usize;
                self.force[k].norm_squared() / bodies.mass[i]
                    + self.moment[k].norm_squared() / bodies.inertia[i].min()
            })
            .sum();
        self.area / (self.stiffness * flexibility).sqrt()
    }

    /// Measures the arcs' closure, applies the pressure the servo sets for the commanded
    /// closure `command` (m), and holds the disc's free motions.
    pub(super) fn apply(&mut self, bodies: &Bodies, forces: &mut Forces, command: f64) {
        let mut closure = [0.0; 2];
        for (k, &i) in self.elements.iter().enumerate() {
            let i = i as usize;
            let u = bodies.pos[i] - self.start[k];
            let turn = rotation_vector(
                &(bodies.orientation[i] * self.start_orientation[k].inverse()).into_inner(),
            );
            closure[usize::from(k >= self.top)] +=
                self.force[k].dot(&u) + self.moment[k].dot(&turn);
        }
        self.closure = closure.map(|c| c / self.area);
        self.load = (self.stiffness * (command - self.closure[0] - self.closure[1])).max(0.0);
        let p = self.load / self.area;
        for (k, &i) in self.elements.iter().enumerate() {
            forces.force[i as usize] += self.force[k] * p;
            forces.torque[i as usize] += self.moment[k] * p;
        }
        self.held_moment = hold_free_motions(bodies, forces);
    }
}

/// Takes out of the forces and torques what would accelerate the elements as one rigid body
/// (translation, and rotation about the centre of mass) or spin them all alike, and returns
/// the moment (N·m) taken from the rotation. Each element loses its mass times the rigid
/// acceleration at its seed, and its mean principal moment times one angular acceleration:
/// the least change that zeroes the net force, the net moment on the positions and the net
/// torque on the spins. With a load that is itself balanced, the two moments taken are
/// equal and opposite: the support puts nothing into the disc's angular momentum.
pub fn hold_free_motions(bodies: &Bodies, forces: &mut Forces) -> f64 {
    let n = bodies.len();
    let (mut mass, mut centre, mut net) = (0.0, Vec3::zeros(), Vec3::zeros());
    let (mut spin_inertia, mut torque) = (0.0, Vec3::zeros());
    for i in 0..n {
        mass += bodies.mass[i];
        centre += bodies.pos[i] * bodies.mass[i];
        net += forces.force[i];
        spin_inertia += bodies.inertia[i].sum() / 3.0;
        torque += forces.torque[i];
    }
    centre /= mass;
    let (mut inertia, mut moment) = (Matrix3::zeros(), Vec3::zeros());
    for i in 0..n {
        let r = bodies.pos[i] - centre;
        inertia += (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * bodies.mass[i];
        moment += r.cross(&forces.force[i]);
    }
    let acceleration = net / mass;
    let turning = inertia
        .try_inverse()
        .map_or(Vec3::zeros(), |inv| inv * moment);
    let spinning = torque / spin_inertia;
    for i in 0..n {
        let r = bodies.pos[i] - centre;
        forces.force[i] -= (acceleration + turning.cross(&r)) * bodies.mass[i];
        forces.torque[i] -= spinning * (bodies.inertia[i].sum() / 3.0);
    }
    moment.norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seeds on a ring just inside a disc of radius 0.1 m, thickness 0.02 m, at three depths
    /// through the thickness, a few of them off the ring's regular spacing.
    fn ring() -> Bodies {
        let mut b = Bodies::default();
        for k in 0..120 {
            let theta =
                (k as f64 + 0.3 * ((k * 7) % 5) as f64 / 5.0) / 120.0 * std::f64::consts::TAU;
            for z in [-0.006, 0.0, 0.007] {
                let r = 0.097 - 0.001 * ((k + 3) % 4) as f64;
                b.push_polyhedron(
                    Vec3::new(r * theta.sin(), r * theta.cos(), z),
                    1e-3 * (1.0 + 0.1 * (k % 3) as f64),
                    Vec3::new(1e-9, 2e-9, 3e-9),
                    UnitQuaternion::identity(),
                    3e-3,
                );
            }
        }
        b
    }

    #[test]
    fn arc_pressure_is_balanced_and_its_resultant_is_that_of_eq_47() {
        let b = ring();
        let all: Vec<u32> = (0..b.len() as u32).collect();
        let alpha = 10f64.to_radians();
        let arc = ArcPressure::new(&b, &all, [0.1, 0.02, alpha, 2e-4], 1e9);
        let area = 2.0 * 0.1 * 0.02 * alpha.sin();
        assert!((arc.area / area - 1.0).abs() < 1e-6, "{}", arc.area / area);
        let top: Vec3 = arc.force[..arc.top].iter().sum();
        let bottom: Vec3 = arc.force[arc.top..].iter().sum();
        // Each arc: 2 R t sin α along the inward y (midpoint sums of sin and cos).
        assert!(
            (top + Vec3::new(0.0, area, 0.0)).norm() < 1e-6 * area,
            "{top}"
        );
        assert!(
            (bottom - Vec3::new(0.0, area, 0.0)).norm() < 1e-6 * area,
            "{bottom}"
        );
        assert!((top + bottom).norm() < 1e-15, "{}", top + bottom);
        let moment: Vec3 = arc
            .elements
            .iter()
            .zip(arc.force.iter().zip(&arc.moment))
            .map(|(&i, (f, m))| b.pos[i as usize].cross(f) + m)
            .sum();
        assert!(moment.norm() < 1e-15, "{moment}");
    }

    #[test]
    fn the_servo_loads_k_times_the_lag_and_the_support_leaves_nothing_to_turn_the_disc() {
        let mut b = ring();
        let all: Vec<u32> = (0..b.len() as u32).collect();
        let mut arc = ArcPressure::new(&b, &all, [0.1, 0.02, 10f64.to_radians(), 2e-4], 1e9);
        // The top arc's elements 2 µm down, the bottom's 1 µm up: 3 µm closed.
        for k in 0..arc.elements.len() {
            b.pos[arc.elements[k] as usize].y += if k < arc.top { -2e-6 } else { 1e-6 };
        }
        let mut forces = Forces::new(b.len());
        // An unbalanced extra force and torque on one element, as the lattice's own.
        forces.force[5] = Vec3::new(3.0, -1.0, 2.0);
        forces.torque[5] = Vec3::new(0.1, 0.2, -0.3);
        arc.apply(&b, &mut forces, 10e-6);
        assert!((arc.closure[0] - 2e-6).abs() < 1e-12, "{:?}", arc.closure);
        assert!((arc.closure[1] - 1e-6).abs() < 1e-12, "{:?}", arc.closure);
        assert!((arc.load - 1e9 * 7e-6).abs() < 1e-6, "{}", arc.load);
        let applied: f64 =
            arc.force[..arc.top].iter().map(|f| f.y).sum::<f64>() * arc.load / arc.area;
        assert!((applied + arc.load).abs() < 1e-9, "{applied}");
        let mass: f64 = b.mass.iter().sum();
        let centre: Vec3 = (0..b.len()).map(|i| b.pos[i] * b.mass[i]).sum::<Vec3>() / mass;
        let net: Vec3 = forces.force.iter().sum();
        let turn: Vec3 = (0..b.len())
            .map(|i| (b.pos[i] - centre).cross(&forces.force[i]))
            .sum();
        let spin: Vec3 = forces.torque.iter().sum();
        assert!(net.norm() < 1e-9, "{net}");
        assert!(turn.norm() < 1e-9, "{turn}");
        assert!(spin.norm() < 1e-12, "{spin}");
        assert!(arc.held_moment > 0.1, "{}", arc.held_moment);
    }
}
