use super::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SPLIT: [f64; 6] = [0.9, 0.1, 0.95, 0.95, 0.95, 0.95];

/// A random vector in the cube [-0.5, 0.5]³.
fn random_vector(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    Vector3::new(
        rng.random::<f64>(),
        rng.random::<f64>(),
        rng.random::<f64>(),
    )
    .add_scalar(-0.5)
}

fn shapes() -> Vec<PolyEllipsoid> {
    vec![
        PolyEllipsoid::new([1.0, 1.5, 0.8, 1.2, 1.9, 0.7]).unwrap(),
        PolyEllipsoid::new([2.0, 1.0, 1.0, 1.0, 1.0, 1.0]).unwrap(),
        PolyEllipsoid::new(SPLIT).unwrap(),
        PolyEllipsoid::new([1.0, 0.1, 0.6, 1.3, 0.9, 0.9]).unwrap(),
    ]
}

/// Uniform points in the bounding box; returns (V, ∫x dV, ∫x xᵀ dV about the origin)
/// estimates and their standard errors (per entry).
fn monte_carlo(
    pe: &PolyEllipsoid,
    n: usize,
    seed: u64,
) -> (
    f64,
    Vector3<f64>,
    Matrix3<f64>,
    f64,
    Vector3<f64>,
    Matrix3<f64>,
) {
    let s = &pe.semi;
    let lo = Vector3::new(-s[1], -s[3], -s[5]);
    let span = Vector3::new(s[0] + s[1], s[2] + s[3], s[4] + s[5]);
    let box_v = span.x * span.y * span.z;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut v1, mut v2) = (0.0, 0.0);
    let (mut m1, mut m2) = (Vector3::zeros(), Vector3::zeros());
    let (mut s1, mut s2) = (Matrix3::zeros(), Matrix3::zeros());
    for _ in 0..n {
        let u = Vector3::new(
            rng.random::<f64>(),
            rng.random::<f64>(),
            rng.random::<f64>(),
        );
        let p = lo + span.component_mul(&u);
        if pe.implicit(&p) <= 1.0 {
            v1 += 1.0;
            v2 += 1.0;
            m1 += p;
            m2 += p.component_mul(&p);
            let pp = p * p.transpose();
            s1 += pp;
            s2 += pp.component_mul(&pp);
        }
    }
    let nf = n as f64;
    // Mean of f·box_v over uniform samples and its standard error.
    let se = |sum: f64, sum2: f64| {
        let mean = sum / nf;
        box_v * ((sum2 / nf - mean * mean) / nf).sqrt()
    };
    let vse = se(v1, v2);
    let mse = Vector3::from_fn(|i, _| se(m1[i], m2[i]));
    let sse = Matrix3::from_fn(|i, j| se(s1[(i, j)], s2[(i, j)]));
    (
        box_v * v1 / nf,
        box_v * m1 / nf,
        box_v * s1 / nf,
        vse,
        mse,
        sse,
    )
}

#[test]
fn volume_centroid_second_moment_match_monte_carlo() {
    // Each estimate within 4.5 standard errors (2e6 samples; the seeds are fixed).
    let mut worst: f64 = 0.0;
    let mut check = |exact: f64, estimate: f64, se: f64, what: &str| {
        let z = (exact - estimate).abs() / se.max(1e-300);
        worst = worst.max(z);
        assert!(z < 4.5, "{what}: {exact} vs Monte Carlo {estimate} ± {se}");
    };
    for (k, pe) in shapes().iter().enumerate() {
        let (v, m, s, vse, mse, sse) = monte_carlo(pe, 2_000_000, 7 + k as u64);
        check(pe.volume(), v, vse, "volume");
        let c = pe.centroid();
        for i in 0..3 {
            check(c[i] * pe.volume(), m[i], mse[i], "first moment");
        }
        // About the origin: S_c + V c cᵀ.
        let s_origin = pe.second_moment() + pe.volume() * c * c.transpose();
        for i in 0..3 {
            for j in 0..3 {
                check(s_origin[(i, j)], s[(i, j)], sse[(i, j)], "second moment");
            }
        }
    }
    println!("Monte Carlo: largest deviation {worst:.2} standard errors");
}

/// Fine midpoint quadrature in each octant (spherical coordinates of the unit ball mapped
/// by the octant's axes) checks the closed forms far below the Monte Carlo noise.
#[test]
fn second_moment_matches_quadrature() {
    for pe in shapes() {
        let n = 160;
        let mut v = 0.0;
        let mut first = Vector3::zeros();
        let mut second = Matrix3::zeros();
        let h = 1.0 / n as f64;
        for sx in [1.0, -1.0] {
            for sy in [1.0, -1.0] {
                for sz in [1.0, -1.0] {
                    let ax = pe.octant_axes(&Vector3::new(sx, sy, sz));
                    let jac = ax.x * ax.y * ax.z;
                    for i in 0..n {
                        let r = (i as f64 + 0.5) * h;
                        for j in 0..n {
                            let th = (j as f64 + 0.5) * h * PI / 2.0;
                            for k in 0..n {
                                let ph = (k as f64 + 0.5) * h * PI / 2.0;
                                let w = jac * r * r * th.sin() * h * h * h * PI * PI / 4.0;
                                let p = Vector3::new(
                                    sx * ax.x * r * th.sin() * ph.cos(),
                                    sy * ax.y * r * th.sin() * ph.sin(),
                                    sz * ax.z * r * th.cos(),
                                );
                                v += w;
                                first += w * p;
                                second += w * p * p.transpose();
                            }
                        }
                    }
                }
            }
        }
        let c = first / v;
        let sc = second - v * c * c.transpose();
        let scale = pe.volume() * pe.semi.iter().cloned().fold(0.0, f64::max).powi(2);
        println!(
            "quadrature {:?}: volume {:.1e}, centroid {:.1e}, second moment {:.1e} (relative)",
            pe.semi,
            (v - pe.volume()).abs() / v,
            (c - pe.centroid()).norm() / pe.semi[0],
            (sc - pe.second_moment()).abs().max() / scale
        );
        assert!((v - pe.volume()).abs() < 2e-5 * v, "volume");
        assert!(
            (c - pe.centroid()).norm() < 2e-5,
            "centroid {c} vs {}",
            pe.centroid()
        );
        assert!(
            (sc - pe.second_moment()).abs().max() < 2e-5 * scale,
            "second moment\n{sc}\n{}",
            pe.second_moment()
        );
    }
}

#[test]
fn sphere_and_ellipsoid_closed_forms() {
    let r = 0.3e-3;
    let rho = 2650.0;
    let sp = PolyEllipsoid::sphere(r);
    let v = 4.0 / 3.0 * PI * r.powi(3);
    assert!((sp.volume() - v).abs() <= 1e-14 * v);
    assert!((sp.equivalent_radius() - r).abs() <= 1e-14 * r);
    assert_eq!(sp.centroid(), Vector3::zeros());
    let i_sphere = 0.4 * rho * v * r * r;
    let (moments, frame) = sp.principal_inertia(rho);
    for k in 0..3 {
        assert!((moments[k] - i_sphere).abs() <= 1e-14 * i_sphere);
    }
    assert_eq!(frame, UnitQuaternion::identity());
    assert_eq!(sp.bounding_radius(), r);

    let (a, b, c) = (2.0e-3, 1.3e-3, 0.7e-3);
    let el = PolyEllipsoid::new([a, a, b, b, c, c]).unwrap();
    let v = 4.0 / 3.0 * PI * a * b * c;
    let m = rho * v;
    assert!((el.volume() - v).abs() <= 1e-14 * v);
    let i = el.inertia(rho);
    let expect = Vector3::new(
        m * (b * b + c * c) / 5.0,
        m * (a * a + c * c) / 5.0,
        m * (a * a + b * b) / 5.0,
    );
    for k in 0..3 {
        assert!((i[(k, k)] - expect[k]).abs() <= 1e-14 * expect[k]);
    }
    assert!(i.m12 == 0.0 && i.m13 == 0.0 && i.m23 == 0.0);
    assert_eq!(el.bounding_radius(), a);
    // A half ellipsoid of semi-axis a along +x and a vanishing one along -x: centroid 3a/8.
    let half = PolyEllipsoid::new([a, 1e-300, b, b, c, c]).unwrap();
    assert!((half.centroid().x - 0.375 * a).abs() < 1e-15);
    assert!((half.volume() - v / 2.0).abs() < 1e-14 * v);
}

#[test]
fn principal_frame_diagonalises_inertia() {
    // Split-like shapes have one asymmetric axis: diagonal tensor, identity frame.
    let split = PolyEllipsoid::new(SPLIT).unwrap();
    assert_eq!(split.principal_inertia(1.0).1, UnitQuaternion::identity());
    for pe in shapes() {
        let i = pe.inertia(2650.0);
        let (moments, frame) = pe.principal_inertia(2650.0);
        let r = frame.to_rotation_matrix().into_inner();
        let back = r * Matrix3::from_diagonal(&moments) * r.transpose();
        assert!(
            (back - i).abs().max() < 1e-12 * i.abs().max(),
            "{back}\n{i}"
        );
        assert!((r.determinant() - 1.0).abs() < 1e-12);
        // Each principal axis is the one closest to its shape axis, on its positive side.
        for k in 0..3 {
            assert!(r[(k, k)] > 0.5, "axis {k} of {:?}: {r}", pe.semi);
        }
    }
    // The first shape has three asymmetric axes: a genuinely rotated frame.
    let (_, frame) = shapes()[0].principal_inertia(1.0);
    assert!(frame.angle() > 1e-3);
}

#[test]
fn support_point_matches_dense_surface_sampling() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for pe in shapes() {
        // Dense samples of the surface: rays from the octant origin on a cube grid.
        let n = 200;
        let pts: Vec<Vector3<f64>> = cube_grid(n)
            .map(|(face, s, t)| pe.surface_point(&cube_direction(face, s, t)))
            .collect();
        let rmax = pe.semi.iter().cloned().fold(0.0, f64::max);
        let rmin = pe.semi.iter().cloned().fold(f64::INFINITY, f64::min);
        // Neighbouring samples are at most about rmax · 2/n · 1.5 apart; the sampled maximum is
        // below the true one by at most (spacing/2)² / (2 ρ_min), ρ_min ≥ rmin²/rmax.
        let spacing = rmax * 3.0 / n as f64;
        let tol = 0.125 * spacing * spacing / (rmin * rmin / rmax);
        for _ in 0..200 {
            let d = random_vector(&mut rng) * 3.0;
            let s = pe.support(&d);
            let h = pe.support_value(&d);
            assert!((s.dot(&d) - h).abs() < 1e-12 * h);
            assert!((pe.implicit(&s) - 1.0).abs() < 1e-12);
            let normal = pe.normal_at(&s);
            assert!((normal - d.normalize()).norm() < 1e-12);
            let dn = d.norm();
            let sampled = pts
                .iter()
                .map(|p| p.dot(&d))
                .fold(f64::NEG_INFINITY, f64::max);
            assert!(sampled <= h + 1e-12 * h * dn, "sample beyond support");
            assert!(
                h - sampled <= tol * dn,
                "support {h} sampled {sampled} tol {}",
                tol * dn
            );
        }
    }
}

#[test]
fn curvature_radii_at_tips_and_of_a_sphere() {
    let r = 0.7;
    let sp = PolyEllipsoid::sphere(r);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..50 {
        let n = random_vector(&mut rng).normalize();
        let (radii, dirs) = sp.principal_curvatures(&n);
        assert!((radii[0] - r).abs() < 1e-14 && (radii[1] - r).abs() < 1e-14);
        assert!(dirs[0].dot(&n).abs() < 1e-14 && dirs[1].dot(&n).abs() < 1e-14);
        let hs = sp.support_hessian(&n);
        assert!(
            (hs - r * (Matrix3::identity() - n * n.transpose()))
                .abs()
                .max()
                < 1e-14
        );
    }
    // Poly-ellipsoid tips: the octants on the tip's side decide (a+ at +x, ...).
    let pe = PolyEllipsoid::new([1.0, 1.5, 0.8, 1.2, 1.9, 0.7]).unwrap();
    let s = pe.semi;
    // At the +x tip the four octants with x > 0 meet; the radii in the y and z directions
    // on the side y > 0, z > 0 are b+²/a+ and c+²/a+ (the support Hessian uses the octant of
    // n with its zero components counted as positive).
    let (radii, dirs) = pe.principal_curvatures(&Vector3::x());
    let mut expect = [s[2] * s[2] / s[0], s[4] * s[4] / s[0]];
    expect.sort_by(f64::total_cmp);
    assert!((radii[0] - expect[0]).abs() < 1e-14 && (radii[1] - expect[1]).abs() < 1e-14);
    assert!(dirs[0].x.abs() < 1e-14);
    let (radii, _) = pe.principal_curvatures(&(-Vector3::z()));
    let mut expect = [s[0] * s[0] / s[5], s[2] * s[2] / s[5]];
    expect.sort_by(f64::total_cmp);
    assert!((radii[0] - expect[0]).abs() < 1e-14 && (radii[1] - expect[1]).abs() < 1e-14);
    // Just off the -y tip into the octant x < 0, z < 0: a-²/b- and c-²/b-.
    let n = Vector3::new(-1e-9, -1.0, -1e-9).normalize();
    let (radii, _) = pe.principal_curvatures(&n);
    let mut expect = [s[1] * s[1] / s[3], s[5] * s[5] / s[3]];
    expect.sort_by(f64::total_cmp);
    assert!((radii[0] - expect[0]).abs() < 1e-8 && (radii[1] - expect[1]).abs() < 1e-8);
}

/// The curvature radii agree with the second derivative of the surface measured by
/// finite differences of support points: moving the normal by a small angle ε along a
/// principal direction moves the support point by ρ ε along it.
#[test]
fn curvature_radii_match_finite_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for pe in shapes() {
        for _ in 0..50 {
            let n = random_vector(&mut rng).normalize();
            let (radii, dirs) = pe.principal_curvatures(&n);
            let eps = 1e-6;
            for k in 0..2 {
                let up = pe.support(&(n + eps * dirs[k]).normalize());
                let down = pe.support(&(n - eps * dirs[k]).normalize());
                let fd = (up - down).dot(&dirs[k]) / (2.0 * eps);
                // A sample within ε of an octant plane straddles the curvature jump.
                if n.abs().min() > 1e-4 {
                    assert!(
                        (fd - radii[k]).abs() < 1e-6 * radii[1],
                        "{fd} vs {}",
                        radii[k]
                    );
                }
            }
        }
    }
}

#[test]
fn surface_points_normals_and_implicit() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for pe in shapes() {
        for _ in 0..200 {
            let d = random_vector(&mut rng);
            let p = pe.surface_point(&d);
            assert!((pe.implicit(&p) - 1.0).abs() < 1e-13);
            assert!(p.normalize().dot(&d.normalize()) > 1.0 - 1e-14);
            // The normal at p has p as its support point.
            let n = pe.normal_at(&p);
            assert!((pe.support(&n) - p).norm() < 1e-12);
            assert!(pe.implicit(&(0.999 * p)) < 1.0 && pe.implicit(&(1.001 * p)) > 1.0);
        }
    }
}

#[test]
fn tangent_basis_is_orthonormal_and_right_handed() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let mut dirs = vec![Vector3::z(), -Vector3::z(), Vector3::x()];
    for _ in 0..1000 {
        let v = random_vector(&mut rng);
        dirs.push(v.normalize());
    }
    for n in dirs {
        let (t1, t2) = tangent_basis(&n);
        assert!((t1.norm() - 1.0).abs() < 1e-14 && (t2.norm() - 1.0).abs() < 1e-14);
        assert!(t1.dot(&t2).abs() < 1e-14 && t1.dot(&n).abs() < 1e-14);
        assert!((t1.cross(&t2) - n).norm() < 1e-14);
    }
}

#[test]
fn constructor_rejects_bad_semi_axes() {
    assert!(
        PolyEllipsoid::new([1.0, 1.0, 0.0, 1.0, 1.0, 1.0])
            .unwrap_err()
            .contains("b+")
    );
    assert!(
        PolyEllipsoid::new([1.0, f64::NAN, 1.0, 1.0, 1.0, 1.0])
            .unwrap_err()
            .contains("a-")
    );
    assert!(PolyEllipsoid::new([1.0, 1.0, 1.0, 1.0, 1.0, -2.0]).is_err());
}
