//! The per-grain kernels that the run, the C ABI and the LAMMPS plugin share: a grain's average
//! stress, whether it fails, its split and the springs that bond its halves.

use super::*;

/// The average stress of a grain (Pa, tension positive, world frame; Eq. 8–13) from its
/// contact moment `Σ f ⊗ x` (N·m, x from its centre of mass) and its motion: the angular
/// acceleration from `torque` (N·m, world) and its angular velocity.
pub fn grain_average_stress(body: &Body, moment: &Matrix3<f64>, torque: &Vec3) -> Matrix3<f64> {
    let rot = body.orientation.to_rotation_matrix().into_inner();
    let mass_moment = criteria::mass_moment(&body.inertia, &rot);
    let alpha = angular_acceleration(body, torque);
    let v = body.volume();
    criteria::average_stress_from_moment(v, moment, &mass_moment, &alpha, &body.omega)
}

/// Whether a free grain fails, and why: the per-grain decision of [`GrainFracture::check`].
/// Hoek–Brown first, on the average stress ([`grain_average_stress`] of the contact moment
/// `moment` and the torque `torque`) with σc, scaled by the grain's Weibull factor `strength`
/// where `p.weibull_sigma_c` says so;
/// then the contacts: `critical` contacts whose tensile stress exceeds σ_fM × `strength`, at
/// least `critical_contacts` of them, with `points` the first (at most 3) of their points
/// (largest stress first; world, m) spanning a plane, `top_stress` (Pa) the largest stress.
/// Returns the trigger, the criterion and the stress that broke the grain (Pa).
#[allow(clippy::too_many_arguments)]
pub fn grain_fails(
    p: &FractureParams,
    body: &Body,
    strength: f64,
    moment: &Matrix3<f64>,
    torque: &Vec3,
    critical: usize,
    points: &[Vec3],
    top_stress: f64,
) -> Option<(Trigger, Criterion, f64)> {
    let stress = grain_average_stress(body, moment, torque);
    let sigma_c = p.compressive_strength(strength);
    // Most grains are far from failing: a bound on the principal values first.
    if criteria::hoek_brown_may_fail(&stress, sigma_c, p.mi) {
        let [s1, _, s3] = criteria::principal_compression_values(&stress);
        if criteria::hoek_brown_fails(s1, s3, sigma_c, p.mi) {
            return Some((Trigger::HoekBrown { stress }, Criterion::HoekBrown, s1));
        }
    }
    if critical >= p.critical_contacts {
        let points = &points[..points.len().min(3)];
        if let Some(normal) = break_plane::contacts_plane_normal(points) {
            return Some((
                Trigger::Contacts { normal },
                Criterion::Contacts,
                top_stress,
            ));
        }
    }
    None
}

/// One split of a grain ([`split_grain`]): the axis of the parent's shape frame it split
/// normal to, the + half (which the parent becomes), the − half (a new body) and what
/// bonding them needs (its body indices `a`, `b` are the caller's to set).
#[derive(Debug, Clone, Copy)]
pub struct GrainSplit {
    pub axis: usize,
    pub plus: Body,
    pub minus: Body,
    pub pending: PendingSplit,
}

/// Splits `body` under the force and torque `force`, `torque` (N, N·m, world) that it carries,
/// for the reason `trigger`: the break plane (a sphere first turns to the ideal plane and by
/// the slight rotation `jitter`, the angles of [`grain_jitter`], when
/// the scene asks), the two halves with the parent's motion, and the pending bond with its
/// spring points (with cohesion). `None` when the grain's shape forbids breaking.
pub fn split_grain(
    p: &FractureParams,
    body: &Body,
    force: &Vec3,
    torque: &Vec3,
    trigger: &Trigger,
    jitter: Option<[f64; 3]>,
) -> Option<GrainSplit> {
    let mut body = *body;
    let (parent, axis) = break_geometry(p, &mut body, trigger, jitter)?;
    let [plus, minus] = subdivision::split(&parent, axis);
    let accel = force * body.inv_mass;
    let alpha = angular_acceleration(&body, torque);
    let half = |h: &subdivision::Half| Body {
        vel: h.velocity,
        omega: parent.omega,
        ..Body::poly_ellipsoid(h.pe, h.mass, h.centroid, parent.frame)
    };
    let mut pending = PendingSplit {
        a: 0,
        b: 0,
        centroid: parent.centroid,
        accel,
        alpha,
        omega: parent.omega,
        points: [Vec3::zeros(); 16],
        count: 0,
        area: 0.0,
    };
    if let Some((_, ns)) = p.cohesion {
        let (local, area) = cohesion::spring_layout(&parent.semi, axis, ns);
        for (k, q) in local.iter().enumerate() {
            pending.points[k] = parent.origin + parent.frame * q;
        }
        pending.count = local.len();
        pending.area = area;
    }
    Some(GrainSplit {
        axis,
        plus: half(&plus),
        minus: half(&minus),
        pending,
    })
}

/// The parent of a split as the subdivision sees it and the axis to split along; `None`
/// when the grain's shape forbids breaking (Section 3.3.3). A sphere first turns its
/// principal directions (`body.orientation`) to the ideal plane and by the random slight
/// rotation `jitter`, when the scene asks.
pub(super) fn break_geometry(
    p: &FractureParams,
    body: &mut Body,
    trigger: &Trigger,
    jitter: Option<[f64; 3]>,
) -> Option<(Parent, usize)> {
    let semi = body.shape.semi_axes(body.radius);
    let sphere = body.shape.is_sphere();
    let axis = if sphere && p.ideal_plane {
        body.orientation = break_plane::turn_to_ideal(&body.orientation, &trigger.ideal_normal());
        0
    } else {
        let (_, q) = body.shape_placement();
        let axes = [q * Vec3::x(), q * Vec3::y(), q * Vec3::z()];
        break_plane::break_axis(&semi, &axes, trigger)?
    };
    if sphere && p.plane_jitter {
        if let Some(angles) = jitter {
            body.orientation = break_plane::jittered(&body.orientation, angles);
        }
    }
    let (origin, frame) = body.shape_placement();
    Some((
        Parent {
            semi,
            origin,
            frame,
            mass: body.mass,
            centroid: body.pos,
            velocity: body.vel,
            omega: body.omega,
        },
        axis,
    ))
}

/// A spring [`bond_split`] made: the spring (body indices 0, the caller's to set) and what it
/// adds at once: `force` on A (N; B gets the opposite) and the torques on A and on B about
/// their centres of mass (N·m).
#[derive(Debug, Clone)]
pub struct MadeSpring {
    pub spring: Spring,
    pub force: Vec3,
    pub torque_a: Vec3,
    pub torque_b: Vec3,
}

/// The springs of one split (Eq. 39–43), handed to `made` in the order of the split's points:
/// their initial forces make each half accelerate and turn as the parent did, given the
/// halves `a` (the + half) and `b` and the forces and torques on them after the split,
/// `[force_a, torque_a, force_b, torque_b]` (N, N·m, world). A spring that would carry no
/// force (|f| <= 1e-12 of the demand) is not made. `gc` is the cohesive energy (J/m²).
pub fn bond_split(
    gc: f64,
    a: &Body,
    b: &Body,
    loads: [&Vec3; 4],
    split: &PendingSplit,
    mut made: impl FnMut(MadeSpring),
) {
    let [force_a, torque_a, force_b, torque_b] = loads;
    let demand_of = |k: &Body, force: &Vec3, torque: &Vec3| {
        let r = k.pos - split.centroid;
        let accel = split.accel + split.alpha.cross(&r) + split.omega.cross(&split.omega.cross(&r));
        let force = accel * k.mass - force;
        let iw = world_inertia(k);
        let torque = iw * split.alpha + split.omega.cross(&(iw * split.omega)) - torque;
        (force, torque)
    };
    let (force_a, torque_a) = demand_of(a, force_a, torque_a);
    let (force_b, torque_b) = demand_of(b, force_b, torque_b);
    let mut points = [Vec3::zeros(); 16];
    for (p, q) in points.iter_mut().zip(&split.points[..split.count]) {
        *p = q - a.pos;
    }
    let points = &points[..split.count];
    let demand = Demand {
        force_a,
        torque_a,
        force_b,
        torque_b,
        b_offset: b.pos - a.pos,
    };
    let f = cohesion::initial_forces(points, &demand);
    let (qa, qb) = (a.orientation, b.orientation);
    let scale = demand.force_a.norm() + demand.force_b.norm();
    for (p, fk) in points.iter().zip(&f) {
        let f0 = fk.norm();
        // A spring with no force would break at once: it is not made.
        if f0 <= 1e-12 * scale {
            continue;
        }
        let world = p + a.pos;
        made(MadeSpring {
            spring: Spring {
                a: 0,
                b: 0,
                on_a: qa.inverse() * (world - a.pos),
                on_b: qb.inverse() * (world - b.pos),
                direction: qa.inverse() * (fk / f0),
                f0,
                k: f0 * f0 / (2.0 * gc * split.area),
                opening: 0.0,
                last_gap: Vec3::zeros(),
                last_force: *fk,
                broken: false,
            },
            force: *fk,
            torque_a: p.cross(fk),
            torque_b: -(world - b.pos).cross(fk),
        });
    }
}

/// A body's inertia tensor in the world frame (kg·m²).
pub(super) fn world_inertia(body: &Body) -> Matrix3<f64> {
    let r = body.orientation.to_rotation_matrix().into_inner();
    r * Matrix3::from_diagonal(&body.inertia) * r.transpose()
}

/// Angular acceleration (rad/s², world) of a body under the torque `torque` (N·m, world):
/// `I⁻¹ (T − ω × I ω)`.
pub fn angular_acceleration(body: &Body, torque: &Vec3) -> Vec3 {
    let q: &UnitQuaternion<f64> = &body.orientation;
    let w = q.inverse_transform_vector(&body.omega);
    let t = q.inverse_transform_vector(torque);
    let i = body.inertia;
    let l = w.component_mul(&i);
    q * (t - w.cross(&l)).component_div(&i)
}
