//! Every kernel export, called through the C ABI of libfractum.so (abi.rs), against the
//! library function it wraps called directly on the run's own data (Bodies, placements): the
//! same bits. contact.rs, fracture.rs and integrate.rs by library area; refusals.rs what the
//! kernels refuse. Inputs and expected outputs are converted by the tests' own reference.rs,
//! written from the header's field docs, never by the kernels' conversions they check.

#[path = "../common/mod.rs"]
mod common;
// The library's own definitions of the status and the structs, and every export's signature:
// not every test names each.
#[allow(dead_code)]
#[path = "../../src/status.rs"]
mod status;
#[allow(dead_code)]
#[path = "../../src/kernels/types.rs"]
mod types;
#[macro_use]
#[path = "../../src/kernels/variants.rs"]
mod variants;

#[allow(dead_code)]
mod abi;
mod contact;
mod fracture;
mod integrate;
mod reference;
mod refusals;
mod sums;

use abi::*;
use fractum::contact::convex::{self, ContactGeometry};
use fractum::contact::hertz_mindlin::{
    Hertz, KernelConsts, Mindlin, ViscousDamping, hertz_mindlin,
};
use fractum::contact::pair::{
    BodyAt, ContactBody, PairMemory, PairOut, Placement, pair_contact, skips, travel_step,
    wall_contact,
};
use fractum::fracture::break_plane::{self, Trigger};
use fractum::fracture::cohesion::{self, Demand};
use fractum::fracture::{
    Criterion, MadeSpring, PendingSplit, bond_split, criteria, grain_average_stress, grain_fails,
    split_grain,
};
use fractum::sample::{UNIFORM_COUNTERS, uniforms};
use fractum::shape::PolyEllipsoid;
use fractum::state::{Bodies, Body, Vec3};
use nalgebra::{Matrix3, UnitQuaternion};
use reference::{c_body, c_rows, c_spring, c_vec, law_params};
use status::FractumStatus::*;
use std::ptr::{null, null_mut};
use types::*;

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

/// `actual` is `expected` to round-off (1e-12, relative above 1): for the hand-written
/// values that the library reaches by another order of operations than the test's.
fn near(actual: &[f64], expected: &[f64]) {
    assert_eq!(actual.len(), expected.len());
    for (k, (a, e)) in actual.iter().zip(expected).enumerate() {
        assert!(
            (a - e).abs() <= 1e-12 * e.abs().max(1.0),
            "element {k}: {actual:?} is not {expected:?}"
        );
    }
}

/// The principal moments (kg m^2) of a poly-ellipsoid of mass `mass` whose semi-axes differ
/// between + and - along x only (b+ = b-, c+ = c-): its products of inertia vanish, so its
/// principal frame is its shape frame (PolyEllipsoid::principal_inertia: the identity) and
/// the moments follow from the octants' second moments (an octant of semi-axes a b c has
/// the volume pi a b c / 6, and the integral of x^2 over it is a^2 / 5 times that), moved
/// from the octant origin to the centroid, 3/8 (a+ - a-) along x.
fn moments_lopsided_x(semi: &[f64; 6], mass: f64) -> [f64; 3] {
    let [ap, am, b, bm, c, cm] = *semi;
    assert!(b == bm && c == cm, "lopsided along x only");
    let pi = std::f64::consts::PI;
    let volume = pi / 6.0 * (ap + am) * (2.0 * b) * (2.0 * c);
    let x_bar = 0.375 * (ap - am);
    let xx = pi / 30.0 * (ap.powi(3) + am.powi(3)) * (2.0 * b) * (2.0 * c) - volume * x_bar * x_bar;
    let yy = pi / 30.0 * (ap + am) * (2.0 * b.powi(3)) * (2.0 * c);
    let zz = pi / 30.0 * (ap + am) * (2.0 * b) * (2.0 * c.powi(3));
    let density = mass / volume;
    [
        density * (yy + zz),
        density * (xx + zz),
        density * (xx + yy),
    ]
}

/// The semi-axes of the poly-ellipsoid of [`hand_body`]: lopsided along x only.
const HAND_SEMI: [f64; 6] = [1.0, 0.9, 0.3, 0.3, 0.2, 0.2];

/// A poly-ellipsoid written out field by field, each a recognisable number: centre (1, 2, 3),
/// velocity (4, 5, 6), angular velocity (7, 8, 9), body to world 120 degrees about (1, 1, 1)
/// (x to y, y to z, z to x), 10 kg, the semi-axes [`HAND_SEMI`] (so its principal frame is
/// its shape frame, and what the kernels make of it follows by hand), the shape frame turned
/// 180 degrees about x in the body frame, the octant origin 3/8 (a+ - a-) = 0.0375 behind the
/// centre of mass along x, its bounding radius the tip of a+ from there.
fn hand_body() -> FractumBody {
    FractumBody {
        pos: [1.0, 2.0, 3.0],
        vel: [4.0, 5.0, 6.0],
        omega: [7.0, 8.0, 9.0],
        quat: [0.5, 0.5, 0.5, 0.5],
        mass: 10.0,
        radius: 0.9625,
        semi: HAND_SEMI,
        origin: [-0.0375, 0.0, 0.0],
        to_body: [0.0, 1.0, 0.0, 0.0],
        inertia: moments_lopsided_x(&HAND_SEMI, 10.0),
        sphere: 0,
    }
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
        particle_strength: 0,
        comminution_limit: 0.0,
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
