//! The sleeve (`walls.sleeve`: a rigid cylinder round the sample, as an SHPB specimen's steel
//! sleeve) against closed forms: a sphere and an ellipsoid pressed on its inside carry the
//! force of Hertz's elliptical contact with a concave cylinder, and a sleeve scene reports as
//! its radial stress the summed normal forces of its contacts over its inner area.

mod common;

use fractum::contact::convex::{Placed, sleeve_contact as sleeve_geometry};
use fractum::contact::hertz_mindlin::{Hertz, KernelConsts};
use fractum::contact::pair::{BodyView, sleeve_contact};
use fractum::models::granular::Simulation;
use fractum::shape::PolyEllipsoid;
use fractum::state::{Bodies, Body, Sleeve, Vec3, Walls};
use nalgebra::{Matrix3, UnitQuaternion};

const E: f64 = 60e9;
const NU: f64 = 0.17;
const RHO: f64 = 2650.0;

/// E* of two bodies of E and ν (the grains and the sleeve share the material).
fn e_star() -> f64 {
    E / (2.0 * (1.0 - NU * NU))
}

/// The complete elliptic integrals K(m) and E(m) of parameter m = k² in [0, 1), by the
/// arithmetic-geometric mean (Abramowitz and Stegun 17.6).
fn elliptic_ke(m: f64) -> (f64, f64) {
    let (mut a, mut b) = (1.0_f64, (1.0 - m).sqrt());
    let mut sum = 0.5 * m;
    let mut weight = 0.5;
    for _ in 0..40 {
        if (a - b).abs() <= 1e-15 * a {
            break;
        }
        let c = 0.5 * (a - b);
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
        weight *= 2.0;
        sum += weight * c * c;
    }
    let k = std::f64::consts::PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// The force (N) of Hertz's elliptical contact at overlap `delta` (m) between bodies of
/// relative principal curvatures 2A and 2B (1/m; `z = A x² + B y²` is the gap, A <= B),
/// E* `e_star` (Johnson, Contact Mechanics, 1985, Sections 3.9 and 4.2): the contact ellipse
/// of semi-axes a >= b, eccentricity e² = 1 − b²/a², has
/// `B/A = ((a²/b²) E(e) − K(e)) / (K(e) − E(e))`, `a² = δ (K − E) / (K e² A)` and
/// `F = 2π E* δ a / (3 K)`. For A = B = 1/(2R) it is `4/3 E* √R δ^{3/2}`.
fn elliptical_hertz_force(a_curv: f64, b_curv: f64, delta: f64, e_star: f64) -> f64 {
    assert!(a_curv > 0.0 && b_curv >= a_curv);
    let ratio = |m: f64| {
        let (k, e) = elliptic_ke(m);
        ((1.0 / (1.0 - m)) * e - k) / (k - e)
    };
    // B/A grows from 1 (m = 0) with m: bisection.
    let target = b_curv / a_curv;
    let (mut lo, mut hi) = (1e-12_f64, 1.0 - 1e-12);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if ratio(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let m = 0.5 * (lo + hi);
    let (k, e) = elliptic_ke(m);
    let a = (delta * (k - e) / (k * m * a_curv)).sqrt();
    2.0 * std::f64::consts::PI * e_star * delta * a / (3.0 * k)
}

#[test]
fn the_elliptical_hertz_closed_form_reduces_to_the_sphere() {
    // A = B: the sphere's law, by the limit m -> 0 the bisection approaches.
    let (r, delta) = (1e-3, 1e-6);
    let f = elliptical_hertz_force(0.5 / r, 0.5 / r * (1.0 + 1e-9), delta, e_star());
    let sphere = 4.0 / 3.0 * e_star() * r.sqrt() * delta.powf(1.5);
    assert!((f / sphere - 1.0).abs() < 1e-6, "{f} against {sphere}");
    // K(1/2) and E(1/2) (Abramowitz and Stegun, Table 17.1).
    let (k, e) = elliptic_ke(0.5);
    assert!((k - 1.854_074_677_301_372).abs() < 1e-14 && (e - 1.350_643_881_047_675).abs() < 1e-14);
}

/// A sleeve of radius `radius` about the z axis.
fn sleeve(radius: f64) -> Sleeve {
    Sleeve::inscribed(
        Vec3::new(-radius, -radius, 0.0),
        Vec3::new(radius, radius, 1.0),
    )
}

/// The kernel's force magnitude on `body` in `sleeve`, without damping and friction, along
/// the sphere path and (a sphere too) the shapes' path.
fn kernel_force<const POLY: bool>(body: &Body, sleeve: &Sleeve) -> (f64, Vec3) {
    let k = KernelConsts::new(&Hertz::new(E, NU), None, None);
    let (mut hist, mut held) = (Vec3::zeros(), 0.0);
    let view = BodyView::new(body);
    let out =
        sleeve_contact::<false, false, POLY>(&k, &view, sleeve, &mut hist, &mut held, 1e-9, true)
            .expect("the body overlaps the sleeve");
    (out.force.norm(), out.normal)
}

#[test]
fn a_sphere_pressed_on_the_sleeve_carries_hertz_force_of_a_concave_cylinder() {
    // The specimen's sleeve (12.7 mm across) with a median Mason grain (0.15 mm), and a
    // sphere 0.4 of a 1 mm sleeve's radius, where the contact ellipse is 1.67 times longer
    // round the hoop than along the axis.
    for (r, big_r) in [(0.15e-3, 6.35e-3), (0.4e-3, 1.0e-3)] {
        let s = sleeve(big_r);
        let delta = 1e-3 * r;
        let mut b = Bodies::default();
        // Off the x axis, so that the radial direction is not a coordinate axis.
        let dir = Vec3::new(0.6, -0.8, 0.0);
        b.push_sphere(
            dir * (big_r - r + delta),
            r,
            RHO,
            UnitQuaternion::identity(),
        );
        let body = b.body(0);
        // The gap z = A x² + B y²: A = (1/r − 1/R)/2 round the hoop, B = 1/(2r) along the axis.
        let exact = elliptical_hertz_force(0.5 * (1.0 / r - 1.0 / big_r), 0.5 / r, delta, e_star());
        for (path, (f, n)) in [
            ("spheres", kernel_force::<false>(&body, &s)),
            ("shapes", kernel_force::<true>(&body, &s)),
        ] {
            assert!(
                (f / exact - 1.0).abs() < 0.01,
                "r {r:e} in R {big_r:e} ({path}): {f:e} N against the closed form's {exact:e} N"
            );
            assert!(
                (n + dir).norm() < 1e-12,
                "the normal points at the axis: {n:?}"
            );
        }
    }
}

/// A Mason-like ellipsoid (semi-axes 0.218, 0.163, 0.118 mm, the assembly's means) resting
/// on its flattest side, its shortest axis along `-dir` (radial), its longest along `long`.
fn ellipsoid_on_the_sleeve(big_r: f64, delta: f64, dir: Vec3, long: Vec3) -> (Body, [f64; 3]) {
    let semi = [0.218e-3, 0.163e-3, 0.118e-3];
    let pe = PolyEllipsoid::new([semi[0], semi[0], semi[1], semi[1], semi[2], semi[2]]).unwrap();
    // Shape axes x, y, z to the world: x along `long`, z along `dir` (out of the axis).
    let mid = dir.cross(&long);
    let rot = UnitQuaternion::from_matrix(&Matrix3::from_columns(&[long, mid, dir]));
    let centre = dir * (big_r - semi[2] + delta);
    let body = Body::poly_ellipsoid(pe, RHO * pe.volume(), centre, rot);
    (body, semi)
}

#[test]
fn an_ellipsoid_pressed_on_the_sleeve_carries_hertz_force_of_a_concave_cylinder() {
    let big_r = 6.35e-3;
    let dir = Vec3::new(0.6, -0.8, 0.0);
    let hoop = Vec3::z().cross(&dir);
    for long_along_axis in [true, false] {
        let long = if long_along_axis { Vec3::z() } else { hoop };
        let delta = 1e-4 * 0.118e-3;
        let (body, [a, b, c]) = ellipsoid_on_the_sleeve(big_r, delta, dir, long);
        // Radii of curvature at the tip of c: a²/c along a, b²/c along b; the sleeve adds
        // −1/R round the hoop.
        let (k_axis, k_hoop) = if long_along_axis {
            (c / (a * a), c / (b * b) - 1.0 / big_r)
        } else {
            (c / (b * b), c / (a * a) - 1.0 / big_r)
        };
        let (lo, hi) = (0.5 * k_axis.min(k_hoop), 0.5 * k_axis.max(k_hoop));
        let exact = elliptical_hertz_force(lo, hi, delta, e_star());
        let (f, n) = kernel_force::<true>(&body, &sleeve(big_r));
        assert!(
            (f / exact - 1.0).abs() < 0.01,
            "long axis along the {}: {f:e} N against the closed form's {exact:e} N (curvature ratio {:.3})",
            if long_along_axis { "axis" } else { "hoop" },
            hi / lo
        );
        assert!(
            (n + dir).norm() < 1e-9,
            "the normal points at the axis: {n:?}"
        );
        // The geometry itself: the overlap and the Hertz radius 1/sqrt(4 A B) exactly.
        let placed_body = BodyView::new(&body);
        let placement = placed_body.placement;
        let pe = match &body.shape {
            fractum::shape::Shape::PolyEllipsoid { pe, .. } => pe,
            _ => unreachable!(),
        };
        let g = sleeve_geometry(
            &Placed::poly_ellipsoid(pe, placement.origin, placement.rot),
            &Vec3::zeros(),
            big_r,
        )
        .expect("in contact");
        assert!(
            (g.depth / delta - 1.0).abs() < 1e-6,
            "overlap {:e} against {delta:e}",
            g.depth
        );
        let r_eff = 1.0 / (4.0 * lo * hi).sqrt();
        assert!(
            (g.r_eff / r_eff - 1.0).abs() < 1e-9,
            "Hertz radius {:e} against {r_eff:e}",
            g.r_eff
        );
    }
}

#[test]
fn a_turned_ellipsoid_meets_the_sleeve_at_its_point_farthest_from_the_axis() {
    // Brute force: the largest distance from the axis over the ellipsoid's surface, sampled
    // on a fine grid of directions, against the search's overlap. A turned poly-ellipsoid;
    // then a long one lying round the hoop, flatter there than the sleeve (radius of curvature
    // 6.4 mm at its middle in a 1 mm sleeve): its ends reach farther than its middle.
    let big_r = 1.0e-3;
    let cases = [
        (
            [0.4e-3, 0.2e-3, 0.3e-3, 0.15e-3, 0.25e-3, 0.1e-3],
            UnitQuaternion::from_euler_angles(0.7, -0.4, 1.9),
            Vec3::new(0.75e-3, 0.4e-3, 0.1e-3),
        ),
        (
            [0.1e-3, 0.1e-3, 0.8e-3, 0.8e-3, 0.2e-3, 0.2e-3],
            UnitQuaternion::identity(),
            Vec3::new(0.75e-3, 0.0, 0.0),
        ),
    ];
    for (semi, q, origin) in cases {
        let pe = PolyEllipsoid::new(semi).unwrap();
        let rot = q.to_rotation_matrix().into_inner();
        let placed = Placed::poly_ellipsoid(&pe, origin, rot);
        let mut farthest = 0.0_f64;
        let n = 400;
        for i in 0..=n {
            let theta = std::f64::consts::PI * i as f64 / n as f64;
            for j in 0..2 * n {
                let phi = std::f64::consts::PI * j as f64 / n as f64;
                let d = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let p = origin + rot * pe.surface_point(&d);
                farthest = farthest.max((p.x * p.x + p.y * p.y).sqrt());
            }
        }
        let brute = farthest - big_r;
        assert!(brute > 0.0, "the ellipsoid reaches the sleeve: {brute:e}");
        let g = sleeve_geometry(&placed, &Vec3::zeros(), big_r).expect("it reaches the sleeve");
        // The grid's spacing (pi/400 rad over radii of a few tenths of a millimetre) bounds how
        // far below the true maximum the samples stay: a few 1e-9 m.
        assert!(
            g.depth >= brute - 1e-12 && g.depth - brute < 1e-8,
            "overlap {:e} against the sampled {brute:e}",
            g.depth
        );
        let p = g.point_a;
        assert!(((p.x * p.x + p.y * p.y).sqrt() - big_r - g.depth).abs() < 1e-15);
    }
}

/// A sphere (or ellipsoid) pushed onto the sleeve by a body force along +x and left to settle:
/// at rest its contact carries the body force, and its overlap is the elliptical Hertz
/// overlap of that force.
#[test]
fn a_sphere_at_rest_on_the_sleeve_under_a_body_force() {
    let (r, big_r, g) = (0.3e-3, 2.0e-3, 2.0e5);
    let mut b = Bodies::default();
    b.push_sphere(
        Vec3::new(big_r - r, 0.0, 0.5e-3),
        r,
        RHO,
        UnitQuaternion::identity(),
    );
    let m = b.mass[0];
    // Contact time scale: the Hertz spring at the force m g.
    let f = m * g;
    let dt = 2e-9;
    let end = 2e-4;
    let extra = format!("[gravity]\nacceleration = [{g:e}, 0.0, 0.0]");
    let mut scene = common::scene("\"contact\", \"damping\", \"gravity\"", &extra, end, dt);
    fractum::scene::apply_override(&mut scene.tables, "material.restitution=0.2").unwrap();
    let mut walls = Walls::new_box(
        Vec3::new(-big_r, -big_r, 0.0),
        Vec3::new(big_r, big_r, 1e-3),
    );
    walls.add_sleeve();
    let mut sim = Simulation::from_sample(scene, common::sample(b, walls), 1).unwrap();
    while !sim.finished() {
        sim.advance(1000).unwrap();
    }
    let st = &sim.model.state;
    let sleeve = st.walls.sleeve.as_ref().unwrap();
    assert!(
        (sleeve.load / f - 1.0).abs() < 1e-3,
        "at rest the sleeve carries m g: {:e} N against {f:e} N",
        sleeve.load
    );
    let delta = st.bodies.pos[0].xy().norm() + r - big_r;
    let exact = elliptical_hertz_force(0.5 * (1.0 / r - 1.0 / big_r), 0.5 / r, delta, e_star());
    assert!(
        (exact / f - 1.0).abs() < 0.01,
        "the overlap {delta:e} m gives {exact:e} N by the closed form, against m g = {f:e} N"
    );
}

#[test]
fn the_sleeve_scene_reports_its_contacts_summed_over_its_area_and_keeps_its_energy() {
    // A 2 mm sleeve of Mason sand grains, jammed at the laboratory's density, driven to 0.02
    // strain with fracture.
    let text = std::fs::read_to_string(common::repo().join("scenes/mason_sand_shpb.toml"))
        .unwrap()
        .replace(
            "../data/mason_sand_shpb/",
            &format!("{}/data/mason_sand_shpb/", common::repo().display()),
        );
    let (_dir, file) = common::scene_file(&text);
    let overrides = [
        "sample.box=[2e-3, 2e-3, 2e-3]",
        "walls.sleeve=true",
        "loading.end_strain=0.02",
        "output.report_strains=[0.01, 0.02]",
        "output.every=50",
    ];
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let scene = fractum::Scene::read(&file, &overrides).unwrap();
    let mut sim = Simulation::new(scene, 1, &mut |_| {}).expect("the 2 mm sleeve scene builds");
    let mut checked = 0;
    while !sim.finished() {
        sim.advance(50).unwrap();
        let st = &sim.model.state;
        let sleeve = st.walls.sleeve.as_ref().unwrap();
        let height = st.walls.box_size().z;
        // The sleeve's contacts as the fracture criteria see them (the records of the step).
        let records = sim.model.pipeline.records().expect("shapes keep records");
        let w = st.walls.walls.len();
        let summed: f64 = records
            .list
            .iter()
            .filter(|c| c.wall() == Some(w))
            .map(|c| c.force.dot(&c.normal))
            .sum();
        let area = 2.0 * std::f64::consts::PI * sleeve.radius * height;
        let reported = st.walls.face_stress(fractum::state::BoxFace::XMin);
        if summed > 0.0 {
            assert!(
                (reported / (summed / area) - 1.0).abs() < 1e-9,
                "radial stress {reported:e} Pa against {:e} Pa summed",
                summed / area
            );
            let profile = sleeve.radial_profile(height);
            let mean = profile.iter().sum::<f64>() / profile.len() as f64;
            assert!(
                (mean / reported - 1.0).abs() < 1e-9,
                "the slices average to the mean"
            );
            checked += 1;
        }
    }
    assert!(checked > 10, "the sleeve carried load at {checked} checks");
    let summary = fractum::run::Run::summary(&sim);
    let error = summary["energy"]["balance_error_relative"]
        .as_f64()
        .unwrap();
    assert!(error.abs() < 0.02, "energy account off by {error}");
    let opposite = summary["stress_opposite_at_strain"]["0.02"]
        .as_f64()
        .unwrap();
    let lateral = summary["stress_lateral_at_strain"]["0.02"]
        .as_f64()
        .unwrap();
    assert!(opposite > 0.0 && lateral > 0.0, "{opposite} {lateral}");
}

/// The sleeve is not saved with a sample or a state: it is made from the scene. A run whose
/// sample comes from the sample cache, and one resumed from a checkpoint, give the same
/// series and summary as the run that made the sample (a cached sample once came without its
/// sleeve columns and the summary stopped on them).
#[test]
fn a_sleeve_run_from_the_sample_cache_or_a_checkpoint_repeats_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let scene = common::repo().join("scenes/mason_sand_specimen.toml");
    let run = |out: &str, extra: &[&str]| {
        let mut args = vec![
            "run",
            scene.to_str().unwrap(),
            "--quiet",
            "--threads",
            "1",
            "--set",
            "sample.box=[2e-3, 2e-3, 2e-3]",
            "--set",
            "loading.end_strain=0.01",
            "--set",
            "output.every=100",
            "--out",
            out,
        ];
        args.extend_from_slice(extra);
        let o = std::process::Command::new(common::fractum_bin())
            .args(&args)
            .current_dir(dir.path())
            .env(fractum::models::granular::sample::SAMPLE_CACHE, &cache)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    run("made", &["--checkpoint-every", "600"]);
    run("cached", &[]);
    let checkpoint = dir.path().join("made/checkpoints/step_000000600.fcp");
    common::resume(dir.path(), &checkpoint, &dir.path().join("resumed"));
    let read =
        |name: &str, file: &str| std::fs::read_to_string(dir.path().join(name).join(file)).unwrap();
    let made = read("made", "series.csv");
    assert!(made.lines().next().unwrap().contains("stress_radial_10"));
    for other in ["cached", "resumed"] {
        assert_eq!(
            made,
            read(other, "series.csv"),
            "series.csv of the {other} run"
        );
        assert_eq!(
            common::without_wall_seconds(&dir.path().join("made/summary.json")),
            common::without_wall_seconds(&dir.path().join(other).join("summary.json")),
            "summary.json of the {other} run"
        );
    }
}
