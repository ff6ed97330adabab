//! Conversions between the kernels' plain doubles and the library's types: quaternions,
//! 3x3 matrices and cohesive springs, field by field (the kernel tests use the same ones).

use fractum::fracture::cohesion::Spring;
use fractum::shape::Shape;
use fractum::state::{Body, Vec3};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion};

use fractum::fracture::{FractureParams, GrainLoad};

use super::types::{FractumBody, FractumFractureLaw, FractumGrainLoad, FractumSpring};

pub(crate) fn quat(q: &[f64; 4]) -> UnitQuaternion<f64> {
    UnitQuaternion::new_unchecked(Quaternion::new(q[0], q[1], q[2], q[3]))
}

pub(crate) fn quat_out(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.w, q.i, q.j, q.k]
}

pub(crate) fn matrix(m: &[f64; 9]) -> Matrix3<f64> {
    Matrix3::from_row_slice(m)
}

/// A 3x3 matrix in the kernels' row-major doubles.
pub(crate) fn matrix_out(m: &Matrix3<f64>) -> [f64; 9] {
    std::array::from_fn(|k| m[(k / 3, k % 3)])
}

/// The library's fracture parameters of a C fracture law, field by field (its counts are
/// checked against their ranges by the caller; no Weibull draw: the kernels take a grain's
/// factor as it is).
pub(crate) fn fracture_params_in(l: &FractumFractureLaw) -> FractureParams {
    FractureParams {
        mi: l.mi,
        sigma_c: l.sigma_c,
        sigma_f: l.sigma_f,
        weibull: None,
        // A host draws its Weibull factors itself (fractum_kernel_grain_strength_sized, with
        // its size exponent): nothing the kernels call reads it.
        size_exponent: f64::NAN,
        weibull_sigma_c: l.weibull_sigma_c != 0,
        particle_strength: l.particle_strength != 0,
        comminution_limit: l.comminution_limit,
        critical_contacts: l.critical_contacts as usize,
        cohesion: (l.springs > 0).then_some((l.gc, l.springs as usize)),
        ideal_plane: l.ideal_plane != 0,
        plane_jitter: l.plane_jitter != 0,
        poisson: l.poisson,
    }
}

/// The C form of a grain load, field by field.
pub(crate) fn grain_load_out(g: &GrainLoad) -> FractumGrainLoad {
    FractumGrainLoad {
        moment: matrix_out(&g.moment),
        count: g.count as i64,
        stress: g.stress,
        point: g.point.map(Into::into),
    }
}

/// A grain load as the 22 doubles of `fractum_copy_grain_loads`: FractumGrainLoad's fields
/// in its order, the count as a double.
pub(crate) fn grain_load_row(g: &GrainLoad) -> [f64; 22] {
    let c = grain_load_out(g);
    let mut row = [0.0; 22];
    row[..9].copy_from_slice(&c.moment);
    row[9] = c.count as f64;
    row[10..13].copy_from_slice(&c.stress);
    for (k, p) in c.point.iter().enumerate() {
        row[13 + 3 * k..16 + 3 * k].copy_from_slice(p);
    }
    row
}

/// The C form of a library spring.
pub(crate) fn spring_out(s: &Spring) -> FractumSpring {
    FractumSpring {
        on_a: s.on_a.into(),
        on_b: s.on_b.into(),
        direction: s.direction.into(),
        f0: s.f0,
        k: s.k,
        opening: s.opening,
        last_gap: s.last_gap.into(),
        last_force: s.last_force.into(),
        broken: i32::from(s.broken),
    }
}

/// The library spring of a C spring (its body indices 0: the kernels name the bodies).
pub(crate) fn spring_in(s: &FractumSpring) -> Spring {
    Spring {
        a: 0,
        b: 0,
        on_a: Vec3::from(s.on_a),
        on_b: Vec3::from(s.on_b),
        direction: Vec3::from(s.direction),
        f0: s.f0,
        k: s.k,
        opening: s.opening,
        last_gap: Vec3::from(s.last_gap),
        last_force: Vec3::from(s.last_force),
        broken: s.broken != 0,
    }
}

/// The C form of a library body (a sphere: its radius six times, no octant origin, the
/// identity shape frame).
pub(crate) fn body_out(b: &Body) -> FractumBody {
    let (semi, origin, to_body) = match &b.shape {
        Shape::PolyEllipsoid {
            pe,
            origin,
            to_body,
        } => (pe.semi, (*origin).into(), quat_out(to_body)),
        _ => ([b.radius; 6], [0.0; 3], [1.0, 0.0, 0.0, 0.0]),
    };
    FractumBody {
        pos: b.pos.into(),
        vel: b.vel.into(),
        omega: b.omega.into(),
        quat: quat_out(&b.orientation),
        mass: b.mass,
        radius: b.radius,
        semi,
        origin,
        to_body,
        inertia: b.inertia.into(),
        sphere: i32::from(b.shape.is_sphere()),
    }
}
