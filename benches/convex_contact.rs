//! `cargo bench --bench convex_contact`: nanoseconds per contact query of
//! `fractum::contact::convex` for sphere–poly-ellipsoid, poly-ellipsoid pairs and
//! poly-ellipsoid–wall, separated (rejected) and overlapping, cold start (centre-to-centre
//! guess) and warm start (the normal of the previous step after a DEM-sized motion).
//!
//! Shapes: semi-axes uniform in [1, 2] × 0.3 mm, random orientations. Overlapping pairs have
//! overlaps log-uniform in [1e-4, 1e-2] of the size; separated pairs gaps uniform in
//! [1e-3, 0.4] of the size (a neighbour list with a 0.4 r skin hands such pairs over). A warm
//! start is the normal found before B moved by 3e-5 of the size and turned by 3e-5 rad: about
//! one time step of scenes/shpb_sand.toml (0.2 × the Rayleigh step of its 0.1 mm grains,
//! 2.2e-8 s; relative speeds about 0.3 m/s, spins about 1e3 rad/s). A second table shows what the convergence tolerance costs and
//! buys on the warm PE–PE queries. Prints tables; asserts nothing.

use std::hint::black_box;
use std::time::Instant;

use fractum::contact::convex::{
    ConvexShape, Placed, contact, contact_with_tolerance, support_world, wall_contact,
};
use fractum::shape::poly_ellipsoid::PolyEllipsoid;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

type V3 = Vector3<f64>;
const R: f64 = 0.3e-3;
const PAIRS: usize = 512;

fn uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}

fn direction(rng: &mut ChaCha8Rng) -> V3 {
    loop {
        let v = V3::new(
            uniform(rng, -1.0, 1.0),
            uniform(rng, -1.0, 1.0),
            uniform(rng, -1.0, 1.0),
        );
        if v.norm() > 0.1 && v.norm() <= 1.0 {
            return v.normalize();
        }
    }
}

fn rotation(rng: &mut ChaCha8Rng) -> Matrix3<f64> {
    let axis = direction(rng);
    UnitQuaternion::from_scaled_axis(axis * uniform(rng, 0.0, std::f64::consts::PI))
        .to_rotation_matrix()
        .into_inner()
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    SpherePe,
    PePe,
    PeWall,
}

/// One query: A, B (or a wall), the cold and the warm guess.
struct Query {
    a: usize,
    b: usize,
    rot: [Matrix3<f64>; 2],
    origin: [V3; 2],
    sphere: f64,
    cold: V3,
    warm: V3,
}

fn queries(
    kind: Kind,
    overlapping: bool,
    shapes: &[PolyEllipsoid],
    rng: &mut ChaCha8Rng,
) -> Vec<Query> {
    let mut out = Vec::with_capacity(PAIRS);
    while out.len() < PAIRS {
        let (ia, ib) = (
            rng.random_range(0..shapes.len()),
            rng.random_range(0..shapes.len()),
        );
        let rot = [rotation(rng), rotation(rng)];
        let sphere = R * uniform(rng, 1.0, 2.0);
        let m = direction(rng);
        let amount = if overlapping {
            R * 10f64.powf(uniform(rng, -4.0, -2.0))
        } else {
            -R * uniform(rng, 1e-3, 0.4)
        };
        let a_origin = V3::new(1e-3, 2e-3, 3e-3);
        let a = match kind {
            Kind::SpherePe => Placed::sphere(sphere, a_origin),
            _ => Placed::poly_ellipsoid(&shapes[ia], a_origin, rot[0]),
        };
        if kind == Kind::PeWall {
            // The wall normal is -m; the body's deepest point along m is `amount` into it.
            let wall_point = support_world(&a, &m) - amount * m;
            out.push(Query {
                a: ia,
                b: ib,
                rot,
                origin: [a_origin, wall_point],
                sphere,
                cold: -m,
                warm: -m,
            });
            continue;
        }
        // B placed with the common normal along m (see tests/convex_contact.rs).
        let b0 = Placed::poly_ellipsoid(&shapes[ib], V3::zeros(), rot[1]);
        let b_origin = support_world(&a, &m) - amount * m - support_world(&b0, &-m);
        let b = Placed {
            origin: b_origin,
            ..b0
        };
        // The previous step: B before a small motion.
        let turn = UnitQuaternion::from_scaled_axis(direction(rng) * 3e-5)
            .to_rotation_matrix()
            .into_inner();
        let before = Placed {
            origin: b_origin - direction(rng) * 3e-5 * R,
            rot: turn * rot[1],
            ..b
        };
        let warm = match contact(&a, &before, &(a.centroid() - before.centroid())) {
            Some(c) => c.normal,
            None => -m,
        };
        if contact(&a, &b, &(a.centroid() - b.centroid())).is_some() != overlapping {
            continue;
        }
        out.push(Query {
            a: ia,
            b: ib,
            rot,
            origin: [a_origin, b_origin],
            sphere,
            cold: a.centroid() - b.centroid(),
            warm,
        });
    }
    out
}

/// ns per call of `query` over the cases: the fastest of 10 timings of `reps / 10` sweeps
/// each (the machine is shared; the minimum is the figure least disturbed by other work).
fn fastest<T>(cases: &[T], reps: usize, query: impl Fn(&T)) -> f64 {
    (0..10)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..reps / 10 {
                for case in black_box(cases) {
                    query(case);
                }
            }
            start.elapsed().as_secs_f64() * 1e9 / ((reps / 10) * cases.len()) as f64
        })
        .fold(f64::INFINITY, f64::min)
}

/// ns per query (see [`fastest`]); mean Newton steps of the contacts found; the share
/// of queries whose guess already separates the pair (δ(guess) < 0, no iteration).
fn time(
    kind: Kind,
    qs: &[Query],
    shapes: &[PolyEllipsoid],
    warm: bool,
    reps: usize,
) -> (f64, f64, f64) {
    // Bodies and guesses built once: the timed loop is the query alone.
    let cases: Vec<(Placed, Placed, V3)> = qs
        .iter()
        .map(|q| {
            let a = match kind {
                Kind::SpherePe => Placed::sphere(q.sphere, q.origin[0]),
                _ => Placed::poly_ellipsoid(&shapes[q.a], q.origin[0], q.rot[0]),
            };
            let b = Placed {
                shape: ConvexShape::PolyEllipsoid(&shapes[q.b]),
                origin: q.origin[1],
                rot: q.rot[1],
            };
            (a, b, if warm { q.warm } else { q.cold })
        })
        .collect();
    let run = |(a, b, guess): &(Placed, Placed, V3)| {
        if kind == Kind::PeWall {
            // The wall: normal `guess`, through B's origin.
            return wall_contact(a, guess, &b.origin);
        }
        contact(a, b, guess)
    };
    let found: Vec<u32> = cases
        .iter()
        .filter_map(|c| run(c).map(|c| c.iterations))
        .collect();
    let steps = found.iter().sum::<u32>() as f64 / found.len().max(1) as f64;
    let rejected = cases
        .iter()
        .filter(|(a, b, guess)| {
            let m = -guess.normalize();
            kind != Kind::PeWall && m.dot(&(support_world(a, &m) - support_world(b, &-m))) < 0.0
        })
        .count() as f64
        / qs.len() as f64;
    let ns = fastest(&cases, reps, |case| {
        black_box(run(case));
    });
    (ns, steps, rejected)
}

fn main() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let shapes: Vec<PolyEllipsoid> = (0..64)
        .map(|_| {
            PolyEllipsoid::new(std::array::from_fn(|_| R * uniform(&mut rng, 1.0, 2.0))).unwrap()
        })
        .collect();
    println!(
        "convex contact queries, {PAIRS} pairs per row: ns per query; for overlapping pairs the"
    );
    println!("mean Newton steps, for separated pairs the share rejected by the guess alone");
    println!();
    println!(
        "| pair | state | cold start ns | steps / rejected | warm start ns | steps / rejected |"
    );
    println!("|---|---|---:|---:|---:|---:|");
    for (kind, name) in [
        (Kind::SpherePe, "sphere–PE"),
        (Kind::PePe, "PE–PE"),
        (Kind::PeWall, "PE–wall"),
    ] {
        for overlapping in [false, true] {
            let qs = queries(kind, overlapping, &shapes, &mut rng);
            let (cold, cold_steps, cold_rej) = time(kind, &qs, &shapes, false, 2000);
            let (state, cold_note) = if overlapping {
                ("overlapping", format!("{cold_steps:.2}"))
            } else {
                ("separated", format!("{:.0}%", 100.0 * cold_rej))
            };
            if kind == Kind::PeWall {
                println!("| {name} | {state} | {cold:.1} | closed form | | |");
                continue;
            }
            let (warm, warm_steps, warm_rej) = time(kind, &qs, &shapes, true, 2000);
            let warm_note = if overlapping {
                format!("{warm_steps:.2}")
            } else {
                format!("{:.0}%", 100.0 * warm_rej)
            };
            println!("| {name} | {state} | {cold:.1} | {cold_note} | {warm:.1} | {warm_note} |");
        }
    }

    // Tolerance against cost: warm PE–PE queries; errors against a run at 1e-14.
    let qs = queries(Kind::PePe, true, &shapes, &mut rng);
    let cases: Vec<(Placed, Placed, V3)> = qs
        .iter()
        .map(|q| {
            let a = Placed::poly_ellipsoid(&shapes[q.a], q.origin[0], q.rot[0]);
            let b = Placed::poly_ellipsoid(&shapes[q.b], q.origin[1], q.rot[1]);
            (a, b, q.warm)
        })
        .collect();
    let exact: Vec<_> = cases
        .iter()
        .map(|(a, b, g)| contact_with_tolerance(a, b, g, 1e-14).unwrap())
        .collect();
    println!();
    println!("warm PE–PE: convergence tolerance (of h_A + h_B) against cost and error (vs 1e-14)");
    println!();
    println!(
        "| tolerance | ns | mean steps | max normal error (rad) | max depth error (of depth) | max r_eff error |"
    );
    println!("|---:|---:|---:|---:|---:|---:|");
    for tol in [1e-6, 1e-8, 1e-9, 1e-10, 1e-12] {
        let (mut steps, mut e_n, mut e_d, mut e_r) = (0u32, 0.0f64, 0.0f64, 0.0f64);
        for ((a, b, g), x) in cases.iter().zip(&exact) {
            let c = contact_with_tolerance(a, b, g, tol).unwrap();
            steps += c.iterations;
            e_n = e_n.max((c.normal - x.normal).norm());
            e_d = e_d.max((c.depth - x.depth).abs() / x.depth);
            e_r = e_r.max((c.r_eff - x.r_eff).abs() / x.r_eff);
        }
        let ns = fastest(&cases, 2000, |(a, b, g)| {
            let _ = black_box(contact_with_tolerance(a, b, g, tol));
        });
        println!(
            "| {tol:.0e} | {ns:.1} | {:.2} | {e_n:.1e} | {e_d:.1e} | {e_r:.1e} |",
            steps as f64 / cases.len() as f64
        );
    }
}
