//! The tests' own conversions between the library's types and the kernels' C structs,
//! written from what include/fractum.h (ffi/src/kernels/types.rs) says each C field means,
//! field by field by name. They are not the kernels' ffi/src/kernels/convert.rs: a test that
//! built its inputs and its expected outputs with the code it checks would pass whatever
//! that code maps wrong, the same mistake on both sides of the comparison.

use fractum::fracture::FractureParams;
use fractum::fracture::cohesion::Spring;
use fractum::shape::Shape;
use fractum::state::{Body, Vec3};
use nalgebra::{Matrix3, UnitQuaternion};

use crate::types::{FractumBody, FractumFractureLaw, FractumSpring};

/// A vector as the header's 3 doubles: x y z.
pub fn c_vec(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// A quaternion as the header's 4 doubles: w x y z ("Quaternions are `w x y z`").
pub fn c_quat(q: &UnitQuaternion<f64>) -> [f64; 4] {
    let v = q.imag();
    [q.scalar(), v.x, v.y, v.z]
}

/// A 3x3 matrix as the kernels' 9 doubles: row-major ("3x3 matrices are row-major"), the
/// first row first.
pub fn c_rows(m: &Matrix3<f64>) -> [f64; 9] {
    [
        m.m11, m.m12, m.m13, // row 0
        m.m21, m.m22, m.m23, // row 1
        m.m31, m.m32, m.m33, // row 2
    ]
}

/// FractumBody of a library body, each field as its doc in the header says: centre of mass
/// `pos`, velocity `vel`, angular velocity `omega`, orientation (body to world) `quat`,
/// `mass`, bounding radius `radius`; a poly-ellipsoid's semi-axes a+ a- b+ b- c+ c- `semi`,
/// octant origin in the body frame `origin` and shape-to-body rotation `to_body`, a sphere's
/// "all = radius", "0" and "1 0 0 0"; the principal moments `inertia`; `sphere` 1 for a
/// sphere, 0 for a poly-ellipsoid.
pub fn c_body(b: &Body) -> FractumBody {
    let (semi, origin, to_body, sphere) = match &b.shape {
        Shape::Sphere => ([b.radius; 6], [0.0; 3], [1.0, 0.0, 0.0, 0.0], 1),
        Shape::PolyEllipsoid {
            pe,
            origin,
            to_body,
        } => (pe.semi, c_vec(origin), c_quat(to_body), 0),
        Shape::Polyhedron => panic!("the kernels take spheres and poly-ellipsoids"),
    };
    FractumBody {
        pos: c_vec(&b.pos),
        vel: c_vec(&b.vel),
        omega: c_vec(&b.omega),
        quat: c_quat(&b.orientation),
        mass: b.mass,
        radius: b.radius,
        semi,
        origin,
        to_body,
        inertia: c_vec(&b.inertia),
        sphere,
    }
}

/// FractumSpring of a library spring, each field as its doc in the header says: the ends on
/// A and on B in their bodies' frames, the force direction on A, the initial force f_i, the
/// softening stiffness k, the largest elongation, the last gap and force, broken 1.
pub fn c_spring(s: &Spring) -> FractumSpring {
    FractumSpring {
        on_a: c_vec(&s.on_a),
        on_b: c_vec(&s.on_b),
        direction: c_vec(&s.direction),
        f0: s.f0,
        k: s.k,
        opening: s.opening,
        last_gap: c_vec(&s.last_gap),
        last_force: c_vec(&s.last_force),
        broken: if s.broken { 1 } else { 0 },
    }
}

/// The library's fracture constants the kernels are documented to use for a
/// FractumFractureLaw ("Grain fracture constants (FractureParams, resolved)"): its fields by
/// name, and for the constants the C law does not carry, what the kernels' docs fix.
pub fn law_params(l: &FractumFractureLaw) -> FractureParams {
    let count = |n: i32| usize::try_from(n).expect("a count the kernels take is not negative");
    FractureParams {
        mi: l.mi,
        sigma_c: l.sigma_c,
        sigma_f: l.sigma_f,
        // No Weibull draw in the kernels that take a law: a grain's factor is their argument
        // (fractum_kernel_check's `strength`, "1 without Weibull statistics"), which a host
        // draws with fractum_kernel_grain_strength (its own modulus and reference size).
        weibull: None,
        // The C law has no size exponent: a host draws its factors with
        // fractum_kernel_grain_strength_sized. Nothing the kernels call reads it.
        size_exponent: f64::NAN,
        // weibull_sigma_c: "Nonzero: ... scales sigma_c as well as sigma_f (`both`); 0:
        // sigma_f only (`contact`)"; particle_strength: "Nonzero: ... the contact tensile
        // strength with its cube root".
        weibull_sigma_c: l.weibull_sigma_c != 0,
        particle_strength: l.particle_strength != 0,
        // comminution_limit: "below which a piece no longer splits ... 0: none".
        comminution_limit: l.comminution_limit,
        critical_contacts: count(l.critical_contacts),
        // springs: "0 without cohesion"; gc: "0 without cohesion"; fractum_kernel_split: "with
        // cohesion (`law->springs` > 0)"; fractum_kernel_bond: "none without cohesion
        // (`law->springs` = 0)".
        cohesion: if l.springs > 0 {
            Some((l.gc, count(l.springs)))
        } else {
            None
        },
        ideal_plane: l.ideal_plane != 0,
        plane_jitter: l.plane_jitter != 0,
        poisson: l.poisson,
    }
}
