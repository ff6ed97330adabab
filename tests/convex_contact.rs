//! Convex contact (src/contact/convex.rs) against brute-force surface sampling, closed forms
//! and a numerical fit of the gap function.
//!
//! Brute force: each surface is sampled by rays from its octant origin on a cube grid
//! (6 × 24², `PolyEllipsoid::surface_point`, independent of the support function), and the
//! overlap `δ(n) = max_A n·x - min_B n·y` is evaluated on a grid of 6 × 16² directions n. The
//! three best well-separated directions are refined by pattern search on the sphere, each
//! evaluation maximising `n·x` over the surface by a pattern search of its own from the best
//! grid sample; both searches stop at a parameter step of 1e-10 (a surface spacing of about
//! 1e-10 of the size), where the sampling error `κ (spacing)²/8` is far below round-off. The
//! brute force is then exact to round-off (about 1e-15 of the size), and the tolerances below
//! are set by round-off and by the search's resolution of the direction, not by sampling.

use fractum::contact::convex::{
    ContactGeometry, ConvexShape, GRADIENT_TOLERANCE, Placed, contact, contact_or_gap,
    contact_with_tolerance, support_world, wall_contact,
};
use fractum::shape::poly_ellipsoid::{PolyEllipsoid, cube_direction, cube_grid};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

type V3 = Vector3<f64>;

/// Size of the particles (m): the base radius of every random shape.
const R: f64 = 0.3e-3;

fn uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}

fn random_rotation(rng: &mut ChaCha8Rng) -> Matrix3<f64> {
    // Shoemake's uniform quaternion.
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let tau = std::f64::consts::TAU;
    let q = nalgebra::Quaternion::new(
        u1.sqrt() * (tau * u3).cos(),
        (1.0 - u1).sqrt() * (tau * u2).sin(),
        (1.0 - u1).sqrt() * (tau * u2).cos(),
        u1.sqrt() * (tau * u3).sin(),
    );
    UnitQuaternion::from_quaternion(q)
        .to_rotation_matrix()
        .into_inner()
}

fn random_direction(rng: &mut ChaCha8Rng) -> V3 {
    loop {
        let v = V3::new(
            uniform(rng, -1.0, 1.0),
            uniform(rng, -1.0, 1.0),
            uniform(rng, -1.0, 1.0),
        );
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return v / n;
        }
    }
}

/// Shapes of the random pool: semi-axes from 1 to 2 times R, split-like halves and flat
/// sub-particles with a- = 0.1 a+.
fn random_shape(rng: &mut ChaCha8Rng, kind: usize) -> PolyEllipsoid {
    let semi = match kind % 4 {
        0 | 1 => std::array::from_fn(|_| R * uniform(rng, 1.0, 2.0)),
        2 => [0.9, 0.1, 0.95, 0.95, 0.95, 0.95].map(|v| v * R),
        _ => {
            let a = R * uniform(rng, 1.0, 2.0);
            [
                a,
                0.1 * a,
                R * uniform(rng, 1.0, 2.0),
                R * uniform(rng, 1.0, 2.0),
                R * uniform(rng, 1.0, 2.0),
                R * uniform(rng, 1.0, 2.0),
            ]
        }
    };
    PolyEllipsoid::new(semi).unwrap()
}

/// World surface point on the ray from the octant origin along the shape-frame direction `u`.
fn surface_world(p: &Placed, u: &V3) -> V3 {
    match p.shape {
        ConvexShape::Sphere { radius } => p.origin + radius * u.normalize(),
        ConvexShape::PolyEllipsoid(pe) => p.origin + p.rot * pe.surface_point(u),
    }
}

/// Pattern search maximising `f(cube_direction(face, s, t))` from `(s, t)` with initial step
/// `step`: the best of the 8 neighbours is taken, the step halved when none improves, down to
/// 1e-10. Returns (max, s, t).
fn pattern_max(
    f: &dyn Fn(&V3) -> f64,
    face: usize,
    mut s: f64,
    mut t: f64,
    mut step: f64,
) -> (f64, f64, f64) {
    let mut best = f(&cube_direction(face, s, t));
    while step > 1e-10 {
        let mut moved = None;
        for (ds, dt) in [
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, 1.0),
            (0.0, -1.0),
            (1.0, 1.0),
            (1.0, -1.0),
            (-1.0, 1.0),
            (-1.0, -1.0),
        ] {
            let (s1, t1) = (s + ds * step, t + dt * step);
            let v = f(&cube_direction(face, s1, t1));
            if v > best {
                best = v;
                moved = Some((s1, t1));
            }
        }
        match moved {
            Some((s1, t1)) => (s, t) = (s1, t1),
            None => step *= 0.5,
        }
    }
    (best, s, t)
}

const SURFACE_GRID: usize = 24;
const DIRECTION_GRID: usize = 16;

/// A body with its coarse surface samples (world points and their ray parameters).
struct Sampled<'a> {
    placed: Placed<'a>,
    points: Vec<(V3, usize, f64, f64)>,
}

impl<'a> Sampled<'a> {
    fn new(placed: Placed<'a>) -> Self {
        let points = cube_grid(SURFACE_GRID)
            .map(|(f, s, t)| (surface_world(&placed, &cube_direction(f, s, t)), f, s, t))
            .collect();
        Sampled { placed, points }
    }

    /// `max over the surface of n·x`: best coarse sample, then pattern search on the ray.
    fn support(&self, n: &V3) -> f64 {
        let mut best = (f64::NEG_INFINITY, 0, 0.0, 0.0);
        for &(p, f, s, t) in &self.points {
            let v = n.dot(&p);
            if v > best.0 {
                best = (v, f, s, t);
            }
        }
        let f = |u: &V3| n.dot(&surface_world(&self.placed, u));
        pattern_max(&f, best.1, best.2, best.3, 2.0 / SURFACE_GRID as f64).0
    }
}

/// Brute-force minimum over unit n (from A to B) of δ(n) = h_A(n) + h_B(-n); returns
/// (depth, normal from B to A).
fn brute_force(a: &Placed, b: &Placed) -> (f64, V3) {
    let (sa, sb) = (Sampled::new(*a), Sampled::new(*b));
    let mut coarse: Vec<(f64, usize, f64, f64)> = cube_grid(DIRECTION_GRID)
        .map(|(f, s, t)| {
            let n = cube_direction(f, s, t);
            let ha = sa
                .points
                .iter()
                .map(|p| n.dot(&p.0))
                .fold(f64::NEG_INFINITY, f64::max);
            let hb = sb
                .points
                .iter()
                .map(|p| -n.dot(&p.0))
                .fold(f64::NEG_INFINITY, f64::max);
            (ha + hb, f, s, t)
        })
        .collect();
    coarse.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut starts: Vec<(usize, f64, f64)> = Vec::new();
    for &(_, f, s, t) in &coarse {
        let n = cube_direction(f, s, t);
        if starts
            .iter()
            .all(|&(g, u, v)| cube_direction(g, u, v).dot(&n) < 0.95)
        {
            starts.push((f, s, t));
            if starts.len() == 3 {
                break;
            }
        }
    }
    let delta = |n: &V3| -(sa.support(n) + sb.support(&-n));
    let mut best = (f64::INFINITY, V3::zeros());
    for (f, s, t) in starts {
        let (v, s, t) = pattern_max(&delta, f, s, t, 2.0 / DIRECTION_GRID as f64);
        if -v < best.0 {
            best = (-v, -cube_direction(f, s, t));
        }
    }
    best
}

fn angle(u: &V3, v: &V3) -> f64 {
    u.cross(v).norm().atan2(u.dot(v))
}

/// Places B so that m (unit, from A to B) satisfies the common-normal condition with overlap
/// `target`: B's support point along -m is A's along m moved back by `target m`. For small
/// overlaps the minimum translation distance is then `target` along m.
fn place<'a>(
    a: &Placed<'a>,
    b_shape: ConvexShape<'a>,
    b_rot: Matrix3<f64>,
    m: &V3,
    target: f64,
) -> Placed<'a> {
    let mut b = Placed {
        shape: b_shape,
        origin: V3::zeros(),
        rot: b_rot,
    };
    let tip_b = support_world(&b, &-m);
    b.origin = support_world(a, m) - target * m - tip_b;
    b
}

/// Checks the finiteness of a contact and the common-normal condition to the accuracy the
/// convergence tolerance `tol` allows: the tangential offset of the deepest points is the
/// gradient, at most `tol (h_A + h_B) <= tol · 4R` (semi-axes up to 2R), and the surface
/// normals turn by that offset over a radius of curvature (at least 0.01 R for the flat
/// halves). Returns the offset.
fn check_common_normal(a: &Placed, b: &Placed, c: &ContactGeometry, tol: f64) -> f64 {
    let all = [c.normal, c.point, c.point_a, c.point_b];
    assert!(
        all.iter().all(|v| v.iter().all(|x| x.is_finite()))
            && c.depth.is_finite()
            && c.r_eff.is_finite()
    );
    assert!(c.r_eff > 0.0);
    assert!((c.normal.norm() - 1.0).abs() < 1e-14);
    let d = c.point_a - c.point_b;
    let tangential = (d - c.normal * c.normal.dot(&d)).norm();
    assert!((-c.normal.dot(&d) - c.depth).abs() < 1e-14 * R * 10.0);
    // Surface normals at the deepest points: -normal on A, +normal on B.
    let outward = |p: &Placed, x: &V3| match p.shape {
        ConvexShape::Sphere { .. } => (x - p.origin).normalize(),
        ConvexShape::PolyEllipsoid(pe) => p.rot * pe.normal_at(&p.rot.tr_mul(&(x - p.origin))),
    };
    let err_a = angle(&outward(a, &c.point_a), &-c.normal);
    let err_b = angle(&outward(b, &c.point_b), &c.normal);
    let offset = tol * 4.0 * R + 1e-14 * R;
    assert!(
        tangential < offset,
        "common normal: tangential offset {tangential:e}"
    );
    let turn = offset / (0.01 * R) + 1e-9;
    assert!(
        err_a < turn && err_b < turn,
        "surface normals off by {err_a:e}, {err_b:e}"
    );
    tangential
}

struct Pair {
    shapes: [PolyEllipsoid; 2],
    rots: [Matrix3<f64>; 2],
    sphere_a: Option<f64>,
    m: V3,
    target: f64,
}

fn random_pair(rng: &mut ChaCha8Rng, i: usize, target: f64) -> Pair {
    let shapes = [random_shape(rng, i), random_shape(rng, i / 4 + 1)];
    let rots = [random_rotation(rng), random_rotation(rng)];
    let sphere_a = (i % 5 == 4).then(|| R * uniform(rng, 1.0, 2.0));
    let m = random_direction(rng);
    Pair {
        shapes,
        rots,
        sphere_a,
        m,
        target,
    }
}

fn placed_pair(p: &Pair) -> (Placed<'_>, Placed<'_>) {
    let origin = V3::new(1.2e-3, -0.7e-3, 2.1e-3);
    let a = match p.sphere_a {
        Some(r) => Placed::sphere(r, origin),
        None => Placed::poly_ellipsoid(&p.shapes[0], origin, p.rots[0]),
    };
    let b = place(
        &a,
        ConvexShape::PolyEllipsoid(&p.shapes[1]),
        p.rots[1],
        &p.m,
        p.target,
    );
    (a, b)
}

#[test]
fn random_pairs_match_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let (mut worst_depth, mut worst_rel, mut worst_angle, mut worst_tangent) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut overlapping, mut separated, mut max_iter, mut sum_iter) = (0, 0, 0, 0);
    let mut smallest: f64 = f64::INFINITY;
    let mut back_steps = 0;
    for i in 0..240 {
        // Overlaps log-uniform in [1e-4, 5e-2] R along m; one pair in six is separated.
        let target = if i % 6 == 5 {
            -R * 10f64.powf(uniform(&mut rng, -4.0, -1.3))
        } else {
            R * 10f64.powf(uniform(&mut rng, -4.0, -1.3))
        };
        let pair = random_pair(&mut rng, i, target);
        let (a, b) = placed_pair(&pair);
        let (bf_depth, bf_normal) = brute_force(&a, &b);
        let got = contact(&a, &b, &(a.centroid() - b.centroid()));
        if bf_depth < 0.0 {
            assert!(
                got.is_none(),
                "pair {i}: separated by {:e} but contact {got:?}",
                -bf_depth
            );
            separated += 1;
            continue;
        }
        let err = check_against_brute_force(i, &a, &b, got, bf_depth, &bf_normal);
        let c = got.unwrap();
        // A guess on the wrong side (from A towards B) starts near the maximum of δ; the
        // iteration may end in a local minimum on the far side, deep enough to be solved again.
        let back = contact(&a, &b, &(b.centroid() - a.centroid()));
        check_against_brute_force(i, &a, &b, back, bf_depth, &bf_normal);
        back_steps = back_steps.max(back.unwrap().iterations);
        overlapping += 1;
        smallest = smallest.min(bf_depth / R);
        worst_depth = worst_depth.max(err);
        worst_rel = worst_rel.max(err * R / bf_depth);
        worst_angle = worst_angle.max(angle(&c.normal, &bf_normal));
        // Converged further, the common-normal condition holds to round-off.
        let tight = contact_with_tolerance(&a, &b, &(a.centroid() - b.centroid()), 1e-13).unwrap();
        worst_tangent = worst_tangent.max(check_common_normal(&a, &b, &tight, 1e-13) / R);
        assert!((tight.depth - c.depth).abs() <= 1e-14 * R);
        max_iter = max_iter.max(c.iterations);
        sum_iter += c.iterations;
    }
    println!(
        "{overlapping} overlapping (smallest {smallest:.2e} R), {separated} separated; |depth - brute force| <= {worst_depth:.2e} R \
         ({worst_rel:.2e} of the overlap); normal within {worst_angle:.2e} rad; tangential offset at tolerance 1e-13 {worst_tangent:.2e} R; \
         iterations mean {:.2} max {max_iter} (from a reversed guess at most {back_steps})",
        sum_iter as f64 / overlapping as f64
    );
    assert!(overlapping >= 180 && separated >= 40);
}

/// Checks an overlapping pair's contact against brute force: depth within 1e-12 R (round-off
/// of both is about 1e-15 R), normal within 1e-6 rad (the brute force resolves it to about
/// 1e-7), the common-normal condition. Returns |depth error| / R.
fn check_against_brute_force(
    i: usize,
    a: &Placed,
    b: &Placed,
    c: Option<ContactGeometry>,
    bf_depth: f64,
    bf_normal: &V3,
) -> f64 {
    let c = c.unwrap_or_else(|| panic!("pair {i}: brute-force overlap {bf_depth:e} missed"));
    check_common_normal(a, b, &c, GRADIENT_TOLERANCE);
    let err = (c.depth - bf_depth).abs() / R;
    assert!(
        err <= 1e-12,
        "pair {i}: depth {:e} vs brute force {bf_depth:e}",
        c.depth
    );
    let ang = angle(&c.normal, bf_normal);
    assert!(ang < 1e-6, "pair {i}: normal off by {ang:e} rad");
    err
}

/// Overlaps up to 0.3 of the smaller size, coincident origins and identical orientations.
#[test]
fn deep_overlaps_and_coincident_centres_match_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let mut worst: f64 = 0.0;
    for i in 0..40 {
        let target = R * uniform(&mut rng, 0.05, 0.3);
        let mut pair = random_pair(&mut rng, i, target);
        if i % 4 == 1 {
            pair.rots[1] = pair.rots[0];
            pair.shapes[1] = pair.shapes[0];
        }
        let (a, mut b) = placed_pair(&pair);
        if i % 10 == 9 {
            b.origin = a.origin;
        }
        let (bf_depth, bf_normal) = brute_force(&a, &b);
        for guess in [a.centroid() - b.centroid(), V3::zeros()] {
            let c = contact(&a, &b, &guess);
            worst = worst.max(check_against_brute_force(
                i, &a, &b, c, bf_depth, &bf_normal,
            ));
        }
    }
    println!("deep overlaps: |depth - brute force| <= {worst:.2e} R");
}

/// Deep overlaps in general position: B is moved along a random direction m until the
/// overlap of the projections on m is `target` (up to 0.3 R), so the contact normal is
/// anywhere; the centroid-to-centroid guess and a zero guess are both tried, and pairs with
/// coincident centroids too (their guess falls back to +x).
#[test]
fn deep_overlaps_in_general_position_match_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(78);
    let (mut worst, mut overlapping, mut separated): (f64, usize, usize) = (0.0, 0, 0);
    for i in 0..60 {
        let target = R * uniform(&mut rng, 0.01, 0.3);
        let pair = random_pair(&mut rng, i, target);
        let (a, b0) = placed_pair(&pair);
        let along = |d: &V3| d.dot(&(support_world(&a, d) - a.origin));
        let mut b = Placed {
            origin: V3::zeros(),
            ..b0
        };
        let reach_b = (-pair.m).dot(&(support_world(&b, &-pair.m) - b.origin));
        b.origin = a.origin + pair.m * (along(&pair.m) + reach_b - target);
        if i % 6 == 5 {
            // Coincident centroids.
            b.origin += a.centroid() - b.centroid();
        }
        let (bf_depth, bf_normal) = brute_force(&a, &b);
        for guess in [a.centroid() - b.centroid(), V3::zeros()] {
            let got = contact(&a, &b, &guess);
            if bf_depth < 0.0 {
                assert!(
                    got.is_none(),
                    "pair {i}: separated by {:e}, contact {got:?}",
                    -bf_depth
                );
                separated += 1;
                continue;
            }
            worst = worst.max(check_against_brute_force(
                i, &a, &b, got, bf_depth, &bf_normal,
            ));
            overlapping += 1;
        }
    }
    println!(
        "deep overlaps in general position: {overlapping} found, {separated} separated; |depth - brute force| <= {worst:.2e} R"
    );
    assert!(overlapping >= 60);
}

#[test]
fn nearly_touching_pairs_stay_finite() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for i in 0..100 {
        let target = R * if i % 2 == 0 { 1e-9 } else { -1e-9 };
        let pair = random_pair(&mut rng, i, target);
        let (a, b) = placed_pair(&pair);
        if let Some(c) = contact(&a, &b, &(a.centroid() - b.centroid())) {
            assert!(
                c.depth > 0.0 && c.depth <= 1e-9 * R * (1.0 + 1e-3) + 1e-15 * R,
                "depth {:e}",
                c.depth
            );
            check_common_normal(&a, &b, &c, GRADIENT_TOLERANCE);
            assert!(target > 0.0, "separated by 1e-9 R along m, yet a contact");
        }
    }
}

/// A warm start from the previous normal after a small motion converges in a step or two to
/// the cold-start answer.
#[test]
fn warm_start_converges_in_few_steps() {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let mut steps = [0u32; 8];
    for i in 0..200 {
        let target = R * 10f64.powf(uniform(&mut rng, -3.0, -1.3));
        let pair = random_pair(&mut rng, i, target);
        let (a, b) = placed_pair(&pair);
        let Some(before) = contact(&a, &b, &(a.centroid() - b.centroid())) else {
            continue;
        };
        // Move B by 3e-5 R and turn it by 3e-5 rad: about one time step of the SHPB job
        // (see benches/convex_contact.rs).
        let turn = UnitQuaternion::from_scaled_axis(random_direction(&mut rng) * 3e-5)
            .to_rotation_matrix()
            .into_inner();
        let moved = Placed {
            origin: b.origin + random_direction(&mut rng) * 3e-5 * R,
            rot: turn * b.rot,
            ..b
        };
        let (Some(warm), Some(cold)) = (
            contact(&a, &moved, &before.normal),
            contact(&a, &moved, &V3::zeros()),
        ) else {
            continue;
        };
        assert!((warm.depth - cold.depth).abs() < 1e-14 * R);
        assert!(angle(&warm.normal, &cold.normal) < 1e-9);
        assert!(
            warm.iterations <= 3,
            "warm start took {} steps",
            warm.iterations
        );
        steps[warm.iterations as usize] += 1;
    }
    println!(
        "warm-start Newton steps (count of queries by steps 0, 1, 2, 3): {:?}",
        &steps[..4]
    );
}

/// r_eff against the curvature of the gap between the surfaces, measured by bisection on the
/// implicit functions along lines parallel to the normal at tangential offsets ±ε.
///
/// The second differences carry a truncation error of about 3 (ε/ρ)² (ρ the smallest radius
/// of curvature at the contact, down to 0.03 R here: 1e-5 at ε = 1e-4 R) and a round-off
/// error of about ulp(|x|) ρ / ε² (x ≈ 2e-3 m: 1e-6); 1e-4 covers both.
#[test]
fn equivalent_radius_matches_gap_fit() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for i in 0..80 {
        let target = R * 10f64.powf(uniform(&mut rng, -4.0, -1.3));
        let pair = random_pair(&mut rng, i, target);
        let (a, b) = placed_pair(&pair);
        let Some(c) = contact(&a, &b, &(a.centroid() - b.centroid())) else {
            continue;
        };
        let eps = 1e-4 * R;
        // The gap is a quadratic only away from the octant planes (the curvature jumps there).
        let local = |p: &Placed, x: &V3| p.rot.tr_mul(&(x - p.origin));
        let clear = |p: &Placed, x: &V3| match p.shape {
            ConvexShape::Sphere { .. } => true,
            ConvexShape::PolyEllipsoid(_) => local(p, x).abs().min() > 100.0 * eps,
        };
        if !(clear(&a, &c.point_a) && clear(&b, &c.point_b)) {
            continue;
        }
        let inside = |p: &Placed, x: &V3| match p.shape {
            ConvexShape::Sphere { radius } => (x - p.origin).norm() <= radius,
            ConvexShape::PolyEllipsoid(pe) => pe.implicit(&local(p, x)) <= 1.0,
        };
        let n = c.normal;
        // Bisection for the boundary of `p` on the line point + x + z n between z_in and z_out.
        let boundary = |p: &Placed, x: &V3, mut z_in: f64, mut z_out: f64| {
            assert!(inside(p, &(c.point + x + z_in * n)) && !inside(p, &(c.point + x + z_out * n)));
            for _ in 0..200 {
                let mid = 0.5 * (z_in + z_out);
                if mid == z_in || mid == z_out {
                    break;
                }
                if inside(p, &(c.point + x + mid * n)) {
                    z_in = mid
                } else {
                    z_out = mid
                }
            }
            0.5 * (z_in + z_out)
        };
        let (za, zb) = (n.dot(&(c.point_a - c.point)), n.dot(&(c.point_b - c.point)));
        let gap = |x: V3| {
            boundary(&a, &x, za + 0.02 * R, za - 1e-3 * R)
                - boundary(&b, &x, zb - 0.02 * R, zb + 1e-3 * R)
        };
        let (t1, t2) = {
            let t = if n.x.abs() < 0.9 { V3::x() } else { V3::y() };
            let t1 = n.cross(&t).normalize();
            (t1, n.cross(&t1))
        };
        let g0 = gap(V3::zeros());
        assert!(
            (g0 + c.depth).abs() < 1e-12 * R,
            "gap at the contact {g0:e} vs depth {:e}",
            c.depth
        );
        let second = |e: V3| (gap(e * eps) + gap(-e * eps) - 2.0 * g0) / (eps * eps);
        let (q11, q22) = (second(t1), second(t2));
        let q12 = second((t1 + t2) / 2f64.sqrt()) - 0.5 * (q11 + q22);
        let fit = 1.0 / (q11 * q22 - q12 * q12).sqrt();
        let rel = (fit - c.r_eff).abs() / c.r_eff;
        worst = worst.max(rel);
        assert!(
            rel < 1e-4,
            "pair {i}: r_eff {:e} vs gap fit {fit:e}",
            c.r_eff
        );
        checked += 1;
    }
    println!("r_eff vs gap fit: {checked} pairs, worst relative error {worst:.2e}");
    assert!(checked >= 40);
}

/// Aligned ellipsoids touching at their axis tips: depth, normal and
/// r_eff = 1/sqrt((a1/b1² + a2/b2²)(a1/c1² + a2/c2²)) in closed form.
#[test]
fn aligned_ellipsoids_at_the_tips() {
    let (a1, b1, c1) = (1.7 * R, 1.1 * R, 1.4 * R);
    let (a2, b2, c2) = (1.2 * R, 1.9 * R, 1.0 * R);
    let e1 = PolyEllipsoid::new([a1, a1, b1, b1, c1, c1]).unwrap();
    let e2 = PolyEllipsoid::new([a2, a2, b2, b2, c2, c2]).unwrap();
    // A split-like poly-ellipsoid touching with its short side: a- governs.
    let p3 = PolyEllipsoid::new([0.9 * R, 0.1 * R, 0.95 * R, 0.95 * R, 0.8 * R, 0.8 * R]).unwrap();
    for overlap in [1e-6 * R, 1e-3 * R, 3e-2 * R] {
        let a = Placed::poly_ellipsoid(
            &e1,
            V3::new(a1 + a2 - overlap, 0.0, 0.0),
            Matrix3::identity(),
        );
        let b = Placed::poly_ellipsoid(&e2, V3::zeros(), Matrix3::identity());
        let c = contact(&a, &b, &V3::new(1.0, 0.02, -0.03)).unwrap();
        assert!(
            (c.depth - overlap).abs() < 1e-15 * R,
            "{:e}",
            c.depth - overlap
        );
        assert!((c.normal - V3::x()).norm() < 1e-14);
        let expect =
            1.0 / ((a1 / (b1 * b1) + a2 / (b2 * b2)) * (a1 / (c1 * c1) + a2 / (c2 * c2))).sqrt();
        assert!((c.r_eff - expect).abs() < 1e-13 * expect);

        let (ap, bp, cp) = (0.1 * R, 0.95 * R, 0.8 * R);
        let s = Placed::poly_ellipsoid(
            &p3,
            V3::new(ap + a2 - overlap, 0.0, 0.0),
            Matrix3::identity(),
        );
        let c = contact(&s, &b, &V3::x()).unwrap();
        assert!((c.depth - overlap).abs() < 1e-15 * R);
        let expect =
            1.0 / ((ap / (bp * bp) + a2 / (b2 * b2)) * (ap / (cp * cp) + a2 / (c2 * c2))).sqrt();
        assert!((c.r_eff - expect).abs() < 1e-13 * expect);
    }
}

/// An ellipsoid turned by α about x resting on the floor z = 0: its lowest point is at
/// `z0 - sqrt(b² sin²α + c² cos²α)`; upright, r_eff = sqrt(radii product) = a b / c.
#[test]
fn ellipsoid_on_a_wall_matches_closed_form() {
    let (a, b, c) = (1.6 * R, 1.2 * R, 0.7 * R);
    let el = PolyEllipsoid::new([a, a, b, b, c, c]).unwrap();
    let n = V3::z();
    for k in 0..12 {
        let alpha = k as f64 * 0.3;
        let rot = UnitQuaternion::from_axis_angle(&V3::x_axis(), alpha)
            .to_rotation_matrix()
            .into_inner();
        let low = (b * b * alpha.sin().powi(2) + c * c * alpha.cos().powi(2)).sqrt();
        let z0 = low - 1e-3 * R;
        let body = Placed::poly_ellipsoid(&el, V3::new(0.3 * R, -0.2 * R, z0), rot);
        let hit = wall_contact(&body, &n, &V3::new(5.0 * R, 1.0 * R, 0.0)).unwrap();
        assert!(
            (hit.depth - 1e-3 * R).abs() < 1e-15 * R * 10.0,
            "α = {alpha}: {:e}",
            hit.depth
        );
        assert!((hit.point_a.z + 1e-3 * R).abs() < 1e-15 * R && hit.point_b.z.abs() < 1e-15 * R);
        if k == 0 {
            assert!((hit.r_eff - a * b / c).abs() < 1e-13 * R);
        }
        // The section of the ellipsoid in the plane x = 0 is an ellipse; its radius of
        // curvature at the lowest point is (b c)² / low³, and along x it is a² / low.
        let expect = ((b * c).powi(2) / low.powi(3) * a * a / low).sqrt();
        assert!(
            (hit.r_eff - expect).abs() < 1e-12 * expect,
            "α = {alpha}: {} vs {expect}",
            hit.r_eff
        );
        let clear = Placed {
            origin: V3::new(0.0, 0.0, low + 1e-12 * R),
            ..body
        };
        assert!(wall_contact(&clear, &n, &V3::zeros()).is_none());
    }
}

/// Random poly-ellipsoids against random walls: the closed form against brute force.
#[test]
fn poly_ellipsoid_wall_matches_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut worst: f64 = 0.0;
    for i in 0..60 {
        let pe = random_shape(&mut rng, i);
        let rot = random_rotation(&mut rng);
        let n = random_direction(&mut rng);
        let x_w = V3::new(1e-3, 2e-3, -1e-3);
        let body = Placed::poly_ellipsoid(&pe, x_w + n * (R * uniform(&mut rng, 0.0, 1.0)), rot);
        let sampled = Sampled::new(body);
        let depth = n.dot(&x_w) + sampled.support(&-n);
        match wall_contact(&body, &n, &x_w) {
            Some(hit) => {
                worst = worst.max((hit.depth - depth).abs() / R);
                assert!((hit.depth - depth).abs() < 1e-13 * R);
                assert!((hit.point_b - x_w).dot(&n).abs() < 1e-15 * R * 10.0);
            }
            None => assert!(depth < 1e-15 * R),
        }
    }
    println!("walls: |depth - brute force| <= {worst:.2e} R");
}

/// The bounding radius against the farthest surface point from the centroid: dense rays
/// (6 × 300²) find its basin, pattern search refines it to round-off.
#[test]
fn bounding_radius_bounds_the_surface() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut shapes: Vec<PolyEllipsoid> = (0..8).map(|i| random_shape(&mut rng, i)).collect();
    shapes.push(PolyEllipsoid::new([1.0, 1.5, 0.8, 1.2, 1.9, 0.7]).unwrap());
    shapes.push(PolyEllipsoid::new([1.0, 0.1, 0.6, 1.3, 0.9, 0.9]).unwrap());
    let mut worst: f64 = 0.0;
    for pe in shapes {
        let c = pe.centroid();
        let dist = |u: &V3| (pe.surface_point(u) - c).norm();
        let mut far = (0.0, 0, 0.0, 0.0);
        for (face, s, t) in cube_grid(300) {
            let d = dist(&cube_direction(face, s, t));
            if d > far.0 {
                far = (d, face, s, t);
            }
        }
        let (refined, _, _) = pattern_max(&dist, far.1, far.2, far.3, 2.0 / 300.0);
        let r = pe.bounding_radius();
        assert!(
            r >= refined,
            "{r} below the farthest surface point {refined} for {:?}",
            pe.semi
        );
        assert!(
            r <= refined * (1.0 + 1e-8),
            "{r} above the farthest point {refined} for {:?}",
            pe.semi
        );
        worst = worst.max(r / refined - 1.0);
    }
    println!("bounding radius above the farthest surface point by at most {worst:.1e} (relative)");
}

/// `contact_or_gap`'s gap, by which the contact effect skips the search of a separated pair
/// until its bodies have moved that far: never more than the distance between the bodies, and
/// while the two centroids' translations plus each bounding radius times its body's rotation
/// angle add up to less than it, the pair stays apart. Pairs placed at known distances
/// (1e-6 to 1e-2 R along a common normal), guesses of three lengths (a unit normal, and the
/// centre-to-centre vector times 1e3 and 1e-3: the gap is per unit direction), then moved
/// towards each other and turned by random shares of 0.999 of the gap.
#[test]
fn the_gap_of_a_separated_pair_bounds_the_motion_that_keeps_it_apart() {
    let mut rng = ChaCha8Rng::seed_from_u64(33);
    let mut checked = 0;
    for i in 0..400 {
        let distance = R * 10f64.powf(uniform(&mut rng, -6.0, -2.0));
        let p = random_pair(&mut rng, i, -distance);
        let (a, b) = placed_pair(&p);
        let c2c = a.centroid() - b.centroid();
        for guess in [-p.m, c2c * 1e3, c2c * 1e-3] {
            let gap = match contact_or_gap(&a, &b, &guess) {
                Err(gap) => gap,
                Ok(c) => panic!("pair {i} apart by {distance:e} found touching: {c:?}"),
            };
            assert!(
                gap >= 0.0 && gap <= distance * (1.0 + 1e-9) + 1e-15 * R,
                "pair {i}: gap {gap:e} against the distance {distance:e}"
            );
            let radius = |p: &Placed| match p.shape {
                ConvexShape::Sphere { radius } => radius,
                ConvexShape::PolyEllipsoid(pe) => pe.bounding_radius(),
            };
            for _ in 0..5 {
                // Shares of the budget: A's and B's translations (towards each other along
                // the normal, or anywhere) and turns.
                let w: [f64; 4] = std::array::from_fn(|_| uniform(&mut rng, 0.0, 1.0));
                let sum: f64 = w.iter().sum();
                let budget = 0.999 * gap;
                let towards = uniform(&mut rng, 0.0, 1.0) < 0.5;
                let dir = |rng: &mut ChaCha8Rng, m: V3| {
                    if towards { m } else { random_direction(rng) }
                };
                let ta = dir(&mut rng, p.m) * (budget * w[0] / sum);
                let tb = dir(&mut rng, -p.m) * (budget * w[1] / sum);
                let turn = |rng: &mut ChaCha8Rng, body: &Placed, share: f64| {
                    let angle = budget * share / sum / radius(body);
                    UnitQuaternion::from_scaled_axis(random_direction(rng) * angle)
                        .to_rotation_matrix()
                        .into_inner()
                };
                fn moved<'a>(body: &Placed<'a>, t: V3, r: Matrix3<f64>) -> Placed<'a> {
                    let c = body.centroid() + t;
                    let rot = r * body.rot;
                    let local = match body.shape {
                        ConvexShape::Sphere { .. } => V3::zeros(),
                        ConvexShape::PolyEllipsoid(pe) => pe.centroid(),
                    };
                    Placed {
                        shape: body.shape,
                        origin: c - rot * local,
                        rot,
                    }
                }
                let ra = turn(&mut rng, &a, w[2]);
                let rb = turn(&mut rng, &b, w[3]);
                let (a2, b2) = (moved(&a, ta, ra), moved(&b, tb, rb));
                assert!(
                    contact(&a2, &b2, &(a2.centroid() - b2.centroid())).is_none(),
                    "pair {i}: moved by {budget:e} of a gap of {gap:e} and touching"
                );
                checked += 1;
            }
        }
    }
    println!("{checked} moved pairs stayed apart");
}
