//! Contact geometry of convex bodies (poly-ellipsoids and spheres) and of a body with a wall:
//! overlap, common normal, contact points and the Hertz equivalent radius from the local
//! curvatures (paper Section 3.1.3 needs the latter for the contact radius).
//!
//! # Algorithm
//!
//! For convex A and B with world support functions `h(n) = n·o + h_local(Rᵀ n)` (o the octant
//! origin, R the shape-to-world rotation), the overlap of their projections on a unit
//! direction `n` pointing from A towards B is
//!
//! ```text
//! δ(n) = h_A(n) + h_B(-n).
//! ```
//!
//! By the separating axis theorem A and B are separated iff `δ(n) < 0` for some `n`; when they
//! overlap, the minimum translation distance (the penetration depth) is `min over unit n of
//! δ(n)` (δ is the support function of the Minkowski difference A - B, and this is the
//! distance from the origin to its boundary). The ambient gradient of δ is
//! `s_A(n) - s_B(-n)` (support points), so at the minimum its tangential part vanishes: the
//! common-normal condition, with contact points `s_A(n)` (the deepest point of A into B) and
//! `s_B(-n)`.
//!
//! δ is minimised by Newton's method on the unit sphere. At `n`, with a tangent basis
//! `(t1, t2)` ([`tangent_basis`], no trigonometry):
//!
//! * gradient `g_i = t_i·(s_A(n) - s_B(-n))`;
//! * Riemannian Hessian `K = (H_A(n) + H_B(-n))_t - δ(n) 1` (the support Hessians restricted
//!   to the tangent plane; the `-δ 1` is the sphere's curvature term, δ being 1-homogeneous);
//! * step `n ← normalize(n - t_i (K⁻¹ g)_i)`, accepted when δ does not increase beyond
//!   round-off, else halved (backtracking). Where K is not positive definite (overlaps deeper
//!   than the sum of the local radii of curvature) its eigenvalues are replaced by their
//!   absolute values, and a zero gradient there is left along the negative-curvature
//!   direction.
//!
//! It stops when `|g| <= 1e-10 (h_A + h_B)` ([`GRADIENT_TOLERANCE`]; `h_A + h_B` is the sum
//! of the local support values, a size of the pair) with K positive definite, or after
//! [`MAX_ITERATIONS`] steps. At that tolerance the normal is within about 1e-10 rad and the
//! depth is exact to round-off (its error is quadratic in g); [`contact_with_tolerance`]
//! takes another. The support function is C1 with a Hessian that jumps across the octant
//! planes, so this is a semismooth Newton method: quadratic inside an octant, superlinear
//! across a plane.
//!
//! Early-outs: if `δ(guess) < 0` the pair is separated and nothing is iterated (the cheap
//! rejection most neighbour pairs take; δ's sign needs no normalised direction, so the
//! normalisation runs beside it); if any iterate has `δ < 0`, likewise. The iteration finds
//! the local minimum of δ nearest the guess, which is the global one unless the overlap is
//! deep compared with the bodies: an overlap above [`DEEP_OVERLAP`] (a quarter) of the
//! thinner body's smallest axis width is therefore solved again from the ± shape axes of
//! both bodies and the smallest minimum kept. (This also catches a guess on the wrong side,
//! which can end in a local minimum on the far side of A - B, as deep as the bodies are wide.) docs/poly_ellipsoid.md has the measured
//! accuracy against brute force.
//!
//! The iteration runs in the shape frame of one poly-ellipsoid, so that its support needs
//! no rotation; the other body's directions are turned by the relative rotation.
//!
//! The Hertz equivalent radius is `r_eff = 1/sqrt(det(K_A + K_B))` with `K_A` the inverse of
//! A's tangent Hessian at `n` (its curvature tensor) and `K_B` likewise at `-n`; for two
//! spheres `r_eff = R_A R_B / (R_A + R_B)`.
//!
//! A wall is closed form: with `n_w` the wall's unit normal (out of the wall),
//! `depth = n_w·(x_w - s_A(-n_w))`, the contact point on the body `s_A(-n_w)`, and
//! `r_eff = 1/sqrt(det K_A) = sqrt(det (H_A(-n_w))_t)`. The sleeve: [`sleeve_contact`].

use nalgebra::{Matrix3, Vector3};

use crate::shape::poly_ellipsoid::{
    PolyEllipsoid, Support, newton_step2, sym2_eigen, tangent_basis,
};

/// At most this many Newton steps per contact query.
pub const MAX_ITERATIONS: u32 = 30;

/// Overlaps deeper than this fraction of the thinner body's smallest axis width are solved
/// again from the shape axes of both bodies (see [`contact`]).
pub const DEEP_OVERLAP: f64 = 0.25;

/// Converged when the tangential gradient is below this fraction of `h_A + h_B`.
pub const GRADIENT_TOLERANCE: f64 = 1e-10;

/// A convex shape in its own frame.
#[derive(Debug, Clone, Copy)]
pub enum ConvexShape<'a> {
    Sphere { radius: f64 },
    PolyEllipsoid(&'a PolyEllipsoid),
}

/// A shape placed in the world.
#[derive(Debug, Clone, Copy)]
pub struct Placed<'a> {
    pub shape: ConvexShape<'a>,
    /// World position of the octant origin (m); a sphere's centre.
    pub origin: Vector3<f64>,
    /// Rotation from the shape frame to the world frame (orthonormal; unused for a sphere).
    pub rot: Matrix3<f64>,
}

impl<'a> Placed<'a> {
    pub fn sphere(radius: f64, centre: Vector3<f64>) -> Self {
        Placed {
            shape: ConvexShape::Sphere { radius },
            origin: centre,
            rot: Matrix3::identity(),
        }
    }

    pub fn poly_ellipsoid(pe: &'a PolyEllipsoid, origin: Vector3<f64>, rot: Matrix3<f64>) -> Self {
        Placed {
            shape: ConvexShape::PolyEllipsoid(pe),
            origin,
            rot,
        }
    }

    /// World position of the centroid (m).
    pub fn centroid(&self) -> Vector3<f64> {
        match self.shape {
            ConvexShape::Sphere { .. } => self.origin,
            ConvexShape::PolyEllipsoid(pe) => self.origin + self.rot * pe.centroid(),
        }
    }
}

/// Geometry of one contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactGeometry {
    /// Unit normal pointing from B to A: the force on A acts along it.
    pub normal: Vector3<f64>,
    /// Overlap (m), > 0: the minimum translation distance.
    pub depth: f64,
    /// World contact point (m), midway between the two deepest points.
    pub point: Vector3<f64>,
    /// Deepest point of A into B (m, world).
    pub point_a: Vector3<f64>,
    /// Deepest point of B into A (m, world); for a wall, the foot of `point_a` on the plane.
    pub point_b: Vector3<f64>,
    /// Hertz equivalent radius (m): `1/sqrt(det(K_A + K_B))`, K the curvature tensors on the
    /// tangent plane.
    pub r_eff: f64,
    /// Newton steps taken, summed over the restarts of a deep overlap (0 for a wall, or when
    /// the guess was already converged).
    pub iterations: u32,
}

/// World support point of `p` in direction `d` (any nonzero `d`).
#[inline]
pub fn support_world(p: &Placed, d: &Vector3<f64>) -> Vector3<f64> {
    match p.shape {
        ConvexShape::Sphere { radius } => p.origin + d * (radius / d.norm()),
        ConvexShape::PolyEllipsoid(pe) => p.origin + p.rot * pe.support(&p.rot.tr_mul(d)),
    }
}

/// One body's support at one direction `d` of the iteration frame (for a sphere only `h`).
///
/// Probes are taken at directions of any length `|d|` (the support point is 0-homogeneous, the
/// support value 1-homogeneous) so that normalising `d` runs beside them; [`rescale`] then
/// makes them those of the unit direction.
type Probe = Support;

/// From a probe at direction `d` to one at `d/|d|`, given `|d|` and `1/|d|`.
#[inline(always)]
fn rescale(p: &mut Probe, norm: f64, inv_norm: f64) {
    p.h *= inv_norm;
    p.inv_h *= norm;
}

/// One body as the Newton iteration sees it. The iteration runs in the shape frame of one
/// poly-ellipsoid (so its support needs no rotation); the other body's directions are turned
/// into its own frame by `to_body`.
trait Side {
    /// Direction `d` of the iteration frame in the body's frame.
    fn to_body(&self, d: &Vector3<f64>) -> Vector3<f64>;
    /// Support value and point at the body-frame direction `dl` of length `norm`.
    fn probe(&self, dl: &Vector3<f64>, norm: f64) -> Probe;
    /// `t_i·s` (iteration frame) and the support Hessian on the tangent plane, `[r11, r12, r22]`,
    /// at a probe of a unit direction.
    fn tangent(&self, p: &Probe, t1: &Vector3<f64>, t2: &Vector3<f64>) -> ([f64; 2], [f64; 3]);
    /// World position of the support point of the probe at the unit iteration-frame direction `d`.
    fn world_point(&self, p: &Probe, d: &Vector3<f64>) -> Vector3<f64>;
    /// The body's shape axes in the iteration frame (columns).
    fn axes(&self) -> Matrix3<f64>;
    /// The smallest width along the shape axes (m), the scale of a deep overlap.
    fn axis_width(&self) -> f64;
}

/// A sphere: `h(d) = r |d|`, support Hessian `r (1 - d dᵀ)` at a unit `d`.
struct SphereSide {
    radius: f64,
    centre: Vector3<f64>,
    /// Iteration frame to world.
    frame: Matrix3<f64>,
}

impl SphereSide {
    /// The sphere `p` (its centre is `p.origin`), the iteration frame mapped to the world by
    /// `frame`.
    fn new(radius: f64, p: &Placed, frame: Matrix3<f64>) -> Self {
        SphereSide {
            radius,
            centre: p.origin,
            frame,
        }
    }
}

impl Side for SphereSide {
    #[inline(always)]
    fn to_body(&self, d: &Vector3<f64>) -> Vector3<f64> {
        *d
    }
    #[inline(always)]
    fn probe(&self, _: &Vector3<f64>, norm: f64) -> Probe {
        sphere_probe(self.radius, norm)
    }
    #[inline(always)]
    fn tangent(&self, _: &Probe, _: &Vector3<f64>, _: &Vector3<f64>) -> ([f64; 2], [f64; 3]) {
        ([0.0, 0.0], [self.radius, 0.0, self.radius])
    }
    #[inline(always)]
    fn world_point(&self, _: &Probe, d: &Vector3<f64>) -> Vector3<f64> {
        self.centre + self.frame * (d * self.radius)
    }
    fn axes(&self) -> Matrix3<f64> {
        Matrix3::identity()
    }
    /// Infinite: a sphere does not make local minima of δ (against a sphere δ(n) = n·d + r_A + r_B
    /// has one), so only a poly-ellipsoid's width calls for the deep-overlap restarts.
    fn axis_width(&self) -> f64 {
        f64::INFINITY
    }
}

/// A sphere's probe at a direction of length `norm`: `h = r |d|`.
#[inline(always)]
fn sphere_probe(radius: f64, norm: f64) -> Probe {
    Probe {
        h: radius * norm,
        inv_h: 0.0,
        point: Vector3::zeros(),
        m2: Vector3::zeros(),
    }
}

/// A poly-ellipsoid; `rot` maps iteration-frame vectors into its shape frame (`None`: the
/// iteration runs in its own frame).
struct PolySide<'a> {
    pe: &'a PolyEllipsoid,
    rot: Option<Matrix3<f64>>,
    origin: Vector3<f64>,
    to_world: Matrix3<f64>,
}

impl<'a> PolySide<'a> {
    /// `pe` placed as `p`, the iteration running in its own shape frame.
    fn own(pe: &'a PolyEllipsoid, p: &Placed) -> Self {
        PolySide {
            pe,
            rot: None,
            origin: p.origin,
            to_world: p.rot,
        }
    }

    /// `pe` placed as `p`, the iteration frame turned into its shape frame by `rot`.
    fn turned(pe: &'a PolyEllipsoid, p: &Placed, rot: Matrix3<f64>) -> Self {
        PolySide {
            rot: Some(rot),
            ..PolySide::own(pe, p)
        }
    }
}

impl Side for PolySide<'_> {
    #[inline(always)]
    fn to_body(&self, d: &Vector3<f64>) -> Vector3<f64> {
        match &self.rot {
            Some(r) => r * d,
            None => *d,
        }
    }
    #[inline(always)]
    fn probe(&self, dl: &Vector3<f64>, _: f64) -> Probe {
        self.pe.support_at(dl)
    }
    #[inline(always)]
    fn tangent(&self, p: &Probe, t1: &Vector3<f64>, t2: &Vector3<f64>) -> ([f64; 2], [f64; 3]) {
        let (t1, t2) = (self.to_body(t1), self.to_body(t2));
        (
            [t1.dot(&p.point), t2.dot(&p.point)],
            p.tangent_hessian(&t1, &t2),
        )
    }
    #[inline(always)]
    fn world_point(&self, p: &Probe, _: &Vector3<f64>) -> Vector3<f64> {
        self.origin + self.to_world * p.point
    }
    fn axes(&self) -> Matrix3<f64> {
        match &self.rot {
            Some(r) => r.transpose(),
            None => Matrix3::identity(),
        }
    }
    fn axis_width(&self) -> f64 {
        let s = &self.pe.semi;
        (s[0] + s[1]).min(s[2] + s[3]).min(s[4] + s[5])
    }
}

/// The value of δ, its tangential gradient and the tangent Hessians of the two supports at one
/// unit direction `m` of the iteration frame.
struct Eval {
    m: Vector3<f64>,
    t1: Vector3<f64>,
    t2: Vector3<f64>,
    delta: f64,
    pa: Probe,
    pb: Probe,
    g: [f64; 2],
    ha: [f64; 3],
    hb: [f64; 3],
}

/// Completes an evaluation from the two probes at the unit direction `m`.
#[inline(always)]
fn evaluate<A: Side, B: Side>(
    a: &A,
    b: &B,
    rel: &Vector3<f64>,
    m: Vector3<f64>,
    delta: f64,
    pa: Probe,
    pb: Probe,
) -> Eval {
    let (t1, t2) = tangent_basis(&m);
    let (sa, ha) = a.tangent(&pa, &t1, &t2);
    let (sb, hb) = b.tangent(&pb, &t1, &t2);
    Eval {
        g: [t1.dot(rel) + sa[0] - sb[0], t2.dot(rel) + sa[1] - sb[1]],
        m,
        t1,
        t2,
        delta,
        pa,
        pb,
        ha,
        hb,
    }
}

/// The Newton step `-K⁻¹ g` in tangent coordinates, with K's eigenvalues made positive where
/// it is not positive definite (and a push of 0.5 rad along a negative-curvature direction
/// when the gradient vanishes there). At most 0.5 rad long.
#[inline]
fn newton_step(k: &[f64; 3], g: &[f64; 2], tol: f64) -> [f64; 2] {
    let det = k[0] * k[2] - k[1] * k[1];
    let mut v = if k[0] > 0.0 && det > 0.0 {
        newton_step2(k, g)
    } else {
        let (lambda, e) = sym2_eigen(*k);
        let floor = 1e-6 * lambda[0].abs().max(lambda[1].abs()).max(f64::MIN_POSITIVE);
        let mut v = [0.0; 2];
        for (l, e) in lambda.iter().zip(e.iter()) {
            let ge = g[0] * e[0] + g[1] * e[1];
            let mut c = -ge / l.abs().max(floor);
            if *l < 0.0 && ge.abs() <= tol {
                c = 0.5;
            }
            v[0] += c * e[0];
            v[1] += c * e[1];
        }
        v
    };
    let len2 = v[0] * v[0] + v[1] * v[1];
    if len2 > 0.25 {
        let shrink = 0.5 / len2.sqrt();
        v[0] *= shrink;
        v[1] *= shrink;
    }
    v
}

/// Contact between convex bodies A and B, or `None` when they are separated.
///
/// `guess` is a direction in the convention of [`ContactGeometry::normal`] (from B towards A,
/// any length): the previous step's normal (warm start) or the centre-to-centre vector
/// `x_A - x_B`. A zero or non-finite guess falls back to the centroid-to-centroid direction,
/// and coincident centroids to +x.
pub fn contact(a: &Placed, b: &Placed, guess: &Vector3<f64>) -> Option<ContactGeometry> {
    contact_with_tolerance(a, b, guess, GRADIENT_TOLERANCE).ok()
}

/// [`contact`], or when A and B are separated `Err(gap)`: the gap (m, >= 0) between their
/// projections on the separating direction `m` the search met, `-δ(m)`. The bodies touch only
/// where δ >= 0 in every direction, and δ(m) changes by at most the two centroids'
/// translations plus each body's bounding radius (about its centroid) times its rotation
/// angle: while those motions add up to less than `gap`, A and B stay apart. 0 where it cannot
/// be told (NaN).
pub fn contact_or_gap(
    a: &Placed,
    b: &Placed,
    guess: &Vector3<f64>,
) -> Result<ContactGeometry, f64> {
    contact_with_tolerance(a, b, guess, GRADIENT_TOLERANCE)
}

/// The gap `-raw / norm` of a separating probe (`raw = norm δ`), 0 for NaN.
#[inline(always)]
fn gap_of(raw: f64, norm: f64) -> f64 {
    let g = -raw / norm;
    if g > 0.0 { g } else { 0.0 }
}

/// [`contact_or_gap`] with the convergence tolerance on the tangential gradient, as a fraction
/// of `h_A + h_B`, given (docs/poly_ellipsoid.md shows what it costs and buys).
pub fn contact_with_tolerance(
    a: &Placed,
    b: &Placed,
    guess: &Vector3<f64>,
    tolerance: f64,
) -> Result<ContactGeometry, f64> {
    let m = initial_direction(a, b, guess);
    let d0 = a.origin - b.origin;
    // δ's sign at the guess needs no normalised direction (h is 1-homogeneous).
    let (qa, ma) = probe_placed(a, &m);
    let (qb, mb) = probe_placed(b, &-m);
    let raw = m.dot(&d0) + qa.h + qb.h;
    if below_zero(raw) {
        return Err(gap_of(raw, m.norm_squared().sqrt()));
    }
    let norm = m.norm_squared().sqrt();
    // The iteration runs in the frame of a poly-ellipsoid (A's if it is one), so that one of
    // the two supports needs no rotation.
    let start = |frame: Matrix3<f64>, m: Vector3<f64>| Start {
        rel: frame.tr_mul(&d0),
        frame,
        m,
        norm,
        raw,
        pa: qa,
        pb: qb,
    };
    match (a.shape, b.shape) {
        (ConvexShape::PolyEllipsoid(pa), ConvexShape::PolyEllipsoid(pb)) => {
            let sb = PolySide::turned(pb, b, b.rot.tr_mul(&a.rot));
            solve(&PolySide::own(pa, a), &sb, start(a.rot, ma), tolerance)
        }
        (ConvexShape::Sphere { radius }, ConvexShape::PolyEllipsoid(pb)) => {
            let sa = SphereSide::new(radius, a, b.rot);
            solve(&sa, &PolySide::own(pb, b), start(b.rot, -mb), tolerance)
        }
        (ConvexShape::PolyEllipsoid(pa), ConvexShape::Sphere { radius }) => {
            let sb = SphereSide::new(radius, b, a.rot);
            solve(&PolySide::own(pa, a), &sb, start(a.rot, ma), tolerance)
        }
        (ConvexShape::Sphere { radius: ra }, ConvexShape::Sphere { radius: rb }) => {
            let i = Matrix3::identity();
            let (sa, sb) = (SphereSide::new(ra, a, i), SphereSide::new(rb, b, i));
            solve(&sa, &sb, start(i, m), tolerance)
        }
    }
}

/// Where the iteration starts: the iteration frame (`frame` maps it to the world), `o_A - o_B`
/// in it, the direction `m` from A towards B of length `norm` with `raw = |m| δ(m/|m|) >= 0`,
/// and the two probes taken at `m` and `-m`.
struct Start {
    frame: Matrix3<f64>,
    rel: Vector3<f64>,
    m: Vector3<f64>,
    norm: f64,
    raw: f64,
    pa: Probe,
    pb: Probe,
}

/// The probe of a placed body at the world direction `d` (any length), and `d` in its shape
/// frame.
#[inline(always)]
fn probe_placed(p: &Placed, d: &Vector3<f64>) -> (Probe, Vector3<f64>) {
    match p.shape {
        ConvexShape::Sphere { radius } => (sphere_probe(radius, d.norm_squared().sqrt()), *d),
        ConvexShape::PolyEllipsoid(pe) => {
            let dl = p.rot.tr_mul(d);
            (pe.support_at(&dl), dl)
        }
    }
}

/// Minimises δ from `start`. An overlap deeper than [`DEEP_OVERLAP`] of the thinner body's
/// smallest axis width is solved again from the ± shape axes of both bodies, keeping the
/// smallest minimum (deep overlaps can have several local minima).
#[inline(always)]
fn solve<A: Side, B: Side>(
    a: &A,
    b: &B,
    start: Start,
    tolerance: f64,
) -> Result<ContactGeometry, f64> {
    let Start {
        frame,
        rel,
        m,
        norm,
        raw,
        pa,
        pb,
    } = start;
    let (mut best, mut iterations) = newton(a, b, &rel, m, norm, raw, pa, pb, tolerance)?;
    if best.delta > DEEP_OVERLAP * a.axis_width().min(b.axis_width()) {
        for axes in [a.axes(), b.axes()] {
            for k in 0..6 {
                let d = axes.column(k / 2) * if k % 2 == 0 { 1.0 } else { -1.0 };
                let (qa, qb) = (a.probe(&a.to_body(&d), 1.0), b.probe(&b.to_body(&-d), 1.0));
                let raw = d.dot(&rel) + qa.h + qb.h;
                if below_zero(raw) {
                    return Err(gap_of(raw, 1.0));
                }
                let (e, steps) = newton(a, b, &rel, d, 1.0, raw, qa, qb, tolerance)?;
                iterations += steps;
                if e.delta < best.delta {
                    best = e;
                }
            }
        }
    }
    let e = best;
    let point_a = a.world_point(&e.pa, &e.m);
    let point_b = b.world_point(&e.pb, &-e.m);
    // r_eff = 1/sqrt(det(K_A + K_B)) with K = H⁻¹ = adj(H)/det(H): one square root, one division.
    let (ha, hb) = (&e.ha, &e.hb);
    let (da, db) = (ha[0] * ha[2] - ha[1] * ha[1], hb[0] * hb[2] - hb[1] * hb[1]);
    let x = [
        db * ha[2] + da * hb[2],
        db * ha[1] + da * hb[1],
        db * ha[0] + da * hb[0],
    ];
    Ok(ContactGeometry {
        normal: -(frame * e.m),
        depth: e.delta,
        point: 0.5 * (point_a + point_b),
        point_a,
        point_b,
        r_eff: da * db / (x[0] * x[2] - x[1] * x[1]).sqrt(),
        iterations,
    })
}

/// Newton's method on the unit sphere for `min δ(m)` from `m` of length `norm` (see
/// [`Start`]): the converged
/// evaluation and the steps taken, or `None` when an iterate shows δ < 0 (separated).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn newton<A: Side, B: Side>(
    a: &A,
    b: &B,
    rel: &Vector3<f64>,
    m: Vector3<f64>,
    norm: f64,
    raw: f64,
    mut pa: Probe,
    mut pb: Probe,
    tolerance: f64,
) -> Result<(Eval, u32), f64> {
    let inv = 1.0 / norm;
    rescale(&mut pa, norm, inv);
    rescale(&mut pb, norm, inv);
    let scale = pa.h + pb.h;
    let tol = tolerance * scale;
    // δ sums terms of size `scale` and `|rel|`: changes below this are round-off.
    let round = 1e-14 * (scale + rel.amax());
    let mut e = evaluate(a, b, rel, m * inv, raw * inv, pa, pb);
    let mut iterations = 0;
    loop {
        let k = [
            e.ha[0] + e.hb[0] - e.delta,
            e.ha[1] + e.hb[1],
            e.ha[2] + e.hb[2] - e.delta,
        ];
        let positive = k[0] > 0.0 && k[0] * k[2] > k[1] * k[1];
        let g2 = e.g[0] * e.g[0] + e.g[1] * e.g[1];
        if (g2 <= tol * tol && positive) || iterations >= MAX_ITERATIONS {
            break;
        }
        let mut v = newton_step(&k, &e.g, tol);
        let mut accepted = false;
        for _ in 0..40 {
            // |step| >= 1; the probes run on the unnormalised step beside its normalisation
            // (only a sphere's probe uses the length).
            let step = e.m + v[0] * e.t1 + v[1] * e.t2;
            let norm = step.norm_squared().sqrt();
            let mut qa = a.probe(&a.to_body(&step), norm);
            let mut qb = b.probe(&b.to_body(&-step), norm);
            let raw = step.dot(rel) + qa.h + qb.h;
            if below_zero(raw) {
                return Err(gap_of(raw, norm));
            }
            if raw <= norm * (e.delta + round) {
                let inv = 1.0 / norm;
                rescale(&mut qa, norm, inv);
                rescale(&mut qb, norm, inv);
                e = evaluate(a, b, rel, step * inv, raw * inv, qa, qb);
                accepted = true;
                break;
            }
            v[0] *= 0.5;
            v[1] *= 0.5;
        }
        if !accepted {
            break;
        }
        iterations += 1;
    }
    if at_most_zero(e.delta) {
        return Err(gap_of(e.delta, 1.0));
    }
    Ok((e, iterations))
}

/// `x < 0`, or NaN: a NaN from degenerate input never counts as an overlap.
#[inline(always)]
fn below_zero(x: f64) -> bool {
    x.is_nan() || x < 0.0
}

/// `x <= 0`, or NaN.
#[inline(always)]
fn at_most_zero(x: f64) -> bool {
    x.is_nan() || x <= 0.0
}

/// The starting direction from A towards B (any length): `-guess`, else centroid to
/// centroid, else +x.
#[inline]
fn initial_direction(a: &Placed, b: &Placed, guess: &Vector3<f64>) -> Vector3<f64> {
    let n2 = guess.norm_squared();
    if n2 > 0.0 && n2.is_finite() {
        return -guess;
    }
    let c = b.centroid() - a.centroid();
    let c2 = c.norm_squared();
    if c2 > 0.0 && c2.is_finite() {
        c
    } else {
        Vector3::x()
    }
}

/// Contact of body A with a wall, or `None` when A is clear of it.
///
/// The wall is the half-space behind the plane through `wall_point`; `wall_normal` (unit)
/// points out of the wall into the free space. Closed form: `depth = n_w·(x_w - s_A(-n_w))`,
/// `point_a = s_A(-n_w)`, `point_b` its foot on the plane, `r_eff = sqrt(det (H_A(-n_w))_t)`.
pub fn wall_contact(
    a: &Placed,
    wall_normal: &Vector3<f64>,
    wall_point: &Vector3<f64>,
) -> Option<ContactGeometry> {
    let base = wall_normal.dot(&(wall_point - a.origin));
    let (depth, point_a, r) = match a.shape {
        ConvexShape::Sphere { radius } => (
            base + radius,
            a.origin - wall_normal * radius,
            [radius, 0.0, radius],
        ),
        ConvexShape::PolyEllipsoid(pe) => {
            let side = PolySide::own(pe, a);
            let m = -a.rot.tr_mul(wall_normal);
            let p = pe.support_at(&m);
            if at_most_zero(base + p.h) {
                return None;
            }
            let (t1, t2) = tangent_basis(&m);
            (
                base + p.h,
                side.world_point(&p, &m),
                side.tangent(&p, &t1, &t2).1,
            )
        }
    };
    if at_most_zero(depth) {
        return None;
    }
    let point_b = point_a + depth * wall_normal;
    Some(ContactGeometry {
        normal: *wall_normal,
        depth,
        point: 0.5 * (point_a + point_b),
        point_a,
        point_b,
        r_eff: (r[0] * r[2] - r[1] * r[1]).sqrt(),
        iterations: 0,
    })
}

mod sleeve;
pub use sleeve::{SLEEVE_ITERATIONS, sleeve_contact, sleeve_hertz_radius};

#[cfg(test)]
mod tests;
