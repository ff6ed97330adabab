//! Loadings of the `dlsm` model (dlsm-voronoi-brittle-elastic.txt, Section 8): what each
//! prescribes on the elements, what it measures in series.csv, and the results it adds to
//! summary.json.
//!
//! A prescribed velocity component is set before each step and the force component on it
//! is zeroed after the force evaluation, so the integrator keeps the prescribed value; the
//! force removed is the reaction, the load the machine applies.

use nalgebra::{Matrix3, UnitQuaternion};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::scene::{Grip, LoadBy, VibrationMode};
use crate::bond::dlsm::rotation_vector;
use crate::contact::polyhedron::{GroundContact, Surface};
use crate::probe::Series;
use crate::probe::fit::least_squares_slope;
use crate::probe::spectrum::dominant_frequency;
use crate::shape::polyhedron::Polyhedron;
use crate::state::{Bodies, Forces, Vec3};

/// 0 → 1 over `ramp` seconds with zero slope at both ends (1 at once without a ramp): the
/// prescribed speeds start smoothly, which keeps the elastic waves of the start small.
pub fn ramp_factor(t: f64, ramp: f64) -> f64 {
    if ramp <= 0.0 || t >= ramp {
        1.0
    } else if t <= 0.0 {
        0.0
    } else {
        0.5 * (1.0 - (std::f64::consts::PI * t / ramp).cos())
    }
}

/// How far a speed rising by [`ramp_factor`] has carried a point by time `t`, per unit speed:
/// the integral of the ramp (s).
pub fn ramp_travel(t: f64, ramp: f64) -> f64 {
    if t <= 0.0 {
        0.0
    } else if ramp <= 0.0 {
        t
    } else if t >= ramp {
        0.5 * ramp + (t - ramp)
    } else {
        0.5 * (t - ramp / std::f64::consts::PI * (std::f64::consts::PI * t / ramp).sin())
    }
}

/// Mean of `f` over a set of elements.
fn mean_of(set: &[u32], f: impl Fn(usize) -> f64) -> f64 {
    set.iter().map(|&i| f(i as usize)).sum::<f64>() / set.len().max(1) as f64
}

/// Quasi-static tension of a box along x (Section 8.2.1, 8.2.3): the elements with a face
/// on x− and x+ move apart along x at the speed a uniform strain rate gives their seeds
/// (`strain_rate × (x − centre)`), so that the two faces move apart at constant speed; their
/// rotations are held, their y and z motions free.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Tension {
    pub strain_rate: f64,
    pub end_strain: f64,
    pub ramp_time: f64,
    /// Box edge along x (m) and cross-section (m²).
    pub length: f64,
    pub section: f64,
    /// Elements with a face on x−, x+, y−, y+, z−, z+.
    pub faces: [Vec<u32>; 6],
    /// Undeformed x of the seeds of the x− and x+ elements, relative to the box centre.
    pub lever: [Vec<f64>; 2],
    /// Initial distance between the mean positions of opposite face sets along x, y, z.
    pub gauge: [f64; 3],
    /// The elements whose undeformed position lies in the middle 60% of the box along x:
    /// the extensometer's gauge section.
    pub middle: Vec<u32>,
    /// Force (N, tension positive) the machine applies on the x− and x+ faces.
    pub reaction: [f64; 2],
    pub stop_fraction: f64,
    pub tensile_strength: Option<f64>,
    /// Clamped grips: the driven elements' y and z are held too.
    #[serde(default)]
    pub grip: Grip,
}

/// A cylinder released from a static field, x− face clamped (Section 8.2.2). In tension the
/// clamp holds the axial motion of its elements and lets the section contract, as the rod
/// theory of Eq. 44 assumes (holding the lateral motion too stiffens an end zone of about a
/// sixth of the radius: +1.7% on the frequency of the 1 m bar); in torsion it holds them.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FreeVibration {
    pub mode: VibrationMode,
    /// A (tension) or α (torsion, rad/m).
    pub amplitude: f64,
    pub end_time: f64,
    pub length: f64,
    pub clamped: Vec<u32>,
    pub free: Vec<u32>,
    /// Eq. 44 / 45 (Hz).
    pub frequency_theory: f64,
}

/// The Brazilian test (Section 8.2.4): the disc squeezed across its y diameter, by driven
/// elements of the loading arcs (the paper's), by two rigid platens or curved jaws, or by a
/// uniform pressure over the loading arcs.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Brazilian {
    pub speed: f64,
    pub end_strain: f64,
    pub ramp_time: f64,
    /// Half loading angle α (rad); 0 for flat loading, platens and jaws.
    pub half_angle: f64,
    pub diameter: f64,
    pub thickness: f64,
    /// The driven elements of the top and bottom loading arcs (empty unless they are driven).
    pub top: Vec<u32>,
    pub bottom: Vec<u32>,
    /// Initial distance between the mean heights of the bottom and top sets (m).
    pub gap: f64,
    /// Compressive force (N) on the top and bottom sets.
    pub reaction: [f64; 2],
    pub stop_fraction: f64,
    pub tensile_strength: Option<f64>,
    /// Rigid surfaces, top (normal −y) and bottom (normal +y), when they load the disc: flat
    /// platens or curved jaws; empty otherwise.
    pub platens: Vec<GroundContact>,
    /// The platens' (jaws') heights (y, m) at the start, top and bottom: their points
    /// nearest to the disc's centre.
    pub platen_start: [f64; 2],
    /// A uniform pressure over the loading arcs, when it loads the disc.
    pub pressure: Option<ArcPressure>,
}

impl Brazilian {
    /// Whether the elements of the loading arcs are driven (rather than platens, jaws or a
    /// pressure loading the disc).
    pub fn drives_elements(&self) -> bool {
        self.platens.is_empty() && self.pressure.is_none()
    }

    /// Whether the platens are curved jaws.
    pub fn jaws(&self) -> bool {
        self.platens
            .first()
            .is_some_and(|p| matches!(p.surface, Surface::Cylinder { .. }))
    }

    /// The `loading.load_by` this loading was built from.
    pub fn load_by(&self) -> LoadBy {
        if self.pressure.is_some() {
            LoadBy::ArcPressure
        } else if self.jaws() {
            LoadBy::CurvedJaws
        } else if !self.platens.is_empty() {
            LoadBy::FlatPlatens
        } else {
            LoadBy::Elements
        }
    }

    /// How far (m) each platen, jaw or side of the servo's command has moved towards the
    /// other by time `t`: `speed × ramp_travel`.
    pub fn travel(&self, t: f64) -> f64 {
        self.speed * ramp_travel(t, self.ramp_time)
    }

    /// The platens' heights (y, m) at time `t`.
    pub fn platen_heights(&self, t: f64) -> [f64; 2] {
        let travel = self.travel(t);
        [self.platen_start[0] - travel, self.platen_start[1] + travel]
    }

    /// The jaws' contact arc 2α (degrees) in the last evaluation: the angle at the disc's
    /// centre spanned by the touching vertices, the mean of the two jaws.
    pub fn contact_arc_degrees(&self) -> f64 {
        let reach = mean_of(&[0, 1], |k| self.platens[k].reach);
        2.0 * (reach / (0.5 * self.diameter)).min(1.0).asin().to_degrees()
    }
}

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
    fn apply(&mut self, bodies: &Bodies, forces: &mut Forces, command: f64) {
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

/// A body thrown onto an inclined ground plane (Section 8.1).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Drop {
    pub end_time: f64,
    /// The ground: a point on it and its upward unit normal.
    pub ground_point: Vec3,
    pub ground_normal: Vec3,
    /// Down the slope, and the axis about which rolling down turns.
    pub downslope: Vec3,
    pub roll_axis: Vec3,
    pub gravity: Vec3,
    /// Turns about `roll_axis` so far, and the body's angular velocity at the last row.
    pub turns: f64,
    pub last_spin: f64,
    pub last_time: f64,
    pub centre0: Vec3,
    /// The body's extent across the ground at the start (m): a ball's diameter.
    #[serde(default)]
    pub size: f64,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum DlsmLoading {
    /// Nothing prescribed for `end_time` seconds.
    Free {
        end_time: f64,
    },
    Tension(Tension),
    FreeVibration(FreeVibration),
    Brazilian(Brazilian),
    Drop(Drop),
}

/// What a row needs besides the bodies.
pub struct RowInputs<'a> {
    pub time: f64,
    pub bodies: &'a Bodies,
    /// Undeformed centroids.
    pub reference: &'a [Vec3],
    pub broken: usize,
    /// Strain energy of the lattice and energy of the ground springs (J), for `drop`.
    pub strain_energy: f64,
    pub contact_energy: f64,
    pub ground_contacts: usize,
}

impl DlsmLoading {
    /// Duration of the loading (s).
    pub fn end_time(&self) -> f64 {
        match self {
            DlsmLoading::Free { end_time } => *end_time,
            DlsmLoading::Tension(t) => 0.5 * t.ramp_time + t.end_strain / t.strain_rate,
            DlsmLoading::FreeVibration(v) => v.end_time,
            DlsmLoading::Brazilian(b) => {
                0.5 * b.ramp_time + b.end_strain * b.diameter / (2.0 * b.speed)
            }
            DlsmLoading::Drop(d) => d.end_time,
        }
    }

    /// Sets the prescribed velocity components for a step whose middle is at `t`.
    pub fn prescribe(&self, bodies: &mut Bodies, t: f64) {
        match self {
            DlsmLoading::Tension(l) => {
                let rate = l.strain_rate * ramp_factor(t, l.ramp_time);
                for k in 0..2 {
                    for (&i, &x) in l.faces[k].iter().zip(&l.lever[k]) {
                        let v = &mut bodies.vel[i as usize];
                        v.x = rate * x;
                        if l.grip == Grip::Clamped {
                            v.y = 0.0;
                            v.z = 0.0;
                        }
                        bodies.omega[i as usize] = Vec3::zeros();
                    }
                }
            }
            DlsmLoading::FreeVibration(l) => {
                for &i in &l.clamped {
                    match l.mode {
                        VibrationMode::Tension => bodies.vel[i as usize].x = 0.0,
                        VibrationMode::Torsion => bodies.vel[i as usize] = Vec3::zeros(),
                    }
                    bodies.omega[i as usize] = Vec3::zeros();
                }
            }
            DlsmLoading::Brazilian(l) if l.drives_elements() => {
                let v = l.speed * ramp_factor(t, l.ramp_time);
                for (set, speed) in [(&l.top, -v), (&l.bottom, v)] {
                    for &i in set {
                        bodies.vel[i as usize].y = speed;
                        bodies.omega[i as usize] = Vec3::zeros();
                    }
                }
            }
            DlsmLoading::Free { .. } | DlsmLoading::Drop(_) | DlsmLoading::Brazilian(_) => {}
        }
    }

    /// The platens or jaws of a Brazilian test push the elements they touch (positions at
    /// time `t`), their reactions the compressive forces they carry; or the arcs' pressure
    /// is applied.
    pub fn press(
        &mut self,
        bodies: &Bodies,
        shapes: &[Polyhedron],
        forces: &mut Forces,
        t: f64,
        dt: f64,
    ) {
        let DlsmLoading::Brazilian(l) = self else {
            return;
        };
        let command = 2.0 * l.travel(t);
        if let Some(arc) = &mut l.pressure {
            arc.apply(bodies, forces, command);
            l.reaction = [arc.load; 2];
            return;
        }
        let heights = l.platen_heights(t);
        let speed = l.speed * ramp_factor(t, l.ramp_time);
        for (k, platen) in l.platens.iter_mut().enumerate() {
            platen.point.y = heights[k];
            // The top platen moves and pushes the elements down (−y), the bottom one up.
            platen.velocity = platen.normal * speed;
            platen.accumulate(bodies, shapes, forces, dt);
            l.reaction[k] = platen.normal.dot(&platen.total);
        }
    }

    /// Takes the reactions out of the forces: records them and zeroes the prescribed
    /// components.
    pub fn constrain(&mut self, forces: &mut Forces) {
        match self {
            DlsmLoading::Tension(l) => {
                let mut r = [0.0; 2];
                for (k, sign) in [(0usize, 1.0), (1, -1.0)] {
                    for &i in &l.faces[k] {
                        let f = &mut forces.force[i as usize];
                        r[k] += sign * f.x;
                        f.x = 0.0;
                        if l.grip == Grip::Clamped {
                            f.y = 0.0;
                            f.z = 0.0;
                        }
                        forces.torque[i as usize] = Vec3::zeros();
                    }
                }
                l.reaction = r;
            }
            DlsmLoading::FreeVibration(l) => {
                for &i in &l.clamped {
                    match l.mode {
                        VibrationMode::Tension => forces.force[i as usize].x = 0.0,
                        VibrationMode::Torsion => forces.force[i as usize] = Vec3::zeros(),
                    }
                    forces.torque[i as usize] = Vec3::zeros();
                }
            }
            DlsmLoading::Brazilian(l) if l.drives_elements() => {
                let mut r = [0.0; 2];
                for (k, set, sign) in [(0usize, &l.top, 1.0), (1, &l.bottom, -1.0)] {
                    for &i in set {
                        r[k] += sign * forces.force[i as usize].y;
                        forces.force[i as usize].y = 0.0;
                        forces.torque[i as usize] = Vec3::zeros();
                    }
                }
                l.reaction = r;
            }
            DlsmLoading::Free { .. } | DlsmLoading::Drop(_) | DlsmLoading::Brazilian(_) => {}
        }
    }

    /// The columns of series.csv.
    pub fn columns(&self) -> Vec<&'static str> {
        match self {
            DlsmLoading::Free { .. } => vec!["time", "kinetic_energy", "broken_contacts"],
            DlsmLoading::Tension(_) => vec![
                "time",
                "strain",
                "stress",
                "lateral_strain_y",
                "lateral_strain_z",
                "strain_faces",
                "lateral_strain_faces",
                "kinetic_energy",
                "broken_contacts",
            ],
            DlsmLoading::FreeVibration(v) => match v.mode {
                VibrationMode::Tension => vec![
                    "time",
                    "free_face_displacement",
                    "kinetic_energy",
                    "strain_energy",
                    "total_energy",
                ],
                VibrationMode::Torsion => vec![
                    "time",
                    "free_face_rotation",
                    "kinetic_energy",
                    "strain_energy",
                    "total_energy",
                ],
            },
            DlsmLoading::Brazilian(l) => {
                let mut c = vec![
                    "time",
                    "diametral_strain",
                    "force",
                    "force_top",
                    "force_bottom",
                    "broken_contacts",
                    "kinetic_energy",
                ];
                if l.jaws() {
                    c.push("contact_arc_degrees");
                }
                if l.pressure.is_some() {
                    c.push("held_moment");
                }
                c
            }
            DlsmLoading::Drop(_) => vec![
                "time",
                "kinetic_energy",
                "potential_energy",
                "strain_energy",
                "contact_energy",
                "total_energy",
                "downslope_distance",
                "height",
                "rotation_turns",
                "ground_contacts",
            ],
        }
    }

    /// One row of series.csv.
    pub fn row(&mut self, r: &RowInputs) -> Vec<f64> {
        let b = r.bodies;
        let ke = b.kinetic_energy();
        match self {
            DlsmLoading::Free { .. } => vec![r.time, ke, r.broken as f64],
            DlsmLoading::Tension(l) => {
                let spread = |lo: &[u32], hi: &[u32], axis: usize| {
                    mean_of(hi, |i| b.pos[i][axis]) - mean_of(lo, |i| b.pos[i][axis])
                };
                let faces = spread(&l.faces[0], &l.faces[1], 0) / l.gauge[0] - 1.0;
                let ly = spread(&l.faces[2], &l.faces[3], 1) / l.gauge[1] - 1.0;
                let lz = spread(&l.faces[4], &l.faces[5], 2) / l.gauge[2] - 1.0;
                // Extensometer: the slope of each displacement component along its own axis,
                // fitted over the gauge section, away from the gripped faces.
                let slope = |axis: usize| {
                    let pts: Vec<(f64, f64)> = l
                        .middle
                        .iter()
                        .map(|&i| {
                            let i = i as usize;
                            (r.reference[i][axis], b.pos[i][axis] - r.reference[i][axis])
                        })
                        .collect();
                    least_squares_slope(&pts)
                };
                let stress = (l.reaction[0] + l.reaction[1]) / (2.0 * l.section);
                vec![
                    r.time,
                    slope(0),
                    stress,
                    slope(1),
                    slope(2),
                    faces,
                    0.5 * (ly + lz),
                    ke,
                    r.broken as f64,
                ]
            }
            DlsmLoading::FreeVibration(v) => {
                let signal = match v.mode {
                    VibrationMode::Tension => mean_of(&v.free, |i| b.pos[i].x - r.reference[i].x),
                    VibrationMode::Torsion => mean_of(&v.free, |i| {
                        let (p, q) = (b.pos[i], r.reference[i]);
                        (q.y * p.z - q.z * p.y).atan2(q.y * p.y + q.z * p.z)
                    }),
                };
                vec![r.time, signal, ke, r.strain_energy, ke + r.strain_energy]
            }
            DlsmLoading::Brazilian(l) => {
                let closure = if let Some(arc) = &l.pressure {
                    arc.closure[0] + arc.closure[1]
                } else if l.platens.is_empty() {
                    // The driven arcs' mean heights.
                    l.gap - (mean_of(&l.top, |i| b.pos[i].y) - mean_of(&l.bottom, |i| b.pos[i].y))
                } else {
                    let [top, bottom] = l.platen_heights(r.time);
                    l.gap - (top - bottom)
                };
                let force = 0.5 * (l.reaction[0] + l.reaction[1]);
                let mut row = vec![
                    r.time,
                    closure / l.diameter,
                    force,
                    l.reaction[0],
                    l.reaction[1],
                    r.broken as f64,
                    ke,
                ];
                if l.jaws() {
                    row.push(l.contact_arc_degrees());
                }
                if let Some(arc) = &l.pressure {
                    row.push(arc.held_moment);
                }
                row
            }
            DlsmLoading::Drop(d) => {
                let mut mass = 0.0;
                let mut centre = Vec3::zeros();
                let mut momentum = Vec3::zeros();
                let mut potential = 0.0;
                for i in 0..b.len() {
                    mass += b.mass[i];
                    centre += b.pos[i] * b.mass[i];
                    momentum += b.vel[i] * b.mass[i];
                    potential -= b.mass[i] * d.gravity.dot(&(b.pos[i] - r.reference[i]));
                }
                centre /= mass;
                // The body's rigid rotation: its angular momentum about the centre of mass
                // over its inertia tensor there (the elements' positions, not their spins).
                let vc = momentum / mass;
                let mut l = Vec3::zeros();
                let mut inertia = Matrix3::zeros();
                for i in 0..b.len() {
                    let x = b.pos[i] - centre;
                    l += x.cross(&(b.vel[i] - vc)) * b.mass[i];
                    inertia +=
                        (Matrix3::identity() * x.norm_squared() - x * x.transpose()) * b.mass[i];
                }
                let spin = inertia
                    .try_inverse()
                    .map_or(0.0, |inv| (inv * l).dot(&d.roll_axis));
                // Trapezoidal turning between rows.
                d.turns +=
                    0.5 * (spin + d.last_spin) * (r.time - d.last_time) / std::f64::consts::TAU;
                d.last_spin = spin;
                d.last_time = r.time;
                let total = ke + potential + r.strain_energy + r.contact_energy;
                vec![
                    r.time,
                    ke,
                    potential,
                    r.strain_energy,
                    r.contact_energy,
                    total,
                    (centre - d.centre0).dot(&d.downslope),
                    (centre - d.ground_point).dot(&d.ground_normal),
                    d.turns,
                    r.ground_contacts as f64,
                ]
            }
        }
    }

    /// With fracture: true once the load has fallen below `stop_fraction` of its peak.
    pub fn failed(&self, series: &Series) -> bool {
        let (column, fraction, on) = match self {
            DlsmLoading::Tension(l) => ("stress", l.stop_fraction, l.tensile_strength.is_some()),
            DlsmLoading::Brazilian(l) => ("force", l.stop_fraction, l.tensile_strength.is_some()),
            _ => return false,
        };
        if !on || fraction <= 0.0 {
            return false;
        }
        let Some(v) = series.column(column) else {
            return false;
        };
        let peak = v.iter().copied().fold(0.0, f64::max);
        peak > 0.0 && v.last().is_some_and(|&x| x < fraction * peak)
    }

    /// The loading's results for summary.json.
    ///
    /// `bounces` (drop): how often the body left the ground after touching it, i.e. output rows
    /// with no ground contact after a row with some; `downslope_sizes`: the distance travelled
    /// down the slope in units of the body's extent across the ground at the start (a ball's
    /// diameter).
    pub fn summarize(&self, series: &Series, dt_row: f64, out: &mut Map<String, Value>) {
        match self {
            DlsmLoading::Tension(l) => tension_summary(l, series, out),
            DlsmLoading::FreeVibration(v) => {
                let name = match v.mode {
                    VibrationMode::Tension => "free_face_displacement",
                    VibrationMode::Torsion => "free_face_rotation",
                };
                if let Some(signal) = series.column(name) {
                    if let Some(f) = dominant_frequency(&signal, dt_row) {
                        out.insert("frequency_measured".into(), f.into());
                        out.insert(
                            "frequency_error".into(),
                            (f / v.frequency_theory - 1.0).into(),
                        );
                    }
                }
                out.insert("frequency_theory".into(), v.frequency_theory.into());
            }
            DlsmLoading::Brazilian(l) => brazilian_summary(l, series, out),
            DlsmLoading::Drop(d) => {
                if let (Some(total), Some(down)) = (
                    series.column("total_energy"),
                    series.column("downslope_distance"),
                ) {
                    if let Some(&e0) = total.first() {
                        let top = total.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                        out.insert("max_energy_ratio".into(), (top / e0).into());
                        out.insert("initial_energy".into(), e0.into());
                    }
                    let distance = down.last().copied().unwrap_or(0.0);
                    out.insert("downslope_distance".into(), distance.into());
                    if d.size > 0.0 {
                        out.insert("downslope_sizes".into(), (distance / d.size).into());
                    }
                }
                if let Some(contacts) = series.column("ground_contacts") {
                    out.insert("bounces".into(), take_offs(&contacts).into());
                }
                out.insert("rotation_turns".into(), d.turns.into());
            }
            DlsmLoading::Free { .. } => {}
        }
    }

    pub fn describe(&self) -> String {
        match self {
            DlsmLoading::Free { end_time } => {
                format!("none: nothing prescribed for {end_time:e} s")
            }
            DlsmLoading::Tension(l) => format!(
                "tension along x: the {} elements on x- and the {} on x+ move apart along x as a uniform strain rate of {:e} 1/s moves their seeds (faces {} m apart), rotations held, {}, speed rising over {:e} s, to strain {}",
                l.faces[0].len(),
                l.faces[1].len(),
                l.strain_rate,
                l.length,
                match l.grip {
                    Grip::Sliding => "y and z free (sliding grips)",
                    Grip::Clamped => "y and z held (clamped grips)",
                },
                l.ramp_time,
                l.end_strain
            ),
            DlsmLoading::FreeVibration(v) => format!(
                "free vibration from a static {} field ({} = {:e}), {} elements on x- clamped, {} on the free face x+ watched, for {:e} s; theory {:.1} Hz",
                match v.mode {
                    VibrationMode::Tension => "tension",
                    VibrationMode::Torsion => "torsion",
                },
                match v.mode {
                    VibrationMode::Tension => "A",
                    VibrationMode::Torsion => "alpha (rad/m)",
                },
                v.amplitude,
                v.clamped.len(),
                v.free.len(),
                v.end_time,
                v.frequency_theory
            ),
            DlsmLoading::Brazilian(l) if l.pressure.is_some() => {
                let arc = l.pressure.as_ref().expect("matched");
                format!(
                    "Brazilian test: a uniform radial pressure over the loading arcs (2 alpha = {:.1} degrees, shared by {} top and {} bottom elements), each arc's load K (c - q) from a servo of stiffness K = {:.3e} N/m on the arcs' closure q, commanded at {} m/s per side, rising over {:e} s, to diametral strain {}; the disc's rigid motions and uniform element spin held",
                    2.0 * l.half_angle.to_degrees(),
                    arc.top,
                    arc.elements.len() - arc.top,
                    arc.stiffness,
                    l.speed,
                    l.ramp_time,
                    l.end_strain
                )
            }
            DlsmLoading::Brazilian(l) if !l.platens.is_empty() => format!(
                "Brazilian test between two rigid {} (frictional contacts of stiffness {:.3e} N/m, friction {}) moving towards each other along y at {} m/s each, speed rising over {:e} s, to diametral strain {}; the force is read on them",
                match l.platens[0].surface {
                    Surface::Plane => "flat platens".to_string(),
                    Surface::Cylinder { radius, .. } => format!("curved jaws of radius {radius} m"),
                },
                l.platens[0].stiffness,
                l.platens[0].friction,
                l.speed,
                l.ramp_time,
                l.end_strain
            ),
            DlsmLoading::Brazilian(l) => format!(
                "Brazilian test: {} top and {} bottom elements (loading arc 2 alpha = {:.1} degrees) move towards each other along y at {} m/s each, speed rising over {:e} s, to diametral strain {}",
                l.top.len(),
                l.bottom.len(),
                2.0 * l.half_angle.to_degrees(),
                l.speed,
                l.ramp_time,
                l.end_strain
            ),
            DlsmLoading::Drop(d) => format!(
                "drop onto a ground plane of normal ({:.4}, {:.4}, {:.4}) through ({:.4e}, {:.4e}, {:.4e}) for {:e} s",
                d.ground_normal.x,
                d.ground_normal.y,
                d.ground_normal.z,
                d.ground_point.x,
                d.ground_point.y,
                d.ground_point.z,
                d.end_time
            ),
        }
    }
}

/// The rows up to the peak of `load` whose `x` is at least a fifth of its value there: the
/// loading branch without its start-up transient.
fn loading_branch(x: &[f64], load: &[f64]) -> (usize, Vec<usize>) {
    let peak = load
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(k, _)| k);
    let from = 0.2 * x[peak];
    (peak, (0..=peak).filter(|&k| x[k] >= from).collect())
}

fn tension_summary(l: &Tension, series: &Series, out: &mut Map<String, Value>) {
    let (Some(strain), Some(stress), Some(ly), Some(lz)) = (
        series.column("strain"),
        series.column("stress"),
        series.column("lateral_strain_y"),
        series.column("lateral_strain_z"),
    ) else {
        return;
    };
    if strain.len() < 3 {
        return;
    }
    let (peak, rows) = loading_branch(&strain, &stress);
    if rows.len() >= 3 {
        let pts: Vec<(f64, f64)> = rows.iter().map(|&k| (strain[k], stress[k])).collect();
        out.insert("apparent_young".into(), least_squares_slope(&pts).into());
        let lat: Vec<(f64, f64)> = rows
            .iter()
            .map(|&k| (strain[k], -0.5 * (ly[k] + lz[k])))
            .collect();
        out.insert("apparent_poisson".into(), least_squares_slope(&lat).into());
        out.insert(
            "fit_strain_range".into(),
            serde_json::json!([strain[rows[0]], strain[peak]]),
        );
    }
    out.insert("strain_final".into(), strain[strain.len() - 1].into());
    if let Some(sf) = l.tensile_strength {
        out.insert("apparent_strength".into(), stress[peak].into());
        out.insert("local_strength".into(), sf.into());
        out.insert("strength_ratio".into(), (stress[peak] / sf).into());
        out.insert("strain_at_peak".into(), strain[peak].into());
    }
}

/// Eq. 47: the factor k of a loading arc of half angle α (1 for α = 0).
pub fn arc_factor(alpha: f64) -> f64 {
    if alpha <= 0.0 {
        return 1.0;
    }
    let (c, s) = (alpha.cos(), alpha.sin());
    let num = (2.0 * c * c * c + c + s / alpha).powi(2);
    num / (8.0 * (c + s / alpha)) * alpha / s
}

fn brazilian_summary(l: &Brazilian, series: &Series, out: &mut Map<String, Value>) {
    // Eq. 46, divided by k of Eq. 47 for a loading arc (Eq. 48).
    let sf = l.tensile_strength.unwrap_or(0.0);
    let eq46 = std::f64::consts::FRAC_PI_2 * sf * l.diameter * l.thickness;
    let theory = eq46 / arc_factor(l.half_angle);
    if let Some(force) = series.column("force") {
        let (k, peak) = force
            .iter()
            .copied()
            .enumerate()
            .fold((0, 0.0), |a, (k, f)| if f > a.1 { (k, f) } else { a });
        let peak_row = (peak > 0.0).then_some(k);
        out.insert("peak_force".into(), peak.into());
        if sf > 0.0 {
            out.insert("theory_force".into(), theory.into());
            out.insert("force_ratio".into(), (peak / theory).into());
        }
        // Jaws: Eq. 48 with the contact arc they made at the peak.
        if let (Some(arcs), Some(k)) = (series.column("contact_arc_degrees"), peak_row) {
            let arc = arcs[k];
            out.insert("contact_arc_degrees".into(), arc.into());
            if sf > 0.0 {
                let at_arc = eq46 / arc_factor(0.5 * arc.to_radians());
                out.insert("theory_force_arc".into(), at_arc.into());
                out.insert("force_ratio_arc".into(), (peak / at_arc).into());
            }
        }
        // The arcs' pressure: the moment the support of the free motions took at the peak,
        // over the load's own moment scale P R.
        if let (Some(held), Some(k)) = (series.column("held_moment"), peak_row) {
            out.insert(
                "held_moment_ratio".into(),
                (held[k] / (peak * 0.5 * l.diameter)).into(),
            );
        }
    }
    out.insert(
        "arc_degrees".into(),
        (2.0 * l.half_angle.to_degrees()).into(),
    );
    out.insert(
        "loaded_elements".into(),
        (l.top.len() + l.bottom.len() + l.pressure.as_ref().map_or(0, |p| p.elements.len())).into(),
    );
    out.insert("load_by".into(), l.load_by().as_str().into());
    if let Some(arc) = &l.pressure {
        out.insert("servo_stiffness".into(), arc.stiffness.into());
    }
}

/// Take-offs in a series of contact counts: rows with none that follow a row with some.
fn take_offs(contacts: &[f64]) -> usize {
    contacts
        .windows(2)
        .filter(|w| w[0] > 0.0 && w[1] == 0.0)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_is_smooth_and_reaches_one() {
        assert_eq!(ramp_factor(0.0, 1.0), 0.0);
        assert!((ramp_factor(0.5, 1.0) - 0.5).abs() < 1e-15);
        assert_eq!(ramp_factor(2.0, 1.0), 1.0);
        assert_eq!(ramp_factor(0.3, 0.0), 1.0);
    }

    #[test]
    fn ramp_travel_is_the_integral_of_the_ramp() {
        // Midpoint sums of ramp_factor against the closed form, during and after the ramp.
        let ramp = 2e-3;
        for t in [0.3e-3, 1e-3, 2e-3, 3.7e-3] {
            let n = 200_000;
            let h = t / n as f64;
            let sum: f64 = (0..n)
                .map(|k| ramp_factor((k as f64 + 0.5) * h, ramp) * h)
                .sum();
            assert!((ramp_travel(t, ramp) - sum).abs() < 1e-12, "{t}");
        }
        assert_eq!(ramp_travel(-1.0, ramp), 0.0);
        assert_eq!(ramp_travel(0.5, 0.0), 0.5);
    }

    #[test]
    fn take_offs_count_rows_leaving_the_ground() {
        // In the air, lands, leaves, chatters down to none for one row, rests.
        assert_eq!(
            take_offs(&[0.0, 0.0, 3.0, 5.0, 0.0, 0.0, 2.0, 0.0, 4.0, 4.0]),
            2
        );
        assert_eq!(take_offs(&[]), 0);
        assert_eq!(take_offs(&[0.0, 0.0]), 0);
    }

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

    #[test]
    fn arc_factor_of_the_paper() {
        // Section 8.2.4: 2α = 20° turns 64.2 kN into 66.8 kN, k = 0.9610.
        let k = arc_factor(10f64.to_radians());
        assert!((k - 0.96029).abs() < 1e-4, "{k}");
        assert!((64.2 / k - 66.8).abs() < 0.1);
    }
}
