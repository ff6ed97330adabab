//! Kernel exports: the per-contact and per-grain functions of Fractum's granular model, for
//! hosts that keep their own particles (a LAMMPS plugin). Each one wraps the library
//! function that Fractum's own run calls (`fractum::effects::contact::pair_contact`,
//! `fractum::fracture::split_grain`, ...), so a host gets the same bits Fractum computes.
//!
//! Every kernel returns a `FractumStatus`: `FRACTUM_ERR_NULL` on a null pointer,
//! `FRACTUM_ERR_INPUT` on an argument the library cannot take (a poly-ellipsoid's semi-axis
//! that is not finite and positive, in any `FractumBody` passed; a count out of range),
//! `FRACTUM_ERR_INTERNAL` on a caught panic. They write their results through out pointers,
//! keep no state, hand nothing to free (split and bond use the library's temporary buffers
//! inside the call), and leave the last-error message of the handle API alone (they are
//! called per contact). Quaternions are `w x y z` and are taken as given (not
//! renormalised); 3x3 matrices are row-major. A `FractumBody`'s inverse mass and moments
//! are taken as 1/m, which is how Fractum's bodies hold them.

use std::panic::{AssertUnwindSafe, catch_unwind};

use fractum::contact::convex::{self, ContactGeometry, Placed};
use fractum::contact::hertz_mindlin::{
    ContactForce, Hertz, KernelConsts, Mindlin, ViscousDamping, hertz_mindlin,
};
use fractum::effects::contact::{
    BodyView, ContactBody, PairMemory, PairOut, Placement, bound_off_wall, bounds_apart, forget,
    pair_contact_or_gap, pair_reach, skips, travel_step, wall_contact,
};
use fractum::fracture::break_plane::{self, Trigger};
use fractum::fracture::cohesion::{self, Demand, Spring};
use fractum::fracture::{
    Criterion, FractureParams, GrainLoad, PendingSplit, bond_split, criteria, grain_average_stress,
    grain_fails, split_grain,
};
use fractum::sample::{UNIFORM_COUNTERS, UNIFORMS_PER_COUNTER, uniforms};
use fractum::shape::{PolyEllipsoid, Shape};
use fractum::state::{Body, Vec3};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion};

use crate::FractumStatus::{self, *};

/// A grain as the kernels see it (SI, world frame).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumBody {
    /// Centre of mass (m).
    pub pos: [f64; 3],
    /// Velocity (m/s).
    pub vel: [f64; 3],
    /// Angular velocity (rad/s).
    pub omega: [f64; 3],
    /// Orientation: body (principal) frame to world, w x y z.
    pub quat: [f64; 4],
    /// Mass (kg).
    pub mass: f64,
    /// Bounding radius (m); a sphere's radius.
    pub radius: f64,
    /// Semi-axes a+ a- b+ b- c+ c- (m); a sphere: all = radius (not read).
    pub semi: [f64; 6],
    /// Octant origin in the body frame (m); a sphere: 0.
    pub origin: [f64; 3],
    /// Shape frame to body frame, w x y z; a sphere: 1 0 0 0.
    pub to_body: [f64; 4],
    /// Principal moments of inertia (kg m^2).
    pub inertia: [f64; 3],
    /// 1: a sphere, 0: a poly-ellipsoid (any nonzero value: a sphere).
    pub sphere: i32,
}

/// The folded constants of the Hertz-Mindlin kernel and which sub-models are on, as
/// `fractum_kernel_contact_law` makes them.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumContactLaw {
    /// 4/3 E* (Pa), E* = E / (2 (1 - nu^2)).
    pub four_thirds_e: f64,
    /// 2 E* (Pa).
    pub two_e: f64,
    /// The damping coefficient c (dimensionless; 0 without damping).
    pub damping: f64,
    /// 8 G* (Pa), G* = G / (2 (2 - nu)); 0 without friction.
    pub eight_g: f64,
    /// Coulomb friction coefficient (dimensionless; 0 without friction).
    pub mu: f64,
    /// Nonzero: the damping effect is on.
    pub damp: i32,
    /// Nonzero: the friction effect is on.
    pub friction: i32,
}

/// What a pair slot (or a wall candidate) remembers between evaluations: the tangential
/// displacement (m), the last contact normal (warm start; 0 0 0 when none) and the held
/// Hertz radius (m; 0 while not touching). 7 doubles: LAMMPS's per-contact history layout.
/// Start a new pair with all zeros.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumPairMemory {
    /// Tangential displacement (m).
    pub hist: [f64; 3],
    /// Last contact normal (unit, from B to A), 0 0 0 before the first contact.
    pub normal: [f64; 3],
    /// Held Hertz radius (m), 0 while not touching.
    pub radius: f64,
}

/// Where a body's shape sits in the world for one force evaluation: the octant origin (m)
/// and the rotation from the shape frame to the world, row by row (its columns are the shape
/// frame's x, y and z axes in world coordinates). `fractum_kernel_placement` computes it; a sphere's is
/// not read.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumPlacement {
    pub origin: [f64; 3],
    pub rot: [f64; 9],
}

/// Geometry of one contact.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumGeometry {
    /// Unit normal from B (or the wall) to A.
    pub normal: [f64; 3],
    /// Overlap (m), > 0.
    pub depth: f64,
    /// Contact point (m), midway between the two deepest points.
    pub point: [f64; 3],
    /// Deepest point of A into B (m).
    pub point_a: [f64; 3],
    /// Deepest point of B into A (m); for a wall, the foot of point_a on the plane.
    pub point_b: [f64; 3],
    /// Hertz equivalent radius (m).
    pub r_eff: f64,
    /// 1: touching; 0: separated (every other field 0).
    pub touching: i32,
}

/// One contact's force and what a record keeps (force on A; B, or the wall, gets the
/// opposite).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumContact {
    /// Force on A (N).
    pub force: [f64; 3],
    /// Torque on A about its centre of mass (N m).
    pub torque_a: [f64; 3],
    /// Torque on B about its centre of mass (N m); 0 against a wall.
    pub torque_b: [f64; 3],
    /// Contact point (m).
    pub point: [f64; 3],
    /// Unit normal from B (or the wall) to A.
    pub normal: [f64; 3],
    /// Normal force (N).
    pub normal_force: f64,
    /// Its elastic (Hertz) part 4/3 E* a delta (N): the force the contact tensile stress
    /// (Eq. 17, fractum_kernel_contact_tensile_stress) reads.
    pub hertz_force: f64,
    /// Hertz contact radius a (m).
    pub radius: f64,
    /// Normal contact stiffness 2 E* a (N/m).
    pub stiffness: f64,
    /// Elastic energy stored in the contact (J).
    pub energy: f64,
    /// Energy damping and sliding dissipated in this step (J).
    pub dissipated: f64,
    /// 1: in contact; 0: no contact, every other field 0.
    pub touching: i32,
}

/// Grain fracture constants (FractureParams, resolved).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumFractureLaw {
    /// Hoek-Brown m_i (dimensionless).
    pub mi: f64,
    /// Uniaxial compressive strength sigma_c (Pa).
    pub sigma_c: f64,
    /// Contact tensile strength sigma_fM (Pa).
    pub sigma_f: f64,
    /// Poisson's ratio of the grains (dimensionless).
    pub poisson: f64,
    /// Critical contacts that break a grain (3 to 64: fractum_kernel_fracture_range).
    pub critical_contacts: i32,
    /// Nonzero: a sphere first turns its principal directions to the ideal break plane.
    pub ideal_plane: i32,
    /// Nonzero: a sphere's break plane takes the random slight rotation.
    pub plane_jitter: i32,
    /// Springs per break plane, 0 without cohesion (else 3 to 16: fractum_kernel_fracture_range).
    pub springs: i32,
    /// Cohesive energy G_c (J/m^2), 0 without cohesion.
    pub gc: f64,
    /// Nonzero: a grain's Weibull factor scales sigma_c as well as sigma_f (a scene's
    /// `fracture.weibull_on = "both"`); 0: sigma_f only (`"contact"`, the paper's reading).
    pub weibull_sigma_c: i32,
}

/// Why a grain breaks. kind 0: it does not; 1: Hoek-Brown on its average stress (`stress`,
/// Pa, tension positive, row-major); 2: critical contacts (`normal`: the unit normal of the
/// plane through them). value: the stress that broke it (Pa; the largest principal
/// compression, or the largest contact tensile stress).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumTrigger {
    /// 0 none, 1 Hoek-Brown, 2 contacts.
    pub kind: i32,
    /// Average stress (Pa, tension positive, row-major); kind 1 only.
    pub stress: [f64; 9],
    /// Unit normal of the critical contacts' plane; kind 2 only.
    pub normal: [f64; 3],
    /// The stress that broke the grain (Pa).
    pub value: f64,
}

/// What a grain's contacts load it with, as Fractum's fracture check sums it
/// (`fractum::fracture::GrainLoad`; `fractum_kernel_grain_load_add` adds one contact): the
/// moment of the contact forces about its centre, 9 doubles row-major (N m), the number of
/// critical contacts, and the three largest (stress, Pa, and point, m), largest first. Start
/// from all zeros each evaluation.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumGrainLoad {
    pub moment: [f64; 9],
    pub count: i64,
    pub stress: [f64; 3],
    pub point: [[f64; 3]; 3],
}

/// A split made, waiting for the halves' forces to set its springs (world frame).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumPending {
    /// The parent's centre of mass (m).
    pub centroid: [f64; 3],
    /// The parent's acceleration (m/s^2).
    pub accel: [f64; 3],
    /// The parent's angular acceleration (rad/s^2).
    pub alpha: [f64; 3],
    /// The parent's angular velocity (rad/s).
    pub omega: [f64; 3],
    /// The spring points (m); the first `count` are used.
    pub points: [[f64; 3]; 16],
    /// Spring points (0 without cohesion; at most 16).
    pub count: i32,
    /// Area each spring stands for (m^2).
    pub area: f64,
}

/// A split: the axis of the parent's shape frame it splits normal to (-1: the shape forbids
/// breaking, nothing else set), the + half (which the parent becomes), the - half (a new
/// body) and the pending bond.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumSplit {
    /// 0, 1 or 2 (x, y, z of the parent's shape frame); -1: no split.
    pub axis: i32,
    /// The + half: the parent becomes it.
    pub plus: FractumBody,
    /// The - half: a new body.
    pub minus: FractumBody,
    /// What `fractum_kernel_bond` needs once the halves' forces are known.
    pub pending: FractumPending,
}

/// One cohesive spring between bodies A and B.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumSpring {
    /// The spring's end on A, in A's body frame (m).
    pub on_a: [f64; 3],
    /// The spring's end on B, in B's body frame (m).
    pub on_b: [f64; 3],
    /// Unit direction of the force on A, in A's body frame.
    pub direction: [f64; 3],
    /// Initial force f_i (N).
    pub f0: f64,
    /// Softening stiffness k (N/m).
    pub k: f64,
    /// Largest elongation reached (m).
    pub opening: f64,
    /// The ends' separation (A's end minus B's, world; m) at the last evaluation.
    pub last_gap: [f64; 3],
    /// The force on A at the last evaluation (N, world).
    pub last_force: [f64; 3],
    /// 1: broken for good.
    pub broken: i32,
}

type KResult = Result<(), FractumStatus>;

/// Runs a kernel: its error as the status, a panic as FRACTUM_ERR_INTERNAL. The last-error
/// message is not touched.
fn kernel(f: impl FnOnce() -> KResult) -> FractumStatus {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => FRACTUM_OK,
        Ok(Err(status)) => status,
        Err(_) => FRACTUM_ERR_INTERNAL,
    }
}

/// A NUL-terminated UTF-8 string argument.
fn c_str<'a>(p: *const std::ffi::c_char) -> Result<&'a str, FractumStatus> {
    if p.is_null() {
        return Err(FRACTUM_ERR_NULL);
    }
    // SAFETY: a non-null pointer from the caller is a NUL-terminated string (documented).
    unsafe { std::ffi::CStr::from_ptr(p) }
        .to_str()
        .map_err(|_| FRACTUM_ERR_INPUT)
}

fn input_if(bad: bool) -> KResult {
    if bad { Err(FRACTUM_ERR_INPUT) } else { Ok(()) }
}

fn get<'a, T>(p: *const T) -> Result<&'a T, FractumStatus> {
    // SAFETY: a non-null pointer from the caller points to a valid T (documented).
    unsafe { p.as_ref() }.ok_or(FRACTUM_ERR_NULL)
}

fn get_mut<'a, T>(p: *mut T) -> Result<&'a mut T, FractumStatus> {
    // SAFETY: as `get`, and the caller does not alias it during the call.
    unsafe { p.as_mut() }.ok_or(FRACTUM_ERR_NULL)
}

/// The `N` doubles at `p`.
fn doubles<'a, const N: usize>(p: *const f64) -> Result<&'a [f64; N], FractumStatus> {
    get(p.cast::<[f64; N]>())
}

fn doubles_mut<'a, const N: usize>(p: *mut f64) -> Result<&'a mut [f64; N], FractumStatus> {
    get_mut(p.cast::<[f64; N]>())
}

fn vec3_at(p: *const f64) -> Result<Vec3, FractumStatus> {
    Ok(Vec3::from(*doubles::<3>(p)?))
}

/// `n` points of 3 doubles (null allowed when `n` is 0), without copying.
fn points<'a>(p: *const [f64; 3], n: usize) -> Result<&'a [Vec3], FractumStatus> {
    const _: () = assert!(std::mem::size_of::<Vec3>() == std::mem::size_of::<[f64; 3]>());
    const _: () = assert!(std::mem::align_of::<Vec3>() == std::mem::align_of::<[f64; 3]>());
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(FRACTUM_ERR_NULL);
    }
    // SAFETY: the caller passes n points; nalgebra's Vector3<f64> is a #[repr(C)] matrix over
    // a #[repr(transparent)] [[f64; 3]; 1], the layout of [f64; 3] (size and alignment
    // checked above).
    Ok(unsafe { std::slice::from_raw_parts(p.cast::<Vec3>(), n) })
}

/// The caller's `n` elements at `p`, read only (null allowed when `n` is 0).
fn slice_in<'a, T>(p: *const T, n: usize) -> Result<&'a [T], FractumStatus> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(FRACTUM_ERR_NULL);
    }
    // SAFETY: the caller passes n elements, not written during the call.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// The caller's `n` elements at `p` (null allowed when `n` is 0).
fn slice_mut<'a, T>(p: *mut T, n: usize) -> Result<&'a mut [T], FractumStatus> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(FRACTUM_ERR_NULL);
    }
    // SAFETY: the caller passes room for n elements, not aliased during the call.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

fn quat(q: &[f64; 4]) -> UnitQuaternion<f64> {
    UnitQuaternion::new_unchecked(Quaternion::new(q[0], q[1], q[2], q[3]))
}

fn quat_out(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.w, q.i, q.j, q.k]
}

fn matrix(m: &[f64; 9]) -> Matrix3<f64> {
    Matrix3::from_row_slice(m)
}

fn matrix_out(m: &Matrix3<f64>) -> [f64; 9] {
    std::array::from_fn(|k| m[(k / 3, k % 3)])
}

/// The library's body from a FractumBody: the inverse mass and moments as the library makes
/// them (1/m); a poly-ellipsoid's semi-axes checked.
#[inline(always)]
fn body_in(b: &FractumBody) -> Result<Body, FractumStatus> {
    let shape = if b.sphere != 0 {
        Shape::Sphere
    } else {
        Shape::PolyEllipsoid {
            pe: PolyEllipsoid::new(b.semi).map_err(|_| FRACTUM_ERR_INPUT)?,
            origin: Vec3::from(b.origin),
            to_body: quat(&b.to_body),
        }
    };
    let inertia = Vec3::from(b.inertia);
    Ok(Body {
        pos: Vec3::from(b.pos),
        vel: Vec3::from(b.vel),
        omega: Vec3::from(b.omega),
        orientation: quat(&b.quat),
        radius: b.radius,
        mass: b.mass,
        inv_mass: 1.0 / b.mass,
        inertia,
        inv_inertia: inertia.map(|m| 1.0 / m),
        shape,
    })
}

/// A grain to split: a body whose radius and mass are finite and positive. A zero-radius
/// sphere split into zero semi-axes and panicked where the halves are built.
fn grain_in(b: &FractumBody) -> Result<Body, FractumStatus> {
    let sized = |x: f64| x.is_finite() && x > 0.0;
    input_if(!(sized(b.radius) && sized(b.mass)))?;
    body_in(b)
}

fn body_out(b: &Body) -> FractumBody {
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

fn consts(law: &FractumContactLaw) -> KernelConsts {
    KernelConsts {
        four_thirds_e: law.four_thirds_e,
        two_e: law.two_e,
        damping: law.damping,
        eight_g: law.eight_g,
        mu: law.mu,
    }
}

/// A candidate the library's bounding test rejects: it forgets what the library's kernel
/// would forget ([`forget`]) and touches nothing.
fn no_contact(
    law: &FractumContactLaw,
    shapes: i32,
    memory: &mut FractumPairMemory,
    out: &mut FractumContact,
) {
    let mut hist = Vec3::from(memory.hist);
    forget(
        &mut hist,
        &mut memory.radius,
        law.friction != 0,
        shapes != 0,
    );
    memory.hist = hist.into();
    *out = contact_out(None);
}

fn contact_out(p: Option<PairOut>) -> FractumContact {
    match p {
        None => FractumContact::default(),
        Some(p) => FractumContact {
            force: p.force.into(),
            torque_a: p.torque_i.into(),
            torque_b: p.torque_j.into(),
            point: p.point.into(),
            normal: p.normal.into(),
            normal_force: p.c.normal_force,
            hertz_force: p.c.hertz_force,
            radius: p.c.radius,
            stiffness: p.c.stiffness,
            energy: p.c.energy,
            dissipated: p.c.dissipated,
            touching: 1,
        },
    }
}

fn geometry_out(g: Option<ContactGeometry>) -> FractumGeometry {
    match g {
        None => FractumGeometry::default(),
        Some(g) => FractumGeometry {
            normal: g.normal.into(),
            depth: g.depth,
            point: g.point.into(),
            point_a: g.point_a.into(),
            point_b: g.point_b.into(),
            r_eff: g.r_eff,
            touching: 1,
        },
    }
}

/// Calls `$f::<DAMP, FRIC, POLY>(args)` for the runtime switches.
macro_rules! variants {
    ($damp:expr, $fric:expr, $poly:expr, $f:ident($($arg:expr),* $(,)?)) => {
        match ($damp, $fric, $poly) {
            (false, false, false) => $f::<false, false, false>($($arg),*),
            (true, false, false) => $f::<true, false, false>($($arg),*),
            (false, true, false) => $f::<false, true, false>($($arg),*),
            (true, true, false) => $f::<true, true, false>($($arg),*),
            (false, false, true) => $f::<false, false, true>($($arg),*),
            (true, false, true) => $f::<true, false, true>($($arg),*),
            (false, true, true) => $f::<false, true, true>($($arg),*),
            (true, true, true) => $f::<true, true, true>($($arg),*),
        }
    };
}

/// The contact law of grains of Young's modulus `young` (Pa) and Poisson's ratio `poisson`,
/// with viscous damping for the restitution coefficient `restitution` (in (0, 1]; read only
/// when `damping` is nonzero) and Mindlin friction of coefficient `mu` (read only when
/// `friction` is nonzero), as Fractum's `contact`, `damping` and `friction` effects fold it.
/// Against walls of another friction coefficient, make a second law with that `mu`.
/// Finding the damping coefficient integrates collisions: a few tens of milliseconds; make
/// the law once.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_contact_law(
    young: f64,
    poisson: f64,
    restitution: f64,
    mu: f64,
    damping: i32,
    friction: i32,
    out: *mut FractumContactLaw,
) -> FractumStatus {
    kernel(|| {
        let out = get_mut(out)?;
        let (damp, fric) = (damping != 0, friction != 0);
        input_if(damp && !(restitution > 0.0 && restitution <= 1.0))?;
        let hertz = Hertz::new(young, poisson);
        let d = damp.then(|| ViscousDamping::from_restitution(restitution));
        let m = fric.then(|| Mindlin::new(young, poisson, mu));
        let k = KernelConsts::new(&hertz, d.as_ref(), m.as_ref());
        *out = FractumContactLaw {
            four_thirds_e: k.four_thirds_e,
            two_e: k.two_e,
            damping: k.damping,
            eight_g: k.eight_g,
            mu: k.mu,
            damp: i32::from(damp),
            friction: i32::from(fric),
        };
        Ok(())
    })
}

/// The Hertz-Mindlin force on A for the overlap `delta` (m, > 0) along the unit normal `n`
/// (3 doubles, from B to A), Hertz radius `r_eff` (m), effective mass `m_eff` (kg; read with
/// damping), velocity `v` (3 doubles, m/s) of A's contact point relative to B's, and the
/// tangential displacement `hist` (3 doubles, m; read and updated with friction) over the
/// step `dt` (s); `update` = 0 only for a force evaluation that must not advance `hist`.
/// Fills force, normal_force, hertz_force, radius, stiffness, energy, dissipated and
/// touching = 1 of
/// `*out` (the rest 0).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_hertz_mindlin(
    law: *const FractumContactLaw,
    n: *const f64,
    delta: f64,
    r_eff: f64,
    m_eff: f64,
    v: *const f64,
    hist: *mut f64,
    dt: f64,
    update: i32,
    out: *mut FractumContact,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let (n, v) = (vec3_at(n)?, vec3_at(v)?);
        let hist = doubles_mut::<3>(hist)?;
        let out = get_mut(out)?;
        let k = consts(law);
        let mut h = Vec3::from(*hist);
        let update = update != 0;
        let c: ContactForce = match (law.damp != 0, law.friction != 0) {
            (false, false) => {
                hertz_mindlin::<false, false>(&k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update)
            }
            (true, false) => {
                hertz_mindlin::<true, false>(&k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update)
            }
            (false, true) => {
                hertz_mindlin::<false, true>(&k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update)
            }
            (true, true) => {
                hertz_mindlin::<true, true>(&k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update)
            }
        };
        *hist = h.into();
        *out = FractumContact {
            force: c.force.into(),
            normal_force: c.normal_force,
            hertz_force: c.hertz_force,
            radius: c.radius,
            stiffness: c.stiffness,
            energy: c.elastic_energy,
            dissipated: c.dissipated,
            touching: 1,
            ..FractumContact::default()
        };
        Ok(())
    })
}

/// The contact geometry of bodies `a` and `b` placed as Fractum places them (a sphere by its
/// radius about its centre), the search started from `guess` (3 doubles: a direction from B
/// to A of any length, e.g. the last normal or a's centre minus b's; 0 0 0: centroid to
/// centroid). `out->touching` = 0 when they are separated.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_convex_contact(
    a: *const FractumBody,
    b: *const FractumBody,
    guess: *const f64,
    out: *mut FractumGeometry,
) -> FractumStatus {
    kernel(|| {
        let (a, b) = (body_in(get(a)?)?, body_in(get(b)?)?);
        let guess = vec3_at(guess)?;
        let out = get_mut(out)?;
        let (va, vb) = (BodyView::new(&a), BodyView::new(&b));
        *out = geometry_out(convex::contact(&va.placed(), &vb.placed(), &guess));
        Ok(())
    })
}

/// The contact geometry of body `a` with the wall through `wall_point` (3 doubles, m) of unit
/// normal `wall_normal` (3 doubles, pointing out of the wall into the free side).
/// `out->touching` = 0 when `a` is clear of it.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_wall_geometry(
    a: *const FractumBody,
    wall_normal: *const f64,
    wall_point: *const f64,
    out: *mut FractumGeometry,
) -> FractumStatus {
    kernel(|| {
        let a = body_in(get(a)?)?;
        let (n, p) = (vec3_at(wall_normal)?, vec3_at(wall_point)?);
        let out = get_mut(out)?;
        *out = geometry_out(convex::wall_contact(&BodyView::new(&a).placed(), &n, &p));
        Ok(())
    })
}

/// The whole contact of the pair (a, b) as Fractum's contact effect computes it: the
/// bounding-sphere rejection; for two spheres (or with `shapes` = 0) the sphere formula, else
/// the convex contact warm-started from `memory->normal` with the Hertz radius held in
/// `memory->radius`; Hertz-Mindlin with the tangential displacement `memory->hist` (m) over
/// the step `dt` (s; `update` = 0 only for a force evaluation that must not advance it);
/// the torques, point and normal. The effective mass is m_a m_b / (m_a + m_b). `shapes` is
/// Fractum's poly-ellipsoid variant, nonzero when any grain of the run may be a
/// poly-ellipsoid: then a pair that is not two spheres takes the convex contact (two spheres
/// take the sphere formula either way).
/// `out->touching` = 0 when they do not touch (memory updated as Fractum does: hist and
/// radius reset).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_pair(
    law: *const FractumContactLaw,
    a: *const FractumBody,
    b: *const FractumBody,
    memory: *mut FractumPairMemory,
    dt: f64,
    update: i32,
    shapes: i32,
    out: *mut FractumContact,
) -> FractumStatus {
    kernel(|| pair_in(law, a, None, b, None, memory, dt, update, shapes, out))
}

/// `fractum_kernel_pair` with the bodies' placements given (`pa`, `pb`, as
/// `fractum_kernel_placement` computes them for `a` and `b` now), as the run places every body
/// once per force evaluation instead of once per pair: a caller with many pairs per body
/// places each body once. The same bits as `fractum_kernel_pair` with those placements; a
/// placement that is not the body's gives the contact of the body so placed.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_pair_placed(
    law: *const FractumContactLaw,
    a: *const FractumBody,
    pa: *const FractumPlacement,
    b: *const FractumBody,
    pb: *const FractumPlacement,
    memory: *mut FractumPairMemory,
    dt: f64,
    update: i32,
    shapes: i32,
    out: *mut FractumContact,
) -> FractumStatus {
    kernel(|| {
        let (pa, pb) = (get(pa)?, get(pb)?);
        pair_in(
            law,
            a,
            Some(pa),
            b,
            Some(pb),
            memory,
            dt,
            update,
            shapes,
            out,
        )
    })
}

/// Where Fractum places body `b`'s shape in the world for a force evaluation
/// (`Placement::of`): for `fractum_kernel_pair_placed`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_placement(
    b: *const FractumBody,
    out: *mut FractumPlacement,
) -> FractumStatus {
    kernel(|| {
        let b = body_in(get(b)?)?;
        let out = get_mut(out)?;
        let p = Placement::of(&b.pos, &b.orientation, &b.shape);
        *out = FractumPlacement {
            origin: p.origin.into(),
            rot: matrix_out(&p.rot),
        };
        Ok(())
    })
}

fn placement_in(p: &FractumPlacement) -> Placement {
    Placement {
        origin: Vec3::from(p.origin),
        rot: matrix(&p.rot),
    }
}

/// The C ABI's body as the contact kernels read it, without building a library `Body`: its
/// kinematics straight from the caller's struct, a poly-ellipsoid by its checked semi-axes and
/// the placement given, or else its own (the same bits as [`BodyView`] over `body_in` of it
/// with that placement).
struct RawBody<'a> {
    b: &'a FractumBody,
    pe: PolyEllipsoid,
    place: Option<&'a FractumPlacement>,
}

impl<'a> RawBody<'a> {
    /// `place` is read only for a poly-ellipsoid (`None`: placed as `Placement::of` places it).
    /// Refuses a poly-ellipsoid whose semi-axes are not finite and positive.
    #[inline(always)]
    fn new(b: &'a FractumBody, place: Option<&'a FractumPlacement>) -> Result<Self, FractumStatus> {
        let pe = if b.sphere != 0 {
            PolyEllipsoid::sphere(b.radius)
        } else {
            PolyEllipsoid::new(b.semi).map_err(|_| FRACTUM_ERR_INPUT)?
        };
        Ok(RawBody { b, pe, place })
    }
}

impl ContactBody for RawBody<'_> {
    #[inline(always)]
    fn pos(&self) -> Vec3 {
        Vec3::from(self.b.pos)
    }
    #[inline(always)]
    fn vel(&self) -> Vec3 {
        Vec3::from(self.b.vel)
    }
    #[inline(always)]
    fn omega(&self) -> Vec3 {
        Vec3::from(self.b.omega)
    }
    #[inline(always)]
    fn mass(&self) -> f64 {
        self.b.mass
    }
    #[inline(always)]
    fn radius(&self) -> f64 {
        self.b.radius
    }
    #[inline(always)]
    fn is_sphere(&self) -> bool {
        self.b.sphere != 0
    }
    #[inline(always)]
    fn placed(&self) -> Placed<'_> {
        if self.b.sphere != 0 {
            return Placed::sphere(self.b.radius, Vec3::from(self.b.pos));
        }
        let p = match self.place {
            Some(p) => placement_in(p),
            None => Placement::of(
                &Vec3::from(self.b.pos),
                &quat(&self.b.quat),
                &Shape::PolyEllipsoid {
                    pe: self.pe,
                    origin: Vec3::from(self.b.origin),
                    to_body: quat(&self.b.to_body),
                },
            ),
        };
        Placed::poly_ellipsoid(&self.pe, p.origin, p.rot)
    }
}

/// The contact of the pair (a, b), placed by `pa`, `pb` when given, as the run computes it:
/// the library's bounding test first (most candidates of a neighbour list do not touch: then
/// only what the library would forget, and the bounding spheres' gap), else the whole kernel
/// (`pair_contact_or_gap`: the contact, or the gap of a separated pair). `hist` and `m` are
/// the pair's memory.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn pair_of(
    law: &FractumContactLaw,
    k: &KernelConsts,
    a: &FractumBody,
    pa: Option<&FractumPlacement>,
    b: &FractumBody,
    pb: Option<&FractumPlacement>,
    hist: &mut Vec3,
    m: &mut PairMemory,
    dt: f64,
    update: bool,
    shapes: bool,
) -> Result<Result<PairOut, f64>, FractumStatus> {
    let (xa, xb) = (Vec3::from(a.pos), Vec3::from(b.pos));
    if bounds_apart(&xa, a.radius, &xb, b.radius) {
        forget(hist, &mut m.radius, law.friction != 0, shapes);
        return Ok(Err((xa - xb).norm() - (a.radius + b.radius)));
    }
    let (va, vb) = (RawBody::new(a, pa)?, RawBody::new(b, pb)?);
    Ok(variants!(
        law.damp != 0,
        law.friction != 0,
        shapes,
        pair_contact_or_gap(k, &va, &vb, hist, m, dt, update)
    ))
}

/// How far body `after` may have moved since it was `before` (the same body one drift
/// later; m), added to `*travel`: the centroid's path plus the bounding radius times a bound
/// on the angle turned, as Fractum's contact effect sums each body's motion for the
/// separated pairs' skip (`fractum::effects::contact::travel_step`). `fractum_kernel_pair_row`
/// reads the sums.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_travel(
    before: *const FractumBody,
    after: *const FractumBody,
    travel: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let (from, to) = (get(before)?, get(after)?);
        let travel = get_mut(travel)?;
        *travel += travel_step(
            &Vec3::from(from.pos),
            &quat(&from.quat),
            &Vec3::from(to.pos),
            &quat(&to.quat),
            to.radius,
        );
        Ok(())
    })
}

/// The contacts of one row of a neighbour list: body `i` of `bodies` (`n_bodies` of them) with
/// each of its `n` candidates `partners[k] & index_mask`, as `fractum_kernel_pair_placed` gives
/// them one by one, in one call. Each pair is computed with the body of the lower `keys` value
/// (a tag) as A, so a pair gives the same bits in whichever row it is found. `places` holds
/// every body's placement (`fractum_kernel_placement`; read with `shapes` on, may be null
/// without). `memory` holds the candidates' records, `stride` doubles apart: a
/// `FractumPairMemory` (7 doubles), then, with `travel` given, the pair's reach (1 double, 0
/// for a new pair; stride >= 8).
///
/// With `travel` (the bodies' summed motions, `fractum_kernel_travel`; null: off) and `shapes`
/// on, a pair found apart keeps the sum of the travels its bodies must reach before they can
/// touch, and is not searched until they do: Fractum's separated pairs' skip, which changes no
/// result (the search would find the pair apart again).
///
/// Writes the touching pairs to `out[0..*n_out]` with their candidate's index in `at` (both
/// with room for `n`), and, when `kept` is not null, `kept[k]` = 1 where candidate k's record
/// is not all zeros after the call (what a host keeps between neighbour builds).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_pair_row(
    law: *const FractumContactLaw,
    bodies: *const FractumBody,
    places: *const FractumPlacement,
    keys: *const i64,
    travel: *const f64,
    n_bodies: i32,
    i: i32,
    partners: *const i32,
    n: i32,
    index_mask: i32,
    memory: *mut f64,
    stride: i32,
    dt: f64,
    update: i32,
    shapes: i32,
    kept: *mut i32,
    out: *mut FractumContact,
    at: *mut i32,
    n_out: *mut i32,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let n_out = get_mut(n_out)?;
        *n_out = 0;
        input_if(n_bodies < 0 || n < 0 || i < 0 || i >= n_bodies)?;
        let (nb, n) = (n_bodies as usize, n as usize);
        let skip = !travel.is_null() && shapes != 0;
        input_if(stride < 7 || (skip && stride < 8))?;
        let stride = stride as usize;
        let bodies = slice_in(bodies, nb)?;
        let keys = slice_in(keys, nb)?;
        let places = if shapes != 0 {
            Some(slice_in(places, nb)?)
        } else {
            None
        };
        let travel = if skip {
            Some(slice_in(travel, nb)?)
        } else {
            None
        };
        let partners = slice_in(partners, n)?;
        let memory = slice_mut(memory, n * stride)?;
        let out = slice_mut(out, n)?;
        let at = slice_mut(at, n)?;
        let mut kept = if kept.is_null() {
            None
        } else {
            Some(slice_mut(kept, n)?)
        };
        let k = consts(law);
        let i = i as usize;
        let mut count = 0;
        for (jj, &p) in partners.iter().enumerate() {
            let j = (p & index_mask) as usize;
            input_if(j >= nb)?;
            let (a, b) = if keys[i] > keys[j] { (j, i) } else { (i, j) };
            let record = &mut memory[jj * stride..(jj + 1) * stride];
            let (ba, bb) = (&bodies[a], &bodies[b]);
            let touched = match travel {
                Some(t) if skips(record[7], t[a], t[b]) => None,
                _ => {
                    let mut hist = Vec3::new(record[0], record[1], record[2]);
                    let mut m = PairMemory {
                        normal: Vec3::new(record[3], record[4], record[5]),
                        radius: record[6],
                    };
                    let place = |x: usize| places.map(|ps| &ps[x]);
                    let result = pair_of(
                        law,
                        &k,
                        ba,
                        place(a),
                        bb,
                        place(b),
                        &mut hist,
                        &mut m,
                        dt,
                        update != 0,
                        shapes != 0,
                    )?;
                    record[..3].copy_from_slice(hist.as_slice());
                    record[3..6].copy_from_slice(m.normal.as_slice());
                    record[6] = m.radius;
                    if let Some(t) = travel {
                        record[7] = match result {
                            Ok(_) => 0.0,
                            Err(gap) => pair_reach(t[a], t[b], gap, ba.radius, bb.radius),
                        };
                    }
                    result.ok()
                }
            };
            if let Some(kept) = kept.as_deref_mut() {
                kept[jj] = i32::from(record.iter().any(|v| *v != 0.0));
            }
            if let Some(p) = touched {
                out[count] = contact_out(Some(p));
                at[count] = jj as i32;
                count += 1;
            }
        }
        *n_out = count as i32;
        Ok(())
    })
}

#[allow(clippy::too_many_arguments)]
fn pair_in(
    law: *const FractumContactLaw,
    a: *const FractumBody,
    pa: Option<&FractumPlacement>,
    b: *const FractumBody,
    pb: Option<&FractumPlacement>,
    memory: *mut FractumPairMemory,
    dt: f64,
    update: i32,
    shapes: i32,
    out: *mut FractumContact,
) -> KResult {
    let law = get(law)?;
    let (a, b) = (get(a)?, get(b)?);
    let memory = get_mut(memory)?;
    let out = get_mut(out)?;
    let mut hist = Vec3::from(memory.hist);
    let mut m = PairMemory {
        normal: Vec3::from(memory.normal),
        radius: memory.radius,
    };
    let p = pair_of(
        law,
        &consts(law),
        a,
        pa,
        b,
        pb,
        &mut hist,
        &mut m,
        dt,
        update != 0,
        shapes != 0,
    )?
    .ok();
    *memory = FractumPairMemory {
        hist: hist.into(),
        normal: m.normal.into(),
        radius: m.radius,
    };
    *out = contact_out(p);
    Ok(())
}

/// The contact of body `a` with the wall through `wall_point` (3 doubles, m) of unit normal
/// `wall_normal` (3 doubles, into the bodies' side) moving at `wall_velocity` (3 doubles,
/// m/s), as Fractum's contact effect computes it (with `shapes` nonzero a poly-ellipsoid's
/// wall contact, else the sphere's), with the candidate's tangential displacement
/// `memory->hist` (m) and held Hertz radius `memory->radius` (m; `memory->normal` is not
/// used) over the step `dt` (s). The wall gets the opposite force; `out->torque_b` is 0.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_wall(
    law: *const FractumContactLaw,
    a: *const FractumBody,
    wall_normal: *const f64,
    wall_point: *const f64,
    wall_velocity: *const f64,
    memory: *mut FractumPairMemory,
    dt: f64,
    update: i32,
    shapes: i32,
    out: *mut FractumContact,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let a = get(a)?;
        let (n, p, w) = (
            vec3_at(wall_normal)?,
            vec3_at(wall_point)?,
            vec3_at(wall_velocity)?,
        );
        let memory = get_mut(memory)?;
        let out = get_mut(out)?;
        if bound_off_wall(&Vec3::from(a.pos), a.radius, &n, &p) {
            no_contact(law, shapes, memory, out);
            return Ok(());
        }
        let a = body_in(a)?;
        let k = consts(law);
        let va = BodyView::new(&a);
        let mut hist = Vec3::from(memory.hist);
        let mut held = memory.radius;
        let c = variants!(
            law.damp != 0,
            law.friction != 0,
            shapes != 0,
            wall_contact(&k, &va, &n, &p, &w, &mut hist, &mut held, dt, update != 0)
        );
        memory.hist = hist.into();
        memory.radius = held;
        *out = contact_out(c);
        Ok(())
    })
}

/// A poly-ellipsoid of semi-axes `semi` (6 doubles, a+ a- b+ b- c+ c-, m; finite and > 0,
/// else FRACTUM_ERR_INPUT) and mass `mass` (kg) at rest, its centroid at `centroid` (3
/// doubles, m) and its shape frame turned by `shape_quat` (4 doubles, shape to world, w x y z),
/// as Fractum adds one: its body frame is its principal frame of inertia.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_poly_ellipsoid_body(
    semi: *const f64,
    mass: f64,
    centroid: *const f64,
    shape_quat: *const f64,
    out: *mut FractumBody,
) -> FractumStatus {
    kernel(|| {
        let semi = *doubles::<6>(semi)?;
        let centroid = vec3_at(centroid)?;
        let q = quat(doubles::<4>(shape_quat)?);
        let out = get_mut(out)?;
        let pe = PolyEllipsoid::new(semi).map_err(|_| FRACTUM_ERR_INPUT)?;
        *out = body_out(&Body::poly_ellipsoid(pe, mass, centroid, q));
        Ok(())
    })
}

/// The volume (m^3) of body `b`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_body_volume(
    b: *const FractumBody,
    volume: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let b = body_in(get(b)?)?;
        *get_mut(volume)? = b.volume();
        Ok(())
    })
}

/// The average stress of grain `b` (9 doubles out, Pa, tension positive, row-major; Eq.
/// 8-13) from the moment of its contact forces `moment` (9 doubles, row-major, N m: the sum
/// of force (x) (point - centre) over its contacts, force on b) and the torque `torque` on it
/// (3 doubles, N m), with the inertial terms of its angular acceleration and velocity.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_average_stress(
    b: *const FractumBody,
    moment: *const f64,
    torque: *const f64,
    stress: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let b = body_in(get(b)?)?;
        let moment = matrix(doubles::<9>(moment)?);
        let torque = vec3_at(torque)?;
        let stress = doubles_mut::<9>(stress)?;
        *stress = matrix_out(&grain_average_stress(&b, &moment, &torque));
        Ok(())
    })
}

/// The principal compressions of a stress (9 doubles, row-major, Pa, tension positive): 3
/// doubles out (Pa, compression positive, s1 >= s2 >= s3; of the symmetric part).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_principal_compressions(
    stress: *const f64,
    out: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let s = matrix(doubles::<9>(stress)?);
        *doubles_mut::<3>(out)? = criteria::principal_compression_values(&s);
        Ok(())
    })
}

/// `*fails` = 1 when Hoek-Brown fails at the principal compressions `s1` >= `s3` (Pa,
/// compression positive) for the strength `sigma_c` (Pa) and `mi`, else 0.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_hoek_brown_fails(
    s1: f64,
    s3: f64,
    sigma_c: f64,
    mi: f64,
    fails: *mut i32,
) -> FractumStatus {
    kernel(|| {
        *get_mut(fails)? = i32::from(criteria::hoek_brown_fails(s1, s3, sigma_c, mi));
        Ok(())
    })
}

/// The largest tensile stress (Pa) of a Hertz contact of elastic (Hertz) normal force
/// `normal_force` (N: a contact's `hertz_force`, not its damped total) and contact radius
/// `contact_radius` (m) for Poisson's ratio `poisson` (Eq. 17).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_contact_tensile_stress(
    normal_force: f64,
    contact_radius: f64,
    poisson: f64,
    stress: *mut f64,
) -> FractumStatus {
    kernel(|| {
        *get_mut(stress)? = criteria::contact_tensile_stress(normal_force, contact_radius, poisson);
        Ok(())
    })
}

/// The Weibull strength factor (dimensionless; Eq. 18) for the uniform variate `p` in (0, 1),
/// the Weibull modulus `w`, the grain's equivalent radius `x` (m) and the reference radius
/// `x_m` (m).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_weibull_factor(
    p: f64,
    w: f64,
    x: f64,
    x_m: f64,
    factor: *mut f64,
) -> FractumStatus {
    kernel(|| {
        *get_mut(factor)? = criteria::weibull_factor(p, w, x, x_m);
        Ok(())
    })
}

/// The unit normal (3 doubles out) of the plane through the `n` points (m; the
/// least-squares plane for more than 3); `*found` = 0 (normal 0 0 0) for fewer than 3 or
/// collinear points.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_contacts_plane_normal(
    points: *const [f64; 3],
    n: usize,
    normal: *mut f64,
    found: *mut i32,
) -> FractumStatus {
    kernel(|| {
        let pts = self::points(points, n)?;
        let normal = doubles_mut::<3>(normal)?;
        let found = get_mut(found)?;
        let nrm = break_plane::contacts_plane_normal(pts);
        *normal = nrm.unwrap_or_else(Vec3::zeros).into();
        *found = i32::from(nrm.is_some());
        Ok(())
    })
}

fn fracture_params(l: &FractumFractureLaw) -> Result<FractureParams, FractumStatus> {
    let within = |v: i32, (lo, hi): (usize, usize)| v >= 0 && (lo..=hi).contains(&(v as usize));
    let springs_ok = l.springs == 0 || within(l.springs, fractum::fracture::SPRINGS);
    input_if(!within(l.critical_contacts, fractum::fracture::CRITICAL_CONTACTS) || !springs_ok)?;
    Ok(FractureParams {
        mi: l.mi,
        sigma_c: l.sigma_c,
        sigma_f: l.sigma_f,
        weibull: None,
        weibull_sigma_c: l.weibull_sigma_c != 0,
        critical_contacts: l.critical_contacts as usize,
        cohesion: (l.springs > 0).then_some((l.gc, l.springs as usize)),
        ideal_plane: l.ideal_plane != 0,
        plane_jitter: l.plane_jitter != 0,
        poisson: l.poisson,
    })
}

fn trigger_out(t: Option<(Trigger, Criterion, f64)>) -> FractumTrigger {
    match t {
        None => FractumTrigger::default(),
        Some((Trigger::HoekBrown { stress }, _, value)) => FractumTrigger {
            kind: 1,
            stress: matrix_out(&stress),
            value,
            ..FractumTrigger::default()
        },
        Some((Trigger::Contacts { normal }, _, value)) => FractumTrigger {
            kind: 2,
            normal: normal.into(),
            value,
            ..FractumTrigger::default()
        },
    }
}

fn trigger_in(t: &FractumTrigger) -> Result<Trigger, FractumStatus> {
    match t.kind {
        1 => Ok(Trigger::HoekBrown {
            stress: matrix(&t.stress),
        }),
        2 => Ok(Trigger::Contacts {
            normal: Vec3::from(t.normal),
        }),
        _ => Err(FRACTUM_ERR_INPUT),
    }
}

/// Whether free grain `b` breaks, as Fractum checks it after a step: Hoek-Brown on its
/// average stress (of the contact moment `moment`, 9 doubles row-major, N m, and the torque
/// `torque`, 3 doubles, N m; see fractum_kernel_average_stress) with sigma_c, times its
/// Weibull factor `strength` (1 without Weibull statistics) where `law->weibull_sigma_c`;
/// else, when `n_critical` >=
/// `law->critical_contacts`, the critical contacts (those with a contact tensile stress above
/// `law->sigma_f * strength`) with `critical_points` their first min(n_critical, 3) points
/// (m, largest stress first; may be null when n_critical is 0) spanning a plane and
/// `top_stress` (Pa) the largest of their stresses. The caller sums the moment over a grain's
/// contacts (force on it (x) (point - centre)) and collects its critical contacts; Fractum
/// checks only grains with a nonzero moment that no spring holds. `out->kind` = 0: no break.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_check(
    law: *const FractumFractureLaw,
    b: *const FractumBody,
    strength: f64,
    moment: *const f64,
    torque: *const f64,
    n_critical: usize,
    critical_points: *const [f64; 3],
    top_stress: f64,
    out: *mut FractumTrigger,
) -> FractumStatus {
    kernel(|| {
        let p = fracture_params(get(law)?)?;
        let b = body_in(get(b)?)?;
        let moment = matrix(doubles::<9>(moment)?);
        let torque = vec3_at(torque)?;
        let pts = points(critical_points, n_critical.min(3))?;
        let out = get_mut(out)?;
        *out = trigger_out(grain_fails(
            &p, &b, strength, &moment, &torque, n_critical, pts, top_stress,
        ));
        Ok(())
    })
}

fn pending_out(s: &PendingSplit) -> FractumPending {
    FractumPending {
        centroid: s.centroid.into(),
        accel: s.accel.into(),
        alpha: s.alpha.into(),
        omega: s.omega.into(),
        points: s.points.map(Into::into),
        count: s.count as i32,
        area: s.area,
    }
}

fn pending_in(s: &FractumPending) -> Result<PendingSplit, FractumStatus> {
    input_if(!(0..=16).contains(&s.count))?;
    Ok(PendingSplit {
        a: 0,
        b: 0,
        centroid: Vec3::from(s.centroid),
        accel: Vec3::from(s.accel),
        alpha: Vec3::from(s.alpha),
        omega: Vec3::from(s.omega),
        points: s.points.map(Vec3::from),
        count: s.count as usize,
        area: s.area,
    })
}

/// The allowed range (inclusive) of the counting fracture key named `key` (a NUL-terminated
/// string: "critical_contacts" or "springs"), the one Fractum's scene checks and kernels use
/// (`fractum::fracture::key_range`): written to `*lo`, `*hi`. FRACTUM_ERR_INPUT for another
/// name.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_fracture_range(
    key: *const std::ffi::c_char,
    lo: *mut f64,
    hi: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let name = c_str(key)?;
        let (a, b) = fractum::fracture::key_range(name).ok_or(FRACTUM_ERR_INPUT)?;
        let (lo, hi) = (get_mut(lo)?, get_mut(hi)?);
        *lo = a as f64;
        *hi = b as f64;
        Ok(())
    })
}

/// Adds one contact to grain load `load`, as Fractum's check adds it
/// (`fractum::fracture::GrainLoad::add`): the force `force` on the grain (3 doubles, N) at
/// `point` (m) to the moment about the grain's centre `centre` (m), and, when the contact
/// tensile stress of its Hertz force `hertz_force` (N) and radius `radius` (m) at Poisson's
/// ratio `poisson` is above `threshold` (Pa: sigma_f times the grain's Weibull factor), to
/// its critical contacts. A host adds a grain's contacts in the order Fractum would (the
/// moment is a sum: its last bits follow the order).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_grain_load_add(
    load: *mut FractumGrainLoad,
    centre: *const f64,
    force: *const f64,
    point: *const f64,
    hertz_force: f64,
    radius: f64,
    poisson: f64,
    threshold: f64,
) -> FractumStatus {
    kernel(|| {
        let l = get_mut(load)?;
        input_if(l.count < 0)?;
        let (centre, force, point) = (vec3_at(centre)?, vec3_at(force)?, vec3_at(point)?);
        let mut g = GrainLoad {
            moment: matrix(&l.moment),
            count: l.count as usize,
            stress: l.stress,
            point: l.point.map(Vec3::from),
        };
        g.add(
            &centre,
            &force,
            &point,
            hertz_force,
            radius,
            poisson,
            threshold,
        );
        l.moment = matrix_out(&g.moment);
        l.count = g.count as i64;
        l.stress = g.stress;
        l.point = g.point.map(Into::into);
        Ok(())
    })
}

/// The Weibull factor of grain `grain` (its identity: 1 + its index in Fractum's bodies, the
/// atom ID of `fractum export lammps --plugin`) after `generation` splits, as Fractum's run
/// draws it (`fractum::fracture::grain_strength`, keyed by `seed`, grain and generation): of
/// the body `b`'s volume, with Weibull modulus `w` and reference size `x_m` (m).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_grain_strength(
    seed: u64,
    grain: u64,
    generation: u32,
    b: *const FractumBody,
    w: f64,
    x_m: f64,
    factor: *mut f64,
) -> FractumStatus {
    kernel(|| {
        input_if(!(w > 0.0 && x_m > 0.0))?;
        let volume = body_in(get(b)?)?.volume();
        *get_mut(factor)? =
            fractum::fracture::grain_strength(seed, grain, generation, volume, w, x_m);
        Ok(())
    })
}

/// The angles (3 doubles, rad) of the slight random rotation of sphere `grain`'s ideal break
/// plane at its split after `generation` splits, as Fractum's run draws them
/// (`fractum::fracture::grain_jitter`), for fractum_kernel_split's `jitter`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_grain_jitter(
    seed: u64,
    grain: u64,
    generation: u32,
    angles: *mut f64,
) -> FractumStatus {
    kernel(|| {
        *doubles_mut::<3>(angles)? = fractum::fracture::grain_jitter(seed, grain, generation);
        Ok(())
    })
}

/// Splits grain `parent`, which carries the force `force` (3 doubles, N) and torque `torque`
/// (3 doubles, N m), for the reason `trigger` (kind 1 or 2, from fractum_kernel_check), as
/// Fractum splits it: the break plane (a sphere first turns to the ideal plane with
/// `law->ideal_plane`, and with `law->plane_jitter` by the slight rotation of the angles
/// `jitter`, 3 doubles in rad from fractum_kernel_jitter_angles; NULL: no rotation), the two
/// halves moving as the parent did, and the pending bond (the parent's acceleration force x
/// (1 / mass), angular acceleration, centroid and angular velocity, and with cohesion
/// (`law->springs` > 0) the spring points on the break plane and the area each stands for). `out->axis` = -1
/// when the grain's shape forbids breaking. FRACTUM_ERR_INPUT when the parent's radius or mass
/// is not finite and positive.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_split(
    law: *const FractumFractureLaw,
    parent: *const FractumBody,
    force: *const f64,
    torque: *const f64,
    trigger: *const FractumTrigger,
    jitter: *const f64,
    out: *mut FractumSplit,
) -> FractumStatus {
    kernel(|| {
        let p = fracture_params(get(law)?)?;
        let parent = grain_in(get(parent)?)?;
        let (force, torque) = (vec3_at(force)?, vec3_at(torque)?);
        let trigger = trigger_in(get(trigger)?)?;
        let jitter = if jitter.is_null() {
            None
        } else {
            Some(*doubles::<3>(jitter)?)
        };
        let out = get_mut(out)?;
        *out = match split_grain(&p, &parent, &force, &torque, &trigger, jitter) {
            None => FractumSplit {
                axis: -1,
                ..FractumSplit::default()
            },
            Some(s) => FractumSplit {
                axis: s.axis as i32,
                plus: body_out(&s.plus),
                minus: body_out(&s.minus),
                pending: pending_out(&s.pending),
            },
        };
        Ok(())
    })
}

/// The angles (3 doubles out, rad) of a sphere's random slight break-plane rotation from 6
/// uniform variates `u` in [0, 1]: per angle k the magnitude `theta_max (0.5 + 0.5 u[2k])`
/// (theta_max = atan(1/5)), positive when `u[2k+1] >= 0.5`, else negative. Fractum draws the
/// six from its fracture stream (per angle: a 53-bit uniform, then a 32-bit word / 2^32); a
/// host may take them from fractum_kernel_uniforms.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_jitter_angles(u: *const f64, angles: *mut f64) -> FractumStatus {
    kernel(|| {
        let u = doubles::<6>(u)?;
        *doubles_mut::<3>(angles)? = break_plane::jitter_angles(u);
        Ok(())
    })
}

/// `n` uniform variates in (0, 1] (53 bits each) into `out` from the ChaCha8 stream `key` of
/// `seed` (seeded as Fractum's scene streams), starting at word `counter` * 2^32: the same
/// (seed, key, counter) always gives the same numbers, on any rank. `counter` < 2^36 and
/// `n` <= 2^31, else FRACTUM_ERR_INPUT; `out` may be null when `n` is 0.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_uniforms(
    seed: u64,
    key: u64,
    counter: u64,
    n: usize,
    out: *mut f64,
) -> FractumStatus {
    kernel(|| {
        input_if(counter >= UNIFORM_COUNTERS || n > UNIFORMS_PER_COUNTER)?;
        uniforms(seed, key, counter, slice_mut(out, n)?);
        Ok(())
    })
}

fn spring_out(s: &Spring) -> FractumSpring {
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

fn spring_in(s: &FractumSpring) -> Spring {
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

/// The cohesive springs of one split (Eq. 39-43), as Fractum makes them once the halves'
/// forces are known: `a` is the + half (the parent's body), `b` the - half, `force_a`,
/// `torque_a`, `force_b`, `torque_b` (3 doubles each, N and N m) the forces and torques on
/// them after the split, `pending` the split's pending bond. Their initial forces make each
/// half accelerate and turn as the parent did; a spring with no force is not made. Writes
/// the `*made` springs to `springs` (room for 16; the rest zeroed); none without cohesion
/// (`law->springs` = 0). Springs come in the order of `pending->points`, skipping any that
/// would carry no force (|f| <= 1e-12 (|demand on a| + |demand on b|)): when `*made` equals
/// `pending->count`, spring k sits at `pending->points[k]`. The caller applies each spring's
/// initial force at once, as Fractum does: `last_force` on a at the spring's point (torque
/// (point - a's centre) x force) and its opposite on b (torque -(point - b's centre) x
/// force); Fractum takes the point as `pending->points[k] - a's centre` (then + a's centre
/// for b's lever), a's centre + q_a on_a agrees with it to round-off.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_bond(
    law: *const FractumFractureLaw,
    a: *const FractumBody,
    b: *const FractumBody,
    force_a: *const f64,
    torque_a: *const f64,
    force_b: *const f64,
    torque_b: *const f64,
    pending: *const FractumPending,
    springs: *mut FractumSpring,
    made: *mut i32,
) -> FractumStatus {
    kernel(|| {
        let law = get(law)?;
        let p = fracture_params(law)?;
        let (a, b) = (body_in(get(a)?)?, body_in(get(b)?)?);
        let loads = [
            vec3_at(force_a)?,
            vec3_at(torque_a)?,
            vec3_at(force_b)?,
            vec3_at(torque_b)?,
        ];
        let pending = pending_in(get(pending)?)?;
        let springs = get_mut(springs.cast::<[FractumSpring; 16]>())?;
        let made = get_mut(made)?;
        *springs = [FractumSpring::default(); 16];
        let mut count = 0;
        if let Some((gc, _)) = p.cohesion {
            let [fa, ta, fb, tb] = &loads;
            bond_split(gc, &a, &b, [fa, ta, fb, tb], &pending, |m| {
                springs[count] = spring_out(&m.spring);
                count += 1;
            });
        }
        *made = count as i32;
        Ok(())
    })
}

/// The initial spring forces (`n` x 3 doubles out, N, on A; B gets the opposite) that meet
/// a split's demand with the least squares, for springs at `points` (`n` x 3 doubles, m,
/// relative to A's centre of mass): `demand` is 15 doubles, force_a torque_a force_b
/// torque_b b_offset (N, N m, N, N m, m; what A needs from B, what B needs from A about its
/// own centre, and B's centre relative to A's).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_spring_initial_forces(
    points: *const [f64; 3],
    n: usize,
    demand: *const f64,
    forces: *mut [f64; 3],
) -> FractumStatus {
    kernel(|| {
        let pts = self::points(points, n)?;
        let d = doubles::<15>(demand)?;
        let v = |k: usize| Vec3::new(d[3 * k], d[3 * k + 1], d[3 * k + 2]);
        let demand = Demand {
            force_a: v(0),
            torque_a: v(1),
            force_b: v(2),
            torque_b: v(3),
            b_offset: v(4),
        };
        let out = slice_mut(forces, n)?;
        let f = cohesion::initial_forces(pts, &demand);
        for (o, x) in out.iter_mut().zip(&f) {
            *o = (*x).into();
        }
        Ok(())
    })
}

/// One evaluation of spring `s` between bodies `a` and `b` (of which it uses the positions and
/// orientations), as Fractum evaluates it each step: its largest elongation, its
/// force on a (`force_a`, 3 doubles, N; b gets the opposite), the torques on a and b about
/// their centres (`torque_a`, `torque_b`, 3 doubles each, N m), and the work it did on the
/// pair since the last evaluation (`*work`, J). When its force has fallen to zero the spring
/// breaks for good: `s->broken` = 1, `*broke` = 1, forces and torques 0. A spring already
/// broken does nothing (all 0, `*broke` = 0).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn fractum_kernel_spring(
    s: *mut FractumSpring,
    a: *const FractumBody,
    b: *const FractumBody,
    force_a: *mut f64,
    torque_a: *mut f64,
    torque_b: *mut f64,
    work: *mut f64,
    broke: *mut i32,
) -> FractumStatus {
    kernel(|| {
        let s = get_mut(s)?;
        let (a, b) = (body_in(get(a)?)?, body_in(get(b)?)?);
        let force_a = doubles_mut::<3>(force_a)?;
        let torque_a = doubles_mut::<3>(torque_a)?;
        let torque_b = doubles_mut::<3>(torque_b)?;
        let (work, broke) = (get_mut(work)?, get_mut(broke)?);
        let mut spring = spring_in(s);
        let act = if spring.broken {
            Default::default()
        } else {
            spring.act(&a.pos, &a.orientation, &b.pos, &b.orientation)
        };
        *s = spring_out(&spring);
        *force_a = act.force.into();
        *torque_a = act.torque_a.into();
        *torque_b = act.torque_b.into();
        *work = act.work;
        *broke = i32::from(act.broke);
        Ok(())
    })
}

/// `*can` = 1 when grain `b` can break along some plane, 0 when its shape forbids breaking
/// whatever triggers it (`fracture::break_plane::shape_forbids_breaking`: two or three bad
/// semi-axis ratios, Section 3.3.3), so that `fractum_kernel_split` would return axis -1: a
/// host that must prepare a split (LAMMPS: a reneighbouring) asks first. A sphere can.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_can_break(b: *const FractumBody, can: *mut i32) -> FractumStatus {
    kernel(|| {
        let b = body_in(get(b)?)?;
        let can = get_mut(can)?;
        *can = i32::from(!fractum::fracture::break_plane::shape_forbids_breaking(
            &b.shape.semi_axes(b.radius),
        ));
        Ok(())
    })
}

/// Velocity Verlet's first half kick and drift of one grain over `dt` (s), as Fractum's
/// integrator moves each body (`velocity_verlet::kick_drift_body`, orientations tracked):
/// `b`'s velocity, position, angular velocity and orientation advance under `force` (3
/// doubles, N) and `torque` (3 doubles, N m, world).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_kick_drift(
    b: *mut FractumBody,
    force: *const f64,
    torque: *const f64,
    dt: f64,
) -> FractumStatus {
    kernel(|| {
        let (force, torque) = (vec3_at(force)?, vec3_at(torque)?);
        let b = get_mut(b)?;
        let mut body = body_in(b)?;
        fractum::integrate::velocity_verlet::kick_drift_body(
            &mut body.pos,
            &mut body.vel,
            &mut body.omega,
            &mut body.orientation,
            &force,
            &torque,
            body.inv_mass,
            &body.inv_inertia,
            dt,
            true,
        );
        b.pos = body.pos.into();
        b.vel = body.vel.into();
        b.omega = body.omega.into();
        b.quat = quat_out(&body.orientation);
        Ok(())
    })
}

/// One contact's share of body `a`'s row in Fractum's frequency bound (rad²/s²), as its step
/// adaptation sums it (`effects::contact::frequency_share` of the `contact_load`s): the
/// contact `c` (its point, normal and stiffness) under `law` (friction adds the tangential
/// spring) loads `a` (its centre, orientation, mass and principal moments are read) and its
/// partner `b` (NULL for a wall). A body's row sums the shares of its contacts, walls
/// included; the bound is sqrt of the largest row: see `fractum_kernel_adapted_step`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_frequency_share(
    law: *const FractumContactLaw,
    c: *const FractumContact,
    a: *const FractumBody,
    b: *const FractumBody,
    share: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let (law, c, a) = (get(law)?, get(c)?, get(a)?);
        let b = if b.is_null() { None } else { Some(get(b)?) };
        let share = get_mut(share)?;
        let own = body_load(law, c, a)?;
        let other = b.map(|b| body_load(law, c, b)).transpose()?;
        *share = fractum::effects::contact::frequency_share(own, other);
        Ok(())
    })
}

/// `fractum_kernel_frequency_share` for both bodies of a pair contact `c` at once, each
/// body's load computed once (as Fractum's own estimate does per contact): `share_a` the
/// contact's share of `a`'s row, `share_b` of `b`'s; the same bits as two calls.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_frequency_shares(
    law: *const FractumContactLaw,
    c: *const FractumContact,
    a: *const FractumBody,
    b: *const FractumBody,
    share_a: *mut f64,
    share_b: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let (law, c, a, b) = (get(law)?, get(c)?, get(a)?, get(b)?);
        let (share_a, share_b) = (get_mut(share_a)?, get_mut(share_b)?);
        let (la, lb) = (body_load(law, c, a)?, body_load(law, c, b)?);
        *share_a = fractum::effects::contact::frequency_share(la, Some(lb));
        *share_b = fractum::effects::contact::frequency_share(lb, Some(la));
        Ok(())
    })
}

/// Contact `c`'s load on `body` (`fractum::effects::contact::contact_load`), its mass and
/// moments checked positive.
fn body_load(
    law: &FractumContactLaw,
    c: &FractumContact,
    body: &FractumBody,
) -> Result<f64, FractumStatus> {
    let tangential = if law.friction != 0 {
        fractum::effects::contact::tangential_ratio(law.eight_g, law.two_e)
    } else {
        0.0
    };
    let inertia = Vec3::from(body.inertia);
    // NaN fails every comparison: refused with the non-positive values.
    let positive = |v: f64| v > 0.0;
    input_if(!positive(body.mass) || !inertia.iter().all(|&m| positive(m)))?;
    Ok(fractum::effects::contact::contact_load(
        &Vec3::from(c.point),
        &Vec3::from(c.normal),
        c.stiffness,
        &Vec3::from(body.pos),
        &quat(&body.quat),
        1.0 / body.mass,
        &inertia.map(|m| 1.0 / m),
        tangential,
    ))
}

/// Fractum's step adaptation for fracture runs (`granular::adapted_step`): with `sum` the
/// largest row of the frequency bound (`fractum_kernel_frequency_share` summed over a body's
/// contacts) over all bodies, `*next` = the step to take after `dt` (s): `dt` shortened so
/// that `omega dt` is `target` when it is above that (omega = sqrt(sum)), else `dt` unchanged.
/// Fractum's target is 3 x `time.safety` (`granular::ADAPT_PER_SAFETY`: 0.6 at the default
/// 0.2); it checks every output step and after every split.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_adapted_step(
    sum: f64,
    dt: f64,
    target: f64,
    next: *mut f64,
) -> FractumStatus {
    kernel(|| {
        let valid = sum >= 0.0 && dt > 0.0 && target > 0.0; // false for NaN too
        input_if(!valid)?;
        let omega = fractum::effects::contact::frequency_bound(sum);
        *get_mut(next)? = fractum::models::granular::adapted_step(omega, dt, target).unwrap_or(dt);
        Ok(())
    })
}

/// Fractum's check of a step against its contacts, as its granular run makes it: with `sum`
/// the largest row of the frequency bound over all bodies (as for
/// `fractum_kernel_adapted_step`), `*omega_dt` = omega dt and `*verdict` = 2 when the step is
/// unstable (`granular::step_verdict`: omega dt above 2, the run stops), 1 when contacts are
/// resolved by few steps (above 1.6: a warning), else 0.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_step_check(
    sum: f64,
    dt: f64,
    omega_dt: *mut f64,
    verdict: *mut i32,
) -> FractumStatus {
    kernel(|| {
        input_if(!(sum >= 0.0 && dt > 0.0 && dt.is_finite()))?;
        let (omega_dt, verdict) = (get_mut(omega_dt)?, get_mut(verdict)?);
        *omega_dt = fractum::effects::contact::frequency_bound(sum) * dt;
        use fractum::models::granular::{StepVerdict, step_verdict};
        *verdict = match step_verdict(*omega_dt) {
            StepVerdict::Fine => 0,
            StepVerdict::Coarse => 1,
            StepVerdict::Unstable => 2,
        };
        Ok(())
    })
}

/// Velocity Verlet's second half kick of one grain (`velocity_verlet::kick_body`): `b`'s
/// velocity and angular velocity advance over `dt`/2 under `force` and `torque`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_kick(
    b: *mut FractumBody,
    force: *const f64,
    torque: *const f64,
    dt: f64,
) -> FractumStatus {
    kernel(|| {
        let (force, torque) = (vec3_at(force)?, vec3_at(torque)?);
        let b = get_mut(b)?;
        let mut body = body_in(b)?;
        fractum::integrate::velocity_verlet::kick_body(
            &mut body.vel,
            &mut body.omega,
            &body.orientation,
            &force,
            &torque,
            body.inv_mass,
            &body.inv_inertia,
            dt,
            true,
        );
        b.vel = body.vel.into();
        b.omega = body.omega.into();
        Ok(())
    })
}

/// The cohesive energy G_c = K_Ic² (1 − ν²) / E (J/m², Eq. 38) of a material of toughness
/// `toughness` (Pa m^0.5), Young's modulus `young` (Pa) and Poisson's ratio `poisson`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_kernel_cohesive_energy(
    toughness: f64,
    young: f64,
    poisson: f64,
    gc: *mut f64,
) -> FractumStatus {
    kernel(|| {
        input_if(!(toughness > 0.0 && young > 0.0 && poisson.is_finite()))?;
        *get_mut(gc)? = cohesion::cohesive_energy(toughness, young, poisson);
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    //! Every export against the library function it wraps, called directly on the run's own
    //! data (Bodies, placements): the same bits.

    use super::*;
    use fractum::effects::contact::pair_contact;
    use fractum::effects::contact::{BodyAt, Placement};
    use fractum::fracture::MadeSpring;
    use fractum::state::Bodies;
    use std::ptr::{null, null_mut};

    /// Seeded variates from the library's keyed stream.
    struct Draw {
        seed: u64,
        counter: u64,
    }

    impl Draw {
        fn new(seed: u64) -> Self {
            Draw { seed, counter: 0 }
        }
        fn u(&mut self) -> f64 {
            let mut x = [0.0];
            uniforms(self.seed, 1, self.counter, &mut x);
            self.counter += 1;
            x[0]
        }
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.u()
        }
        fn vec(&mut self, s: f64) -> Vec3 {
            Vec3::new(self.range(-s, s), self.range(-s, s), self.range(-s, s))
        }
        fn unit(&mut self) -> Vec3 {
            loop {
                let v = self.vec(1.0);
                let n = v.norm();
                if n > 0.1 && n <= 1.0 {
                    return v / n;
                }
            }
        }
        fn quat(&mut self) -> UnitQuaternion<f64> {
            UnitQuaternion::from_scaled_axis(self.vec(3.0))
        }
        fn flag(&mut self) -> bool {
            self.u() < 0.5
        }
    }

    /// A random grain in motion: a sphere, or a poly-ellipsoid of six different semi-axes
    /// (so its principal frame is not its shape frame).
    fn random_body(d: &mut Draw, sphere: bool) -> Body {
        let at = d.vec(1e-3);
        let mut b = if sphere {
            let mut bodies = Bodies::default();
            bodies.push_sphere(at, d.range(0.5e-3, 1e-3), 2650.0, d.quat());
            bodies.body(0)
        } else {
            let semi = std::array::from_fn(|_| d.range(0.35e-3, 1e-3));
            let pe = PolyEllipsoid::new(semi).unwrap();
            Body::poly_ellipsoid(pe, 2650.0 * pe.volume(), at, d.quat())
        };
        b.vel = d.vec(2.0);
        b.omega = d.vec(2000.0);
        b
    }

    /// The C form of a library body, field by field.
    fn fb(b: &Body) -> FractumBody {
        let q = |q: &UnitQuaternion<f64>| [q.w, q.i, q.j, q.k];
        let mut out = FractumBody {
            pos: [b.pos.x, b.pos.y, b.pos.z],
            vel: [b.vel.x, b.vel.y, b.vel.z],
            omega: [b.omega.x, b.omega.y, b.omega.z],
            quat: q(&b.orientation),
            mass: b.mass,
            radius: b.radius,
            semi: [b.radius; 6],
            origin: [0.0; 3],
            to_body: [1.0, 0.0, 0.0, 0.0],
            inertia: [b.inertia.x, b.inertia.y, b.inertia.z],
            sphere: 1,
        };
        if let Shape::PolyEllipsoid {
            pe,
            origin,
            to_body,
        } = &b.shape
        {
            out.semi = pe.semi;
            out.origin = [origin.x, origin.y, origin.z];
            out.to_body = q(to_body);
            out.sphere = 0;
        }
        out
    }

    fn bits(x: &[f64]) -> Vec<u64> {
        x.iter().map(|v| v.to_bits()).collect()
    }

    fn vb(v: &Vec3) -> Vec<u64> {
        bits(v.as_slice())
    }

    fn body_bits(b: &FractumBody) -> Vec<u64> {
        let mut v = Vec::new();
        for x in [&b.pos[..], &b.vel, &b.omega, &b.quat, &[b.mass, b.radius]] {
            v.extend(bits(x));
        }
        for x in [&b.semi[..], &b.origin, &b.to_body, &b.inertia] {
            v.extend(bits(x));
        }
        v.push(b.sphere as u64);
        v
    }

    fn spring_bits(s: &FractumSpring) -> Vec<u64> {
        let mut v = Vec::new();
        for x in [&s.on_a[..], &s.on_b, &s.direction, &[s.f0, s.k, s.opening]] {
            v.extend(bits(x));
        }
        v.extend(bits(&s.last_gap));
        v.extend(bits(&s.last_force));
        v.push(s.broken as u64);
        v
    }

    fn same_contact(out: &FractumContact, p: &Option<PairOut>) {
        match p {
            None => assert_eq!(*out, FractumContact::default()),
            Some(p) => {
                assert_eq!(out.touching, 1);
                assert_eq!(bits(&out.force), vb(&p.force));
                assert_eq!(bits(&out.torque_a), vb(&p.torque_i));
                assert_eq!(bits(&out.torque_b), vb(&p.torque_j));
                assert_eq!(bits(&out.point), vb(&p.point));
                assert_eq!(bits(&out.normal), vb(&p.normal));
                let c = &p.c;
                assert_eq!(
                    bits(&[
                        out.normal_force,
                        out.hertz_force,
                        out.radius,
                        out.stiffness,
                        out.energy,
                        out.dissipated
                    ]),
                    bits(&[
                        c.normal_force,
                        c.hertz_force,
                        c.radius,
                        c.stiffness,
                        c.energy,
                        c.dissipated
                    ])
                );
            }
        }
    }

    fn same_geometry(out: &FractumGeometry, g: &Option<ContactGeometry>) {
        match g {
            None => assert_eq!(*out, FractumGeometry::default()),
            Some(g) => {
                assert_eq!(out.touching, 1);
                assert_eq!(bits(&out.normal), vb(&g.normal));
                assert_eq!(bits(&out.point), vb(&g.point));
                assert_eq!(bits(&out.point_a), vb(&g.point_a));
                assert_eq!(bits(&out.point_b), vb(&g.point_b));
                assert_eq!(bits(&[out.depth, out.r_eff]), bits(&[g.depth, g.r_eff]));
            }
        }
    }

    const YOUNG: f64 = 60e9;
    const POISSON: f64 = 0.17;

    /// The export's law and the library's constants for the switches.
    fn laws(damp: bool, fric: bool, mu: f64) -> (FractumContactLaw, KernelConsts) {
        let mut law = FractumContactLaw::default();
        let s = fractum_kernel_contact_law(
            YOUNG,
            POISSON,
            0.6,
            mu,
            i32::from(damp),
            i32::from(fric),
            &mut law,
        );
        assert_eq!(s, FRACTUM_OK);
        let k = KernelConsts::new(
            &Hertz::new(YOUNG, POISSON),
            damp.then(|| ViscousDamping::from_restitution(0.6)).as_ref(),
            fric.then(|| Mindlin::new(YOUNG, POISSON, mu)).as_ref(),
        );
        (law, k)
    }

    const SWITCHES: [(bool, bool, bool); 8] = [
        (false, false, false),
        (true, false, false),
        (false, true, false),
        (true, true, false),
        (false, false, true),
        (true, false, true),
        (false, true, true),
        (true, true, true),
    ];

    /// The run's view of two bodies: in a Bodies, placed once per evaluation.
    fn run_pair(a: &Body, b: &Body) -> (Bodies, Vec<Placement>) {
        let mut bodies = Bodies::default();
        bodies.push(*a);
        bodies.push(*b);
        let placements = (0..2)
            .map(|i| Placement::of(&bodies.pos[i], &bodies.orientation[i], &bodies.shape[i]))
            .collect();
        (bodies, placements)
    }

    #[test]
    fn contact_law_folds_the_library_constants() {
        for (damp, fric) in [(false, false), (true, false), (false, true), (true, true)] {
            let (law, k) = laws(damp, fric, 0.35);
            assert_eq!(
                bits(&[
                    law.four_thirds_e,
                    law.two_e,
                    law.damping,
                    law.eight_g,
                    law.mu
                ]),
                bits(&[k.four_thirds_e, k.two_e, k.damping, k.eight_g, k.mu])
            );
            assert_eq!((law.damp, law.friction), (damp as i32, fric as i32));
        }
        let mut law = FractumContactLaw::default();
        let s = fractum_kernel_contact_law(YOUNG, POISSON, 0.0, 0.3, 1, 0, &mut law);
        assert_eq!(s, FRACTUM_ERR_INPUT);
        let s = fractum_kernel_contact_law(YOUNG, POISSON, 0.5, 0.3, 0, 0, null_mut());
        assert_eq!(s, FRACTUM_ERR_NULL);
    }

    #[test]
    fn hertz_mindlin_gives_the_library_bits() {
        let mut d = Draw::new(1);
        for (damp, fric) in [(false, false), (true, false), (false, true), (true, true)] {
            let (law, k) = laws(damp, fric, 0.3);
            for _ in 0..50 {
                let n = d.unit();
                let (delta, r_eff, m_eff) = (
                    d.range(1e-9, 1e-5),
                    d.range(1e-4, 1e-3),
                    d.range(1e-6, 1e-5),
                );
                let v = d.vec(2.0);
                let h0 = d.vec(1e-6);
                let (dt, update) = (d.range(1e-9, 1e-7), d.flag());
                let mut h = h0;
                let c = match (damp, fric) {
                    (false, false) => hertz_mindlin::<false, false>(
                        &k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update,
                    ),
                    (true, false) => hertz_mindlin::<true, false>(
                        &k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update,
                    ),
                    (false, true) => hertz_mindlin::<false, true>(
                        &k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update,
                    ),
                    (true, true) => hertz_mindlin::<true, true>(
                        &k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update,
                    ),
                };
                let mut hist: [f64; 3] = h0.into();
                let mut out = FractumContact::default();
                let s = fractum_kernel_hertz_mindlin(
                    &law,
                    n.as_ptr(),
                    delta,
                    r_eff,
                    m_eff,
                    v.as_ptr(),
                    hist.as_mut_ptr(),
                    dt,
                    i32::from(update),
                    &mut out,
                );
                assert_eq!(s, FRACTUM_OK);
                assert_eq!(bits(&hist), vb(&h));
                assert_eq!(bits(&out.force), vb(&c.force));
                assert_eq!(
                    bits(&[
                        out.normal_force,
                        out.hertz_force,
                        out.radius,
                        out.stiffness,
                        out.energy,
                        out.dissipated
                    ]),
                    bits(&[
                        c.normal_force,
                        c.hertz_force,
                        c.radius,
                        c.stiffness,
                        c.elastic_energy,
                        c.dissipated
                    ])
                );
                assert_eq!(out.touching, 1);
            }
        }
    }

    /// Each counting fracture key is refused by the kernels at the bounds the library gives
    /// (the scene's checks take the same constants; tests/bad_input.rs and the plugin's
    /// tests check those layers).
    #[test]
    fn fracture_ranges_are_the_librarys_and_bound_the_kernels() {
        let (mut lo, mut hi) = (0.0, 0.0);
        for (key, range) in [
            (c"critical_contacts", fractum::fracture::CRITICAL_CONTACTS),
            (c"springs", fractum::fracture::SPRINGS),
        ] {
            assert_eq!(
                fractum_kernel_fracture_range(key.as_ptr(), &mut lo, &mut hi),
                FRACTUM_OK
            );
            assert_eq!((lo, hi), (range.0 as f64, range.1 as f64));
        }
        assert_eq!(
            fractum_kernel_fracture_range(c"mi".as_ptr(), &mut lo, &mut hi),
            FRACTUM_ERR_INPUT
        );
        let ok = |critical: i32, springs: i32| {
            let mut l = fracture_law(springs, true, true);
            l.critical_contacts = critical;
            fracture_params(&l).is_ok()
        };
        let (c, s) = (
            fractum::fracture::CRITICAL_CONTACTS,
            fractum::fracture::SPRINGS,
        );
        assert!(ok(c.0 as i32, 0) && ok(c.1 as i32, 0));
        assert!(!ok(c.0 as i32 - 1, 0) && !ok(c.1 as i32 + 1, 0));
        assert!(ok(3, s.0 as i32) && ok(3, s.1 as i32));
        assert!(!ok(3, s.0 as i32 - 1) && !ok(3, s.1 as i32 + 1));
    }

    /// The step check's verdicts at Fractum's limits (omega dt 2: stop, 1.6: warn), and bad
    /// arguments refused.
    #[test]
    fn step_check_gives_the_runs_verdicts() {
        let (mut x, mut v) = (0.0, -1);
        // omega = 1e6 rad/s (sum 1e12): dt 1e-6 gives omega dt 1.
        for (dt, expect) in [(1e-6, 0), (1.7e-6, 1), (2.1e-6, 2)] {
            assert_eq!(
                fractum_kernel_step_check(1e12, dt, &mut x, &mut v),
                FRACTUM_OK
            );
            assert_eq!(v, expect, "dt {dt}");
            assert!((x - dt * 1e6).abs() <= 1e-12 * x);
        }
        assert_eq!(
            fractum_kernel_step_check(f64::NAN, 1e-6, &mut x, &mut v),
            FRACTUM_ERR_INPUT
        );
        assert_eq!(
            fractum_kernel_step_check(1.0, 0.0, &mut x, &mut v),
            FRACTUM_ERR_INPUT
        );
        assert_eq!(
            fractum_kernel_step_check(1.0, 1.0, null_mut(), &mut v),
            FRACTUM_ERR_NULL
        );
    }

    /// Pairs of spheres and poly-ellipsoids at separations scaled from touching bounding
    /// spheres, each evaluated over a few steps as it moves (warm start, held radius,
    /// tangential history), in every variant: the export's contact and memory are the
    /// library's, bit for bit.
    #[test]
    fn pair_gives_the_library_bits() {
        let mut d = Draw::new(2);
        let mut touching = [0usize; 2];
        for &(damp, fric, poly) in &SWITCHES {
            let (law, k) = laws(damp, fric, 0.4);
            for case in 0..40 {
                let (sa, sb) = match case % 4 {
                    0 => (true, true),
                    1 => (true, false),
                    2 => (false, true),
                    _ => (false, false),
                };
                let mut a = random_body(&mut d, sa);
                let mut b = random_body(&mut d, sb);
                let u = d.unit();
                b.pos = a.pos - u * (d.range(0.4, 1.02) * (a.radius + b.radius));
                let dt = 2e-8;
                let (mut hist, mut memory) = (Vec3::zeros(), PairMemory::default());
                let mut mem = FractumPairMemory::default();
                for step in 0..4 {
                    let update = step > 0;
                    let (bodies, placements) = run_pair(&a, &b);
                    let at = |i| BodyAt {
                        bodies: &bodies,
                        placements: &placements,
                        i,
                    };
                    let p = variants!(
                        damp,
                        fric,
                        poly,
                        pair_contact(&k, &at(0), &at(1), &mut hist, &mut memory, dt, update)
                    );
                    let mut out = FractumContact::default();
                    let placed_before = mem;
                    let s = fractum_kernel_pair(
                        &law,
                        &fb(&a),
                        &fb(&b),
                        &mut mem,
                        dt,
                        i32::from(update),
                        i32::from(poly),
                        &mut out,
                    );
                    assert_eq!(s, FRACTUM_OK);
                    same_contact(&out, &p);
                    // Placed once per body, as a caller with many pairs does: the same bits,
                    // and the placement is the run's.
                    let (mut pa, mut pb) =
                        (FractumPlacement::default(), FractumPlacement::default());
                    assert_eq!(fractum_kernel_placement(&fb(&a), &mut pa), FRACTUM_OK);
                    assert_eq!(fractum_kernel_placement(&fb(&b), &mut pb), FRACTUM_OK);
                    for (given, run) in [(&pa, &placements.first()), (&pb, &placements.get(1))] {
                        if let Some(run) = run {
                            assert_eq!(bits(&given.origin), vb(&run.origin));
                            assert_eq!(bits(&given.rot), bits(&matrix_out(&run.rot)));
                        }
                    }
                    let mut placed = FractumContact::default();
                    let mut placed_mem = placed_before;
                    let s = fractum_kernel_pair_placed(
                        &law,
                        &fb(&a),
                        &pa,
                        &fb(&b),
                        &pb,
                        &mut placed_mem,
                        dt,
                        i32::from(update),
                        i32::from(poly),
                        &mut placed,
                    );
                    assert_eq!(s, FRACTUM_OK);
                    same_contact(&placed, &p);
                    for m in [&mem, &placed_mem] {
                        assert_eq!(bits(&m.hist), vb(&hist));
                        assert_eq!(bits(&m.normal), vb(&memory.normal));
                        assert_eq!(m.radius.to_bits(), memory.radius.to_bits());
                    }
                    touching[usize::from(sa && sb)] += usize::from(p.is_some());
                    a.pos += a.vel * 1e-5;
                    b.pos += b.vel * 1e-5;
                    a.orientation =
                        UnitQuaternion::from_scaled_axis(a.omega * 1e-5) * a.orientation;
                }
            }
        }
        assert!(touching[0] > 200 && touching[1] > 100, "{touching:?}");
    }

    /// A cluster of spheres and poly-ellipsoids moving and turning over many steps, each row
    /// of its half neighbour list given to the row kernel at once (partners with a flag bit
    /// the mask removes, tags that put the lower one as A in either row): the contacts and
    /// memories are `fractum_kernel_pair_placed`'s bit for bit, with the separated pairs'
    /// skip on (travel summed by `fractum_kernel_travel`) and off, and the skip skips.
    #[test]
    fn pair_row_gives_the_pair_kernels_bits_with_and_without_the_skip() {
        let mut d = Draw::new(21);
        let (mut skipped, mut touching, mut searched_apart) = (0usize, 0usize, 0usize);
        for &(damp, fric, poly) in &SWITCHES {
            let (law, _) = laws(damp, fric, 0.4);
            let n = 14;
            let mut bodies: Vec<Body> = (0..n).map(|k| random_body(&mut d, k % 3 == 0)).collect();
            for b in &mut bodies {
                b.pos *= 1.6;
            }
            // Tags out of index order.
            let keys: Vec<i64> = (0..n as i64).map(|k| (7 * k + 3) % n as i64).collect();
            let pairs: Vec<(usize, usize)> = (0..n)
                .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                .collect();
            let mut reference = vec![FractumPairMemory::default(); pairs.len()];
            let mut with_skip = vec![0.0; 8 * pairs.len()];
            let mut without = vec![0.0; 7 * pairs.len()];
            let mut travel = vec![0.0; n];
            let h = 2e-5;
            let dt = 2e-8;
            for step in 0..40 {
                let update = i32::from(step > 0);
                let fbs: Vec<FractumBody> = bodies.iter().map(fb).collect();
                let places: Vec<FractumPlacement> = fbs
                    .iter()
                    .map(|b| {
                        let mut p = FractumPlacement::default();
                        assert_eq!(fractum_kernel_placement(b, &mut p), FRACTUM_OK);
                        p
                    })
                    .collect();
                let mut expected = Vec::new();
                for (slot, &(i, j)) in pairs.iter().enumerate() {
                    let (a, b) = if keys[i] > keys[j] { (j, i) } else { (i, j) };
                    let mut c = FractumContact::default();
                    let s = fractum_kernel_pair_placed(
                        &law,
                        &fbs[a],
                        &places[a],
                        &fbs[b],
                        &places[b],
                        &mut reference[slot],
                        dt,
                        update,
                        i32::from(poly),
                        &mut c,
                    );
                    assert_eq!(s, FRACTUM_OK);
                    expected.push(c);
                    if poly && skips(with_skip[8 * slot + 7], travel[a], travel[b]) {
                        skipped += 1;
                        assert_eq!(c.touching, 0, "a skipped pair touches");
                    } else if c.touching == 0 && fbs[a].sphere * fbs[b].sphere == 0 {
                        searched_apart += 1;
                    }
                }
                let mut first = 0;
                for i in 0..n {
                    let row: Vec<usize> = (i + 1..n).collect();
                    let partners: Vec<i32> = row
                        .iter()
                        .map(|&j| j as i32 | ((j as i32 & 1) << 29))
                        .collect();
                    let m = row.len();
                    for (memory, stride, t) in [
                        (&mut with_skip, 8usize, travel.as_ptr()),
                        (&mut without, 7, null()),
                    ] {
                        let mut out = vec![FractumContact::default(); m];
                        let mut at = vec![-1; m];
                        let mut kept = vec![-1; m];
                        let mut count = -1;
                        let s = fractum_kernel_pair_row(
                            &law,
                            fbs.as_ptr(),
                            if poly { places.as_ptr() } else { null() },
                            keys.as_ptr(),
                            t,
                            n as i32,
                            i as i32,
                            partners.as_ptr(),
                            m as i32,
                            (1 << 29) - 1,
                            memory[first * stride..].as_mut_ptr(),
                            stride as i32,
                            dt,
                            update,
                            i32::from(poly),
                            kept.as_mut_ptr(),
                            out.as_mut_ptr(),
                            at.as_mut_ptr(),
                            &mut count,
                        );
                        assert_eq!(s, FRACTUM_OK);
                        let touching_here: Vec<usize> = (0..m)
                            .filter(|&k| expected[first + k].touching != 0)
                            .collect();
                        assert_eq!(count as usize, touching_here.len());
                        for (c, &k) in out.iter().zip(&at).take(count as usize) {
                            assert_eq!(*c, expected[first + k as usize]);
                            assert_eq!(bits(&c.force), bits(&expected[first + k as usize].force));
                        }
                        for k in 0..m {
                            let record = &memory[(first + k) * stride..(first + k + 1) * stride];
                            let r = &reference[first + k];
                            assert_eq!(bits(&record[..3]), bits(&r.hist));
                            assert_eq!(bits(&record[3..6]), bits(&r.normal));
                            assert_eq!(record[6].to_bits(), r.radius.to_bits());
                            assert_eq!(kept[k], i32::from(record.iter().any(|v| *v != 0.0)));
                        }
                    }
                    touching += expected[first..first + m]
                        .iter()
                        .filter(|c| c.touching != 0)
                        .count();
                    first += m;
                }
                for (b, t) in bodies.iter_mut().zip(&mut travel) {
                    let before = fb(b);
                    b.pos += b.vel * h;
                    b.orientation = UnitQuaternion::from_scaled_axis(b.omega * h) * b.orientation;
                    assert_eq!(fractum_kernel_travel(&before, &fb(b), t), FRACTUM_OK);
                }
            }
        }
        assert!(
            skipped > 500 && touching > 500 && searched_apart > 100,
            "skipped {skipped}, touching {touching}, searched apart {searched_apart}"
        );
    }

    /// The travel kernel adds the library's step: a turn and a shift, summed.
    #[test]
    fn travel_adds_the_library_step() {
        let mut d = Draw::new(4);
        for sphere in [true, false] {
            let a = random_body(&mut d, sphere);
            let mut b = a;
            b.pos += d.vec(1e-5);
            b.orientation = UnitQuaternion::from_scaled_axis(d.vec(0.01)) * a.orientation;
            let mut t = 0.25e-3;
            assert_eq!(fractum_kernel_travel(&fb(&a), &fb(&b), &mut t), FRACTUM_OK);
            let step = travel_step(&a.pos, &a.orientation, &b.pos, &b.orientation, b.radius);
            assert_eq!(t.to_bits(), (0.25e-3 + step).to_bits());
            let angle = a.orientation.angle_to(&b.orientation);
            assert!(step >= (b.pos - a.pos).norm() + b.radius * angle);
        }
        assert_eq!(
            fractum_kernel_travel(null(), null(), null_mut()),
            FRACTUM_ERR_NULL
        );
    }

    /// The frequency shares of pair contacts as the run's estimate sums them (over a Bodies,
    /// as `records_max_frequency` reads it), and the adapted step.
    #[test]
    fn frequency_share_and_adapted_step_give_the_library_bits() {
        use fractum::effects::contact::{
            ContactRecord, WALL, frequency_bound, records_max_frequency, tangential_ratio,
        };
        let mut d = Draw::new(9);
        let (mut shortened, mut touching) = (0, 0);
        for fric in [false, true] {
            let (law, k) = laws(true, fric, 0.4);
            let tangential = if fric {
                tangential_ratio(k.eight_g, k.two_e)
            } else {
                0.0
            };
            for case in 0..40 {
                let a = random_body(&mut d, case % 2 == 0);
                let mut b = random_body(&mut d, case % 3 == 0);
                b.pos = a.pos - d.unit() * (0.9 * (a.radius + b.radius));
                let mut mem = FractumPairMemory::default();
                let mut c = FractumContact::default();
                let s = fractum_kernel_pair(&law, &fb(&a), &fb(&b), &mut mem, 2e-8, 1, 1, &mut c);
                assert_eq!(s, FRACTUM_OK);
                if c.touching == 0 {
                    continue;
                }
                touching += 1;
                let (bodies, _) = run_pair(&a, &b);
                // The run's bound over this one contact, between the bodies and against a wall.
                let record = |j| ContactRecord {
                    i: 0,
                    j,
                    point: Vec3::from(c.point),
                    normal: Vec3::from(c.normal),
                    force: Vec3::from(c.force),
                    normal_force: c.normal_force,
                    hertz_force: c.hertz_force,
                    radius: c.radius,
                    stiffness: c.stiffness,
                    energy: c.energy,
                };
                let (fa, fb_) = (fb(&a), fb(&b));
                let mut shares = [f64::NAN; 2];
                for (k, (own, other)) in [(&fa, &fb_), (&fb_, &fa)].into_iter().enumerate() {
                    let s = fractum_kernel_frequency_share(&law, &c, own, other, &mut shares[k]);
                    assert_eq!(s, FRACTUM_OK);
                }
                let mut both = [f64::NAN; 2];
                let s = fractum_kernel_frequency_shares(
                    &law,
                    &c,
                    &fa,
                    &fb_,
                    &mut both[0],
                    &mut both[1],
                );
                assert_eq!(s, FRACTUM_OK);
                assert_eq!(bits(&both), bits(&shares));
                let sum = shares[0].max(shares[1]);
                let lib = records_max_frequency(&[record(1)], &bodies, tangential);
                assert_eq!(frequency_bound(sum).to_bits(), lib.to_bits());
                let mut wall = f64::NAN;
                let s = fractum_kernel_frequency_share(&law, &c, &fa, null(), &mut wall);
                assert_eq!(s, FRACTUM_OK);
                let lib = records_max_frequency(&[record(WALL)], &bodies, tangential);
                assert_eq!(frequency_bound(wall).to_bits(), lib.to_bits());
                let omega = frequency_bound(sum);
                for dt in [0.5, 1.5, 3.0].map(|f| f * 0.6 / omega) {
                    let mut next = f64::NAN;
                    assert_eq!(
                        fractum_kernel_adapted_step(sum, dt, 0.6, &mut next),
                        FRACTUM_OK
                    );
                    let lib = fractum::models::granular::adapted_step(omega, dt, 0.6);
                    assert_eq!(next.to_bits(), lib.unwrap_or(dt).to_bits());
                    shortened += usize::from(lib.is_some());
                }
            }
        }
        assert!(touching > 20, "{touching}");
        assert_eq!(
            shortened,
            2 * touching,
            "the steps above 0.6 / omega are shortened"
        );
        let mut next = 0.0;
        assert_eq!(
            fractum_kernel_adapted_step(-1.0, 1e-8, 0.6, &mut next),
            FRACTUM_ERR_INPUT
        );
        assert_eq!(
            fractum_kernel_adapted_step(1.0, 0.0, 0.6, &mut next),
            FRACTUM_ERR_INPUT
        );
        assert_eq!(
            fractum_kernel_adapted_step(1.0, 1e-8, f64::NAN, &mut next),
            FRACTUM_ERR_INPUT
        );
    }

    /// The same pairs' geometry alone.
    #[test]
    fn convex_and_wall_geometry_give_the_library_bits() {
        let mut d = Draw::new(3);
        let mut touching = 0;
        for case in 0..200 {
            let a = random_body(&mut d, case % 3 == 0);
            let mut b = random_body(&mut d, case % 5 == 0);
            let u = d.unit();
            b.pos = a.pos - u * (d.range(0.4, 1.02) * (a.radius + b.radius));
            let guess = if d.flag() { d.vec(1.0) } else { Vec3::zeros() };
            let (bodies, placements) = run_pair(&a, &b);
            let at = |i| BodyAt {
                bodies: &bodies,
                placements: &placements,
                i,
            };
            let g = convex::contact(&at(0).placed(), &at(1).placed(), &guess);
            touching += usize::from(g.is_some());
            let mut out = FractumGeometry::default();
            let s = fractum_kernel_convex_contact(&fb(&a), &fb(&b), guess.as_ptr(), &mut out);
            assert_eq!(s, FRACTUM_OK);
            same_geometry(&out, &g);
            let wp = a.pos - u * (d.range(0.3, 1.05) * a.radius);
            let g = convex::wall_contact(&at(0).placed(), &u, &wp);
            let s = fractum_kernel_wall_geometry(&fb(&a), u.as_ptr(), wp.as_ptr(), &mut out);
            assert_eq!(s, FRACTUM_OK);
            same_geometry(&out, &g);
        }
        assert!(touching > 80, "{touching}");
    }

    #[test]
    fn wall_gives_the_library_bits() {
        let mut d = Draw::new(4);
        let mut touching = 0;
        for &(damp, fric, poly) in &SWITCHES {
            let (law, k) = laws(damp, fric, 0.25);
            for case in 0..40 {
                let mut a = random_body(&mut d, case % 2 == 0);
                let n = d.unit();
                let wp = a.pos - n * (d.range(0.3, 1.05) * a.radius);
                let wv = d.vec(0.5);
                let dt = 3e-8;
                let (mut hist, mut held) = (Vec3::zeros(), 0.0);
                let mut mem = FractumPairMemory::default();
                for step in 0..3 {
                    let update = step > 0;
                    let (bodies, placements) = run_pair(&a, &a);
                    let at = BodyAt {
                        bodies: &bodies,
                        placements: &placements,
                        i: 0,
                    };
                    let p = variants!(
                        damp,
                        fric,
                        poly,
                        wall_contact(&k, &at, &n, &wp, &wv, &mut hist, &mut held, dt, update)
                    );
                    let mut out = FractumContact::default();
                    let s = fractum_kernel_wall(
                        &law,
                        &fb(&a),
                        n.as_ptr(),
                        wp.as_ptr(),
                        wv.as_ptr(),
                        &mut mem,
                        dt,
                        i32::from(update),
                        i32::from(poly),
                        &mut out,
                    );
                    assert_eq!(s, FRACTUM_OK);
                    same_contact(&out, &p);
                    assert_eq!(bits(&mem.hist), vb(&hist));
                    assert_eq!(mem.radius.to_bits(), held.to_bits());
                    touching += usize::from(p.is_some());
                    a.pos += a.vel * 1e-5;
                }
            }
        }
        assert!(touching > 300, "{touching}");
    }

    #[test]
    fn poly_ellipsoid_body_is_what_the_run_adds() {
        let mut d = Draw::new(5);
        for _ in 0..20 {
            let semi: [f64; 6] = std::array::from_fn(|_| d.range(0.2e-3, 1e-3));
            let (mass, c, q) = (d.range(1e-6, 1e-5), d.vec(1e-2), d.quat());
            let mut bodies = Bodies::default();
            bodies.push_poly_ellipsoid(PolyEllipsoid::new(semi).unwrap(), mass, c, q);
            let qa: [f64; 4] = [q.w, q.i, q.j, q.k];
            let mut out = FractumBody::default();
            let s = fractum_kernel_poly_ellipsoid_body(
                semi.as_ptr(),
                mass,
                c.as_ptr(),
                qa.as_ptr(),
                &mut out,
            );
            assert_eq!(s, FRACTUM_OK);
            assert_eq!(body_bits(&out), body_bits(&fb(&bodies.body(0))));
            let mut v = 0.0;
            assert_eq!(fractum_kernel_body_volume(&out, &mut v), FRACTUM_OK);
            assert_eq!(v.to_bits(), bodies.volume(0).to_bits());
        }
        let mut bodies = Bodies::default();
        bodies.push_sphere(Vec3::zeros(), 0.7e-3, 2500.0, d.quat());
        let mut v = 0.0;
        let s = fractum_kernel_body_volume(&fb(&bodies.body(0)), &mut v);
        assert_eq!(s, FRACTUM_OK);
        assert_eq!(v.to_bits(), bodies.volume(0).to_bits());
    }

    #[test]
    fn criteria_give_the_library_bits() {
        let mut d = Draw::new(6);
        for case in 0..100 {
            let b = random_body(&mut d, case % 2 == 0);
            let moment: [f64; 9] = std::array::from_fn(|_| d.range(-1e-2, 1e-2));
            let torque = d.vec(1e-3);
            let mut stress = [0.0; 9];
            let s = fractum_kernel_average_stress(
                &fb(&b),
                moment.as_ptr(),
                torque.as_ptr(),
                stress.as_mut_ptr(),
            );
            assert_eq!(s, FRACTUM_OK);
            let m = grain_average_stress(&b, &Matrix3::from_row_slice(&moment), &torque);
            let rows: Vec<f64> = (0..9).map(|k| m[(k / 3, k % 3)]).collect();
            assert_eq!(bits(&stress), bits(&rows));
            let mut p = [0.0; 3];
            let s = fractum_kernel_principal_compressions(stress.as_ptr(), p.as_mut_ptr());
            assert_eq!(s, FRACTUM_OK);
            assert_eq!(bits(&p), bits(&criteria::principal_compression_values(&m)));
            let (s1, s3, sc, mi) = (
                d.range(-1e8, 1e9),
                d.range(-1e8, 1e8),
                d.range(1e8, 1e9),
                d.range(5.0, 25.0),
            );
            let mut fails = -1;
            let s = fractum_kernel_hoek_brown_fails(s1, s3, sc, mi, &mut fails);
            assert_eq!(s, FRACTUM_OK);
            assert_eq!(fails, i32::from(criteria::hoek_brown_fails(s1, s3, sc, mi)));
            let (f, a, nu) = (d.range(0.0, 50.0), d.range(1e-6, 1e-4), d.range(0.1, 0.4));
            let mut st = 0.0;
            let s = fractum_kernel_contact_tensile_stress(f, a, nu, &mut st);
            assert_eq!(s, FRACTUM_OK);
            assert_eq!(
                st.to_bits(),
                criteria::contact_tensile_stress(f, a, nu).to_bits()
            );
            let (pr, w, x, xm) = (d.u(), d.range(1.0, 5.0), d.range(1e-4, 1e-3), 5e-4);
            let mut wf = 0.0;
            assert_eq!(
                fractum_kernel_weibull_factor(pr, w, x, xm, &mut wf),
                FRACTUM_OK
            );
            assert_eq!(
                wf.to_bits(),
                criteria::weibull_factor(pr, w, x, xm).to_bits()
            );
            let n = case % 6;
            let pts: Vec<[f64; 3]> = (0..n).map(|_| d.vec(1e-3).into()).collect();
            let (mut normal, mut found) = ([9.0; 3], -1);
            let s = fractum_kernel_contacts_plane_normal(
                pts.as_ptr(),
                n,
                normal.as_mut_ptr(),
                &mut found,
            );
            assert_eq!(s, FRACTUM_OK);
            let v: Vec<Vec3> = pts.iter().map(|p| Vec3::from(*p)).collect();
            match break_plane::contacts_plane_normal(&v) {
                Some(nrm) => {
                    assert_eq!(found, 1);
                    assert_eq!(bits(&normal), vb(&nrm));
                }
                None => assert_eq!((found, normal), (0, [0.0; 3])),
            }
        }
        let line = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let (mut normal, mut found) = ([0.0; 3], -1);
        let s =
            fractum_kernel_contacts_plane_normal(line.as_ptr(), 3, normal.as_mut_ptr(), &mut found);
        assert_eq!((s, found), (FRACTUM_OK, 0));
    }

    fn fracture_law(springs: i32, ideal: bool, jitter: bool) -> FractumFractureLaw {
        FractumFractureLaw {
            mi: 20.56,
            sigma_c: 592e6,
            sigma_f: 2.0e9,
            poisson: POISSON,
            critical_contacts: 3,
            ideal_plane: i32::from(ideal),
            plane_jitter: i32::from(jitter),
            springs,
            gc: 50.7,
            weibull_sigma_c: 0,
        }
    }

    fn params_of(l: &FractumFractureLaw) -> FractureParams {
        FractureParams {
            mi: l.mi,
            sigma_c: l.sigma_c,
            sigma_f: l.sigma_f,
            weibull: None,
            weibull_sigma_c: l.weibull_sigma_c != 0,
            critical_contacts: l.critical_contacts as usize,
            cohesion: (l.springs > 0).then_some((l.gc, l.springs as usize)),
            ideal_plane: l.ideal_plane != 0,
            plane_jitter: l.plane_jitter != 0,
            poisson: l.poisson,
        }
    }

    fn same_trigger(out: &FractumTrigger, t: &Option<(Trigger, Criterion, f64)>) {
        match t {
            None => assert_eq!(*out, FractumTrigger::default()),
            Some((Trigger::HoekBrown { stress }, c, v)) => {
                assert_eq!((out.kind, *c), (1, Criterion::HoekBrown));
                let rows: Vec<f64> = (0..9).map(|k| stress[(k / 3, k % 3)]).collect();
                assert_eq!(bits(&out.stress), bits(&rows));
                assert_eq!(out.value.to_bits(), v.to_bits());
            }
            Some((Trigger::Contacts { normal }, c, v)) => {
                assert_eq!((out.kind, *c), (2, Criterion::Contacts));
                assert_eq!(bits(&out.normal), vb(normal));
                assert_eq!(out.value.to_bits(), v.to_bits());
            }
        }
    }

    /// A moment that squeezes grain `b` along `axis` with forces `f` (N) at its surface.
    fn squeeze(b: &Body, axis: Vec3, f: f64) -> Matrix3<f64> {
        let x = axis * b.radius;
        (-axis * f) * x.transpose() + (axis * f) * (-x).transpose()
    }

    #[test]
    fn check_gives_the_library_bits() {
        let mut d = Draw::new(7);
        let mut kinds = [0usize; 3];
        for case in 0..200 {
            let law = FractumFractureLaw {
                weibull_sigma_c: i32::from(d.flag()),
                ..fracture_law(4, d.flag(), d.flag())
            };
            let p = params_of(&law);
            let b = random_body(&mut d, case % 2 == 0);
            // Up to 2.5 times the force that fails a sphere in uniaxial compression.
            let f =
                d.range(0.0, 2.5) * law.sigma_c * 2.0 * std::f64::consts::PI * b.radius * b.radius
                    / 3.0;
            let m = squeeze(&b, d.unit(), f);
            let torque = d.vec(1e-4);
            let strength = d.range(0.5, 2.0);
            let n_critical = case % 6;
            let pts: Vec<[f64; 3]> = (0..n_critical).map(|_| d.vec(1e-3).into()).collect();
            let top = d.range(1e9, 5e9);
            let v: Vec<Vec3> = pts.iter().take(3).map(|p| Vec3::from(*p)).collect();
            let t = grain_fails(&p, &b, strength, &m, &torque, n_critical, &v, top);
            let rows: Vec<f64> = (0..9).map(|k| m[(k / 3, k % 3)]).collect();
            let mut out = FractumTrigger::default();
            let s = fractum_kernel_check(
                &law,
                &fb(&b),
                strength,
                rows.as_ptr(),
                torque.as_ptr(),
                n_critical,
                if n_critical == 0 {
                    null()
                } else {
                    pts.as_ptr()
                },
                top,
                &mut out,
            );
            assert_eq!(s, FRACTUM_OK);
            same_trigger(&out, &t);
            kinds[out.kind as usize] += 1;
        }
        assert!(kinds.iter().all(|&k| k > 20), "{kinds:?}");
    }

    fn same_pending(out: &FractumPending, p: &PendingSplit) {
        for (x, y) in [
            (&out.centroid, &p.centroid),
            (&out.accel, &p.accel),
            (&out.alpha, &p.alpha),
            (&out.omega, &p.omega),
        ] {
            assert_eq!(bits(x), vb(y));
        }
        for k in 0..16 {
            assert_eq!(bits(&out.points[k]), vb(&p.points[k]));
        }
        assert_eq!(out.count as usize, p.count);
        assert_eq!(out.area.to_bits(), p.area.to_bits());
    }

    /// Splits of spheres (ideal plane or not, with and without the slight rotation) and
    /// poly-ellipsoids (well and badly shaped) by either trigger, with and without
    /// cohesion; then the bond of each split and its springs' evaluations as the halves
    /// part, until they break.
    #[test]
    fn split_bond_and_springs_give_the_library_bits() {
        let mut d = Draw::new(8);
        let (mut splits, mut springs_made, mut broke, mut forbidden) = (0, 0, 0, 0);
        for case in 0..120 {
            let springs = [0, 3, 4, 16][case % 4];
            let law = fracture_law(springs, d.flag(), d.flag());
            let p = params_of(&law);
            let mut b = random_body(&mut d, case % 3 != 0);
            if case % 12 == 5 {
                let pe = PolyEllipsoid::new([1e-3, 0.1e-3, 1e-3, 0.1e-3, 1e-3, 0.1e-3]).unwrap();
                b = Body::poly_ellipsoid(pe, 1e-6, b.pos, d.quat());
            }
            let trigger = if d.flag() {
                let m = squeeze(&b, d.unit(), 50.0);
                Trigger::HoekBrown {
                    stress: m / b.volume() + Matrix3::from_fn(|_, _| d.range(-1e6, 1e6)),
                }
            } else {
                Trigger::Contacts { normal: d.unit() }
            };
            let ft = match trigger {
                Trigger::HoekBrown { stress } => FractumTrigger {
                    kind: 1,
                    stress: std::array::from_fn(|k| stress[(k / 3, k % 3)]),
                    ..Default::default()
                },
                Trigger::Contacts { normal } => FractumTrigger {
                    kind: 2,
                    normal: normal.into(),
                    ..Default::default()
                },
            };
            let (force, torque) = (d.vec(30.0), d.vec(1e-3));
            let u: [f64; 6] = std::array::from_fn(|_| d.u());
            let jitter = d.flag().then(|| break_plane::jitter_angles(&u));
            let lib = split_grain(&p, &b, &force, &torque, &trigger, jitter);
            let mut out = FractumSplit::default();
            let s = fractum_kernel_split(
                &law,
                &fb(&b),
                force.as_ptr(),
                torque.as_ptr(),
                &ft,
                jitter.as_ref().map_or(null(), |j| j.as_ptr()),
                &mut out,
            );
            assert_eq!(s, FRACTUM_OK);
            // Asked first, the shape test agrees with the split.
            let mut can = -1;
            assert_eq!(fractum_kernel_can_break(&fb(&b), &mut can), FRACTUM_OK);
            assert_eq!(can, i32::from(out.axis >= 0));
            forbidden += usize::from(can == 0);
            let Some(split) = lib else {
                assert_eq!(out.axis, -1);
                continue;
            };
            splits += 1;
            assert_eq!(out.axis as usize, split.axis);
            assert_eq!(body_bits(&out.plus), body_bits(&fb(&split.plus)));
            assert_eq!(body_bits(&out.minus), body_bits(&fb(&split.minus)));
            same_pending(&out.pending, &split.pending);

            // The bond, under the halves' own forces after the split.
            let (pa, pb) = (split.plus, split.minus);
            let loads = [d.vec(10.0), d.vec(1e-3), d.vec(10.0), d.vec(1e-3)];
            let mut made: Vec<MadeSpring> = Vec::new();
            if let Some((gc, _)) = p.cohesion {
                let [fa, ta, fb_, tb] = &loads;
                bond_split(gc, &pa, &pb, [fa, ta, fb_, tb], &split.pending, |m| {
                    made.push(m)
                });
            }
            let mut fsprings = [FractumSpring::default(); 16];
            let mut n_made = -1;
            let s = fractum_kernel_bond(
                &law,
                &fb(&pa),
                &fb(&pb),
                loads[0].as_ptr(),
                loads[1].as_ptr(),
                loads[2].as_ptr(),
                loads[3].as_ptr(),
                &out.pending,
                fsprings.as_mut_ptr(),
                &mut n_made,
            );
            assert_eq!(s, FRACTUM_OK);
            assert_eq!(n_made as usize, made.len());
            springs_made += made.len();
            for (k, m) in made.iter().enumerate() {
                assert_eq!(
                    spring_bits(&fsprings[k]),
                    spring_bits(&spring_out(&m.spring))
                );
                assert_eq!(bits(&fsprings[k].last_force), vb(&m.force));
            }

            // Each spring as the halves part: evaluated until it breaks.
            let (mut a, mut bb) = (pa, pb);
            let apart = (pa.pos - pb.pos).normalize();
            for (k, m) in made.iter().enumerate() {
                let mut lib = m.spring.clone();
                let mut fs = fsprings[k];
                for step in 0..400 {
                    a.pos += apart * (1e-9 * step as f64);
                    bb.pos -= apart * (1e-9 * step as f64);
                    bb.orientation = UnitQuaternion::from_scaled_axis(d.vec(1e-4)) * bb.orientation;
                    let act = lib.act(&a.pos, &a.orientation, &bb.pos, &bb.orientation);
                    let (mut f, mut ta, mut tb, mut w, mut br) =
                        ([9.0; 3], [9.0; 3], [9.0; 3], 9.0, -1);
                    let s = fractum_kernel_spring(
                        &mut fs,
                        &fb(&a),
                        &fb(&bb),
                        f.as_mut_ptr(),
                        ta.as_mut_ptr(),
                        tb.as_mut_ptr(),
                        &mut w,
                        &mut br,
                    );
                    assert_eq!(s, FRACTUM_OK);
                    assert_eq!(spring_bits(&fs), spring_bits(&spring_out(&lib)));
                    assert_eq!(bits(&f), vb(&act.force));
                    assert_eq!(bits(&ta), vb(&act.torque_a));
                    assert_eq!(bits(&tb), vb(&act.torque_b));
                    assert_eq!(
                        (w.to_bits(), br),
                        (act.work.to_bits(), i32::from(act.broke))
                    );
                    if act.broke {
                        broke += 1;
                        // A broken spring does nothing more.
                        let s = fractum_kernel_spring(
                            &mut fs,
                            &fb(&a),
                            &fb(&bb),
                            f.as_mut_ptr(),
                            ta.as_mut_ptr(),
                            tb.as_mut_ptr(),
                            &mut w,
                            &mut br,
                        );
                        assert_eq!((s, br, w, f), (FRACTUM_OK, 0, 0.0, [0.0; 3]));
                        break;
                    }
                }
            }
        }
        assert!(
            splits > 60 && springs_made > 200 && broke > 100 && forbidden > 5,
            "{splits} {springs_made} {broke} {forbidden}"
        );
    }

    #[test]
    fn spring_initial_forces_give_the_library_bits() {
        let mut d = Draw::new(9);
        for n in [0usize, 3, 4, 7, 16] {
            let pts: Vec<[f64; 3]> = (0..n).map(|_| d.vec(1e-3).into()).collect();
            let demand: [f64; 15] =
                std::array::from_fn(|k| d.range(-1.0, 1.0) * [10.0, 1e-3, 10.0, 1e-3, 1e-3][k / 3]);
            let v = |k: usize| Vec3::new(demand[3 * k], demand[3 * k + 1], demand[3 * k + 2]);
            let lib = cohesion::initial_forces(
                &pts.iter().map(|p| Vec3::from(*p)).collect::<Vec<_>>(),
                &Demand {
                    force_a: v(0),
                    torque_a: v(1),
                    force_b: v(2),
                    torque_b: v(3),
                    b_offset: v(4),
                },
            );
            let mut forces = vec![[9.0; 3]; n];
            let s = fractum_kernel_spring_initial_forces(
                if n == 0 { null() } else { pts.as_ptr() },
                n,
                demand.as_ptr(),
                if n == 0 {
                    null_mut()
                } else {
                    forces.as_mut_ptr()
                },
            );
            assert_eq!(s, FRACTUM_OK);
            for (f, l) in forces.iter().zip(&lib) {
                assert_eq!(bits(f), vb(l));
            }
        }
    }

    #[test]
    fn jitter_angles_and_uniforms_give_the_library_bits() {
        let mut d = Draw::new(10);
        for _ in 0..100 {
            let u: [f64; 6] = std::array::from_fn(|_| d.u());
            let mut angles = [0.0; 3];
            let s = fractum_kernel_jitter_angles(u.as_ptr(), angles.as_mut_ptr());
            assert_eq!(s, FRACTUM_OK);
            assert_eq!(bits(&angles), bits(&break_plane::jitter_angles(&u)));
        }
        for (seed, key, counter, n) in
            [(1u64, 2u64, 0u64, 10usize), (1, 2, 1, 10), (7, 0, 12345, 3)]
        {
            let mut out = vec![0.0; n];
            let s = fractum_kernel_uniforms(seed, key, counter, n, out.as_mut_ptr());
            assert_eq!(s, FRACTUM_OK);
            let mut lib = vec![0.0; n];
            uniforms(seed, key, counter, &mut lib);
            assert_eq!(bits(&out), bits(&lib));
            assert!(out.iter().all(|&x| x > 0.0 && x <= 1.0));
        }
        let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
        fractum_kernel_uniforms(1, 2, 0, 4, a.as_mut_ptr());
        fractum_kernel_uniforms(1, 2, 1, 4, b.as_mut_ptr());
        assert_ne!(a, b);
        let mut x = 0.0;
        let s = fractum_kernel_uniforms(1, 2, UNIFORM_COUNTERS, 1, &mut x);
        assert_eq!(s, FRACTUM_ERR_INPUT);
        assert_eq!(fractum_kernel_uniforms(1, 2, 0, 0, null_mut()), FRACTUM_OK);
        assert_eq!(
            fractum_kernel_uniforms(1, 2, 0, 1, null_mut()),
            FRACTUM_ERR_NULL
        );
    }

    #[test]
    fn null_pointers_and_bad_input_are_refused() {
        let mut d = Draw::new(11);
        let (law, _) = laws(true, true, 0.3);
        let sphere = fb(&random_body(&mut d, true));
        let poly = fb(&random_body(&mut d, false));
        let mut bad = poly;
        bad.semi[3] = -1e-4;
        let mut nan = poly;
        nan.semi[0] = f64::NAN;
        let v = [0.0, 0.0, 1.0];
        let mut h = [0.0; 3];
        let mut mem = FractumPairMemory::default();
        let mut c = FractumContact::default();
        let mut g = FractumGeometry::default();
        let p = v.as_ptr();

        let s = fractum_kernel_hertz_mindlin(
            null(),
            p,
            1e-6,
            1e-3,
            1e-6,
            p,
            h.as_mut_ptr(),
            1e-8,
            1,
            &mut c,
        );
        assert_eq!(s, FRACTUM_ERR_NULL);
        let s =
            fractum_kernel_hertz_mindlin(&law, p, 1e-6, 1e-3, 1e-6, p, null_mut(), 1e-8, 1, &mut c);
        assert_eq!(s, FRACTUM_ERR_NULL);
        assert_eq!(
            fractum_kernel_convex_contact(&sphere, null(), p, &mut g),
            FRACTUM_ERR_NULL
        );
        assert_eq!(
            fractum_kernel_convex_contact(&sphere, &poly, p, null_mut()),
            FRACTUM_ERR_NULL
        );
        assert_eq!(
            fractum_kernel_convex_contact(&sphere, &bad, p, &mut g),
            FRACTUM_ERR_INPUT
        );
        assert_eq!(
            fractum_kernel_wall_geometry(&poly, p, null(), &mut g),
            FRACTUM_ERR_NULL
        );
        assert_eq!(
            fractum_kernel_wall_geometry(&nan, p, p, &mut g),
            FRACTUM_ERR_INPUT
        );
        let s = fractum_kernel_pair(&law, &sphere, &poly, null_mut(), 1e-8, 1, 1, &mut c);
        assert_eq!(s, FRACTUM_ERR_NULL);
        let s = fractum_kernel_pair(&law, &bad, &poly, &mut mem, 1e-8, 1, 1, &mut c);
        assert_eq!(s, FRACTUM_ERR_INPUT);
        let s = fractum_kernel_pair(&law, &sphere, &bad, &mut mem, 1e-8, 1, 1, &mut c);
        assert_eq!(s, FRACTUM_ERR_INPUT);
        let mut place = FractumPlacement::default();
        assert_eq!(
            fractum_kernel_placement(&bad, &mut place),
            FRACTUM_ERR_INPUT
        );
        assert_eq!(
            fractum_kernel_placement(&poly, null_mut()),
            FRACTUM_ERR_NULL
        );
        assert_eq!(fractum_kernel_placement(&poly, &mut place), FRACTUM_OK);
        let s = fractum_kernel_pair_placed(
            &law,
            &sphere,
            null(),
            &poly,
            &place,
            &mut mem,
            1e-8,
            1,
            1,
            &mut c,
        );
        assert_eq!(s, FRACTUM_ERR_NULL);
        let s = fractum_kernel_wall(&law, &poly, p, p, null(), &mut mem, 1e-8, 1, 1, &mut c);
        assert_eq!(s, FRACTUM_ERR_NULL);
        let s = fractum_kernel_wall(&law, &bad, p, p, p, &mut mem, 1e-8, 1, 1, &mut c);
        assert_eq!(s, FRACTUM_ERR_INPUT);

        let mut body = FractumBody::default();
        let q = [1.0, 0.0, 0.0, 0.0];
        let mut semi = [1e-3; 6];
        let s = fractum_kernel_poly_ellipsoid_body(semi.as_ptr(), 1e-6, p, null(), &mut body);
        assert_eq!(s, FRACTUM_ERR_NULL);
        semi[4] = 0.0;
        let s = fractum_kernel_poly_ellipsoid_body(semi.as_ptr(), 1e-6, p, q.as_ptr(), &mut body);
        assert_eq!(s, FRACTUM_ERR_INPUT);
        let mut x = 0.0;
        assert_eq!(fractum_kernel_body_volume(null(), &mut x), FRACTUM_ERR_NULL);
        assert_eq!(fractum_kernel_body_volume(&bad, &mut x), FRACTUM_ERR_INPUT);

        let m = [0.0; 9];
        let mut out9 = [0.0; 9];
        let s = fractum_kernel_average_stress(&poly, null(), p, out9.as_mut_ptr());
        assert_eq!(s, FRACTUM_ERR_NULL);
        let s = fractum_kernel_average_stress(&bad, m.as_ptr(), p, out9.as_mut_ptr());
        assert_eq!(s, FRACTUM_ERR_INPUT);
        assert_eq!(
            fractum_kernel_principal_compressions(m.as_ptr(), null_mut()),
            FRACTUM_ERR_NULL
        );
        assert_eq!(
            fractum_kernel_hoek_brown_fails(1.0, 0.0, 1.0, 1.0, null_mut()),
            FRACTUM_ERR_NULL
        );
        assert_eq!(
            fractum_kernel_contact_tensile_stress(1.0, 1.0, 0.2, null_mut()),
            FRACTUM_ERR_NULL
        );
        assert_eq!(
            fractum_kernel_weibull_factor(0.5, 1.0, 1.0, 1.0, null_mut()),
            FRACTUM_ERR_NULL
        );
        let mut found = 0;
        let mut n3 = [0.0; 3];
        let s = fractum_kernel_contacts_plane_normal(null(), 3, n3.as_mut_ptr(), &mut found);
        assert_eq!(s, FRACTUM_ERR_NULL);

        let fl = fracture_law(4, true, true);
        let mut t = FractumTrigger::default();
        let s = fractum_kernel_check(&fl, &poly, 1.0, m.as_ptr(), p, 2, null(), 0.0, &mut t);
        assert_eq!(s, FRACTUM_ERR_NULL);
        let s = fractum_kernel_check(&fl, &bad, 1.0, m.as_ptr(), p, 0, null(), 0.0, &mut t);
        assert_eq!(s, FRACTUM_ERR_INPUT);
        let many = fracture_law(17, true, true);
        let s = fractum_kernel_check(&many, &poly, 1.0, m.as_ptr(), p, 0, null(), 0.0, &mut t);
        assert_eq!(s, FRACTUM_ERR_INPUT);

        let mut split = FractumSplit::default();
        let hb = FractumTrigger {
            kind: 1,
            ..Default::default()
        };
        let none = FractumTrigger::default();
        let s = fractum_kernel_split(&fl, &poly, p, p, null(), null(), &mut split);
        assert_eq!(s, FRACTUM_ERR_NULL);
        let s = fractum_kernel_split(&fl, &poly, p, p, &none, null(), &mut split);
        assert_eq!(s, FRACTUM_ERR_INPUT);
        let s = fractum_kernel_split(&fl, &bad, p, p, &hb, null(), &mut split);
        assert_eq!(s, FRACTUM_ERR_INPUT);
        let s = fractum_kernel_split(&fl, &sphere, p, p, &hb, null(), &mut split);
        assert_eq!(s, FRACTUM_OK);
        let mut u6 = [0.5; 6];
        assert_eq!(
            fractum_kernel_jitter_angles(u6.as_ptr(), null_mut()),
            FRACTUM_ERR_NULL
        );
        assert_eq!(
            fractum_kernel_jitter_angles(null(), u6.as_mut_ptr()),
            FRACTUM_ERR_NULL
        );

        let mut springs = [FractumSpring::default(); 16];
        let mut made = 0;
        let s = fractum_kernel_bond(
            &fl,
            &split.plus,
            &split.minus,
            p,
            p,
            p,
            p,
            &split.pending,
            null_mut(),
            &mut made,
        );
        assert_eq!(s, FRACTUM_ERR_NULL);
        let s = fractum_kernel_bond(
            &fl,
            &split.plus,
            &bad,
            p,
            p,
            p,
            p,
            &split.pending,
            springs.as_mut_ptr(),
            &mut made,
        );
        assert_eq!(s, FRACTUM_ERR_INPUT);
        let mut pend = split.pending;
        pend.count = 17;
        let s = fractum_kernel_bond(
            &fl,
            &split.plus,
            &split.minus,
            p,
            p,
            p,
            p,
            &pend,
            springs.as_mut_ptr(),
            &mut made,
        );
        assert_eq!(s, FRACTUM_ERR_INPUT);
        let demand = [0.0; 15];
        let s = fractum_kernel_spring_initial_forces(
            split.pending.points.as_ptr(),
            4,
            demand.as_ptr(),
            null_mut(),
        );
        assert_eq!(s, FRACTUM_ERR_NULL);
        let mut sp = FractumSpring::default();
        let (mut w, mut br) = (0.0, 0);
        let s = fractum_kernel_spring(
            &mut sp,
            &poly,
            &poly,
            h.as_mut_ptr(),
            h.as_mut_ptr(),
            null_mut(),
            &mut w,
            &mut br,
        );
        assert_eq!(s, FRACTUM_ERR_NULL);
        let mut f3 = [0.0; 3];
        let mut t3 = [0.0; 3];
        let s = fractum_kernel_spring(
            &mut sp,
            &poly,
            &bad,
            h.as_mut_ptr(),
            f3.as_mut_ptr(),
            t3.as_mut_ptr(),
            &mut w,
            &mut br,
        );
        assert_eq!(s, FRACTUM_ERR_INPUT);
    }

    /// A grain of zero (or negative, or non-finite) radius or mass is refused with
    /// FRACTUM_ERR_INPUT: a zero-radius sphere panicked in the split (FRACTUM_ERR_INTERNAL and
    /// a panic message on the host's stderr).
    #[test]
    fn split_of_a_grain_without_size_or_mass_is_refused_as_input() {
        let mut d = Draw::new(11);
        let fl = fracture_law(4, true, true);
        let hb = FractumTrigger {
            kind: 1,
            ..Default::default()
        };
        let v = [0.0; 3];
        for sphere in [true, false] {
            let good = fb(&random_body(&mut d, sphere));
            for (radius, mass) in [
                (0.0, good.mass),
                (-1e-3, good.mass),
                (f64::NAN, good.mass),
                (f64::INFINITY, good.mass),
                (good.radius, 0.0),
                (good.radius, f64::NAN),
            ] {
                let mut bad = good;
                bad.radius = radius;
                bad.mass = mass;
                let mut split = FractumSplit::default();
                let s = fractum_kernel_split(
                    &fl,
                    &bad,
                    v.as_ptr(),
                    v.as_ptr(),
                    &hb,
                    null(),
                    &mut split,
                );
                assert_eq!(
                    s, FRACTUM_ERR_INPUT,
                    "sphere {sphere}, radius {radius}, mass {mass}"
                );
            }
        }
    }

    /// The kernels leave the handle API's last-error message alone.
    #[test]
    fn kernels_keep_the_last_error() {
        assert_eq!(crate::fractum_free(u64::MAX), FRACTUM_ERR_HANDLE);
        // SAFETY: fractum_last_error returns a valid NUL-terminated string.
        let before = unsafe { std::ffi::CStr::from_ptr(crate::fractum_last_error()) }.to_owned();
        assert!(!before.is_empty());
        let mut x = 0.0;
        assert_eq!(fractum_kernel_body_volume(null(), &mut x), FRACTUM_ERR_NULL);
        let mut law = FractumContactLaw::default();
        assert_eq!(
            fractum_kernel_contact_law(YOUNG, POISSON, 0.5, 0.3, 0, 1, &mut law),
            FRACTUM_OK
        );
        // SAFETY: as above.
        let after = unsafe { std::ffi::CStr::from_ptr(crate::fractum_last_error()) }.to_owned();
        assert_eq!(before, after);
    }
}
