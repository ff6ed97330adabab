//! Dry Mason sand (data/mason_sand_shpb/, sources in docs/references.md): samples at the
//! densities of real sand from the measured grains, the measured assembly imported as it is,
//! and the calibrated SHPB scene at reduced size. The full-size calibration and predictions
//! are examples/mason_sand.py's, reported in docs/validation.md.

mod common;

use common::{assert_stable_and_balanced, column, repo, run_scene, run_scene_failing};
use fractum::Scene;
use fractum::models::granular::sample::from_scene;
use fractum::shape::Shape;

const SCENE: &str = "scenes/mason_sand_shpb.toml";
const ASSEMBLY: &str = "data/mason_sand_shpb/grains_mason_sand_ellipsoids.csv";

fn shipped(sets: &[&str]) -> Scene {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Scene::read(&repo().join(SCENE), &sets).unwrap()
}

/// One row of the assembly: semi-axes (a, b, c), centre, and the 3 x 3 direction cosines
/// (row: axis a, b, c; column: world x, y, z).
type Row = ([f64; 3], [f64; 3], [[f64; 3]; 3]);

/// The assembly's rows, read here independently of the library's reader.
fn assembly() -> Vec<Row> {
    let text = std::fs::read_to_string(repo().join(ASSEMBLY)).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').skip(1).map(|t| t.parse().unwrap()).collect();
            let cos = [0, 1, 2].map(|axis| [0, 1, 2].map(|world| v[6 + 3 * axis + world].cos()));
            ([v[0], v[1], v[2]], [v[3], v[4], v[5]], cos)
        })
        .collect()
}

#[test]
fn mason_sand_grains_reach_0_66_in_a_small_box_reproducibly_and_0_80_is_refused() {
    // 2 mm box: about 200 grains, seven median grain diameters a side. The drawing of the
    // grains is the same for every packing; the frictionless compaction reaches 0.66 here and
    // refuses 0.80 in seconds (the jammed preparation is tested below).
    let sets = [
        "sample.box=[2e-3,2e-3,2e-3]",
        "sample.solid_fraction=0.66",
        "sample.packing=\"compaction\"",
    ];
    let a = from_scene(&shipped(&sets), &mut |_| {}).unwrap();
    let rows = assembly();
    let volumes: Vec<f64> = rows
        .iter()
        .map(|(s, _, _)| 4.0 / 3.0 * std::f64::consts::PI * s[0] * s[1] * s[2])
        .collect();
    let largest = volumes.iter().copied().fold(0.0, f64::max) / 8e-9;
    // Grains are drawn until they fill 0.66, the last kept only if that lands closer: within
    // half the largest grain's share of the box.
    let phi = a.info.solid_fraction;
    assert!((phi - 0.66).abs() <= largest / 2.0, "{phi}");
    assert_eq!(a.info.box_size, [2e-3, 2e-3, 2e-3]);
    // Every grain an ellipsoid (equal halves) of the assembly's semi-axes, inside the box.
    for i in 0..a.bodies.len() {
        let Shape::PolyEllipsoid { pe, .. } = a.bodies.shape[i] else {
            panic!("body {i} is not an ellipsoid");
        };
        let s = pe.semi;
        assert!(s[0] == s[1] && s[2] == s[3] && s[4] == s[5], "{s:?}");
        assert!(
            rows.iter().any(|(r, _, _)| *r == [s[0], s[2], s[4]]),
            "semi-axes {s:?} are not an assembly grain's"
        );
        let p = a.bodies.pos[i];
        assert!(p.iter().all(|&x| (0.0..=2e-3).contains(&x)), "{p}");
    }
    // The same seed builds the same sample, bit for bit.
    let b = from_scene(&shipped(&sets), &mut |_| {}).unwrap();
    assert_eq!(a.bodies.pos, b.bodies.pos);
    assert_eq!(a.bodies.orientation, b.bodies.orientation);

    // 0.80 is denser than random packings of such grains get: one sentence naming the key and
    // where the grains jammed. Frictionless ellipsoids of these aspect ratios jam near
    // 0.70-0.74 in bulk (Donev et al. 2004); the wall layers of a small box lower that, and
    // ellipsoids pack denser than spheres' random close packing, 0.64.
    let (code, stderr, wrote) = run_scene_failing(
        SCENE,
        &[
            "--set",
            "sample.box=[2e-3,2e-3,2e-3]",
            "--set",
            "sample.solid_fraction=0.80",
            "--set",
            "sample.packing=\"compaction\"",
        ],
    );
    assert_eq!(code, Some(2), "{stderr}");
    assert!(!wrote, "a refused sample left an output folder");
    let line = stderr.trim();
    assert_eq!(line.lines().count(), 1, "{stderr}");
    // It names the fraction asked for, not only what the grains drawn for it fill.
    assert!(
        line.contains("sample.solid_fraction (set with --set) = 0.8 (")
            && line.contains("jammed at about"),
        "{line}"
    );
    let at: f64 = line.split("jammed at about ").nth(1).unwrap()[..5]
        .parse()
        .unwrap();
    assert!((0.64..0.74).contains(&at), "{line}");
}

#[test]
fn compaction_in_a_small_box_lands_within_the_tolerance_of_the_fraction_or_is_refused() {
    // A 1.2 mm box holds about 56 Mason grains: one grain is up to 0.03 of the box. Drawn
    // until they filled 0.574, 8 seeds of 30 were built at 0.594-0.614 without a word. Each
    // seed now builds within fractum::sample::FRACTION_TOLERANCE of the scene's fraction, or is
    // refused in one sentence naming that fraction and what the whole grains fill.
    let tolerance = fractum::sample::FRACTION_TOLERANCE;
    let (mut built, mut refused) = (0, 0);
    for seed in 1..=30 {
        let seed = format!("seed={seed}");
        let sets = [
            seed.as_str(),
            "sample.box=[1.2e-3,1.2e-3,1.2e-3]",
            "sample.packing=\"compaction\"",
        ];
        match from_scene(&shipped(&sets), &mut |_| {}) {
            Ok(a) => {
                let phi = a.info.solid_fraction;
                assert!((phi - 0.574).abs() <= tolerance, "{seed}: built at {phi}");
                built += 1;
            }
            Err(e) => {
                let line = e.to_string();
                assert_eq!(line.trim().lines().count(), 1, "{seed}: {line}");
                assert!(
                    line.contains("sample.solid_fraction = 0.574"),
                    "{seed}: {line}"
                );
                refused += 1;
            }
        }
    }
    // Most seeds are built: whole grains come within 0.01 of the fraction unless the grain
    // left over is among the largest.
    eprintln!("1.2 mm box, 30 seeds: {built} built, {refused} refused");
    assert!(built > refused, "{built} built, {refused} refused");
}

#[test]
fn the_mason_sand_assembly_imports_with_its_grains_semi_axes_and_orientations() {
    let text = format!(
        r#"
name = "assembly"
effects = ["contact"]
[material]
young = 29e9
poisson = 0.18
density = 2650.0
[sample]
kind = "ellipsoid_assembly"
file = "{ASSEMBLY}"
[loading]
kind = "none"
end_time = 1e-6
"#
    );
    let scene = Scene::from_toml(&text, "assembly", &repo(), &[]).unwrap();
    let sample = from_scene(&scene, &mut |_| {}).unwrap();
    let rows = assembly();
    assert_eq!(rows.len(), 644);
    assert_eq!(sample.bodies.len(), 644);
    for (i, (semi, centre, cos)) in rows.iter().enumerate() {
        let Shape::PolyEllipsoid { pe, .. } = sample.bodies.shape[i] else {
            panic!("body {i} is not an ellipsoid");
        };
        let s = pe.semi;
        for (k, v) in [s[0], s[2], s[4]].iter().enumerate() {
            assert!(
                (v / semi[k] - 1.0).abs() <= 1e-12,
                "grain {i}: {s:?} {semi:?}"
            );
        }
        assert!(s[0] == s[1] && s[2] == s[3] && s[4] == s[5]);
        let (origin, q) = sample.bodies.shape_placement(i);
        for k in 0..3 {
            assert!((origin[k] - centre[k]).abs() <= 1e-12 * 3e-3, "grain {i}");
        }
        // The shape frame's axes in the world: the nearest rotation to the file's cosines
        // (to 1e-12), which are themselves orthonormal only to their 7 printed digits.
        let m = nalgebra::Matrix3::from_fn(|world, axis| cos[axis][world]);
        let nearest =
            nalgebra::Rotation3::from_matrix_eps(&m, 1e-15, 100, nalgebra::Rotation3::identity());
        let r = q.to_rotation_matrix();
        let off = (r.matrix() - nearest.matrix()).abs().max();
        assert!(off <= 1e-12, "grain {i}: rotation off by {off:e}");
        let raw = (r.matrix() - m).abs().max();
        assert!(raw <= 3e-6, "grain {i}: off the file's cosines by {raw:e}");
    }
    // The box its grains span: the 3 mm cube of the study, solid fraction 0.583.
    let size = sample.info.box_size;
    for (k, want) in [3e-3, 3e-3, 3e-3].iter().enumerate() {
        assert!((size[k] - want).abs() < 1e-7, "{size:?}");
    }
    assert!(
        (sample.info.solid_fraction - 0.5833).abs() < 1e-3,
        "{}",
        sample.info.solid_fraction
    );
}

/// The shipped scene at reduced size (a 2 mm box, about 180 grains) to 2% strain. Its jammed
/// preparation lands at the fraction of the grains drawn (within the protocol's stated 0.01)
/// and carries load before the platen moves: the stress it jammed at on its faces and at least
/// four contacts per grain (the isostatic count of frictional grains; a sample compressed
/// without friction below jamming has neither).
#[test]
fn the_mason_sand_scene_jams_its_sample_and_runs_to_0_02_strain_at_reduced_size() {
    let (_dir, s, series) = run_scene(
        SCENE,
        &[
            "--threads",
            "2",
            "--set",
            "sample.box=[2e-3,2e-3,2e-3]",
            "--set",
            "loading.end_strain=0.02",
            "--set",
            "output.report_strains=[0.01,0.02]",
        ],
    );
    assert!((s["strain_final"].as_f64().unwrap() - 0.02).abs() < 1e-3);
    // Grains are drawn until they fill 0.574, the last kept only if that lands closer: within
    // half the largest grain's share of this box (1.6%), then jammed within 0.01 of what they
    // fill.
    let phi = s["solid_fraction_initial"].as_f64().unwrap();
    let tolerance = fractum::sample::FRACTION_TOLERANCE;
    assert!((phi - 0.574).abs() <= 0.008 + tolerance, "{phi}");
    // Jammed: settled, the grains still carried the protocol's jamming pressure,
    // fractum::sample::JAM_PER_MODULUS of E/(1 - ν²), on the mean of the faces.
    let stress = s["initial_mean_stress"].as_f64().unwrap();
    let z = s["initial_coordination"].as_f64().unwrap();
    let modulus = 95e9 / (1.0 - 0.18f64.powi(2));
    assert!(
        stress >= fractum::sample::JAM_PER_MODULUS * modulus,
        "{stress} Pa"
    );
    assert!(z >= 4.0, "{z} contacts per grain");
    // The main job's energy check (docs/validation.md): within 2% of the face work.
    assert_stable_and_balanced(&s, &series, 0.02);
    // Each face and the sides at the report strains, named apart. Wall friction carries part
    // of the load, so the face opposite the driven one carries less; frictional grains press
    // their sides with less than the axial stress (K0 < 1).
    for e in ["0.01", "0.02"] {
        let driven = s["stress_driven_at_strain"][e].as_f64().unwrap();
        let opposite = s["stress_opposite_at_strain"][e].as_f64().unwrap();
        let lateral = s["stress_lateral_at_strain"][e].as_f64().unwrap();
        let mean = s["stress_at_strain"][e].as_f64().unwrap();
        assert!(
            (mean - 0.5 * (driven + opposite)).abs() <= 1e-9 * mean,
            "{e}"
        );
        assert!(
            opposite > 0.0 && opposite < driven,
            "{e}: {opposite} {driven}"
        );
        assert!(lateral > 0.0 && lateral < mean, "{e}: {lateral} {mean}");
    }
    // The summary's value is series.csv's, interpolated.
    let eps = column(&series, "axial_strain");
    let bottom = column(&series, "stress_opposite");
    let k = eps.iter().position(|&x| x >= 0.02).unwrap();
    let t = (0.02 - eps[k - 1]) / (eps[k] - eps[k - 1]);
    let want = bottom[k - 1] + t * (bottom[k] - bottom[k - 1]);
    let got = s["stress_opposite_at_strain"]["0.02"].as_f64().unwrap();
    assert!((got - want).abs() <= 1e-9 * want.abs(), "{got} {want}");
}

/// The particle strength the scene's Hoek–Brown σc stands for, measured as a crushing test
/// measures it: the scene's own grain material between flat platens (scenes/crush_grain.toml
/// with a sphere of the reference radius, the Mason scene's E, ν and σc, no Weibull scatter)
/// breaks at its first force peak at F = (2π/3) σc x_M² (a sphere under two opposite forces
/// F carries the average stress 3F/(2π x_M²) along them: Hoek–Brown with σ3 = 0 fails at
/// σc), i.e. a particle strength F/d² = (π/6) σc, raised by the grain's flattening at its
/// platens; and the Hertz edge stress (Eq. 17) at its
/// platen contacts at that force, worked out here by hand, is the contact strength the scene
/// derives from σc (fracture::platen_contact_strength).
#[test]
fn the_scene_s_particle_strength_is_what_its_grain_shows_between_platens() {
    let scene = shipped(&[]);
    let f = &scene.tables["fracture"];
    let m = &scene.tables["material"];
    let num = |t: &toml::Value, k: &str| t[k].as_float().unwrap();
    let (sigma_c, x_m) = (num(f, "sigma_c"), num(f, "reference_radius"));
    let (young, nu) = (num(m, "young"), num(m, "poisson"));
    let strength = fractum::fracture::platen_contact_strength(sigma_c, x_m, young, nu);
    let (_dir, s, _) = run_scene(
        "scenes/crush_grain.toml",
        &[
            "--set",
            r#"effects=["contact","damping","friction","fracture"]"#,
            "--set",
            &format!("sample.semi_axes=[{x_m:e},{x_m:e},{x_m:e},{x_m:e},{x_m:e},{x_m:e}]"),
            "--set",
            &format!("material.young={young:e}"),
            "--set",
            &format!("material.poisson={nu}"),
            "--set",
            &format!("fracture.sigma_c={sigma_c:e}"),
            "--set",
            &format!("fracture.reference_strength={strength:e}"),
            "--set",
            "loading.end_displacement=0.03e-3",
        ],
    );
    let peak = s["first_peak_force"].as_f64().unwrap();
    let want = 2.0 * std::f64::consts::PI / 3.0 * sigma_c * x_m * x_m;
    // Eq. 8 takes each force at its contact point, which for a grain on a wall is on the
    // wall's plane: the lever is x_M − δ, δ the Hertz overlap at that force, so the grain
    // fails at want · x_M / (x_M − δ) (δ/x_M about 5% at 95 GPa).
    let e_star = young / (2.0 * (1.0 - nu * nu));
    let overlap = |f: f64| (3.0 * f / (4.0 * e_star * x_m.sqrt())).powf(2.0 / 3.0);
    let mut at_lever = want;
    for _ in 0..20 {
        at_lever = want * x_m / (x_m - overlap(at_lever));
    }
    // The platens move at 6 mm/s: the grain's inertia adds to the average stress by
    // (ρ a x_M) / σc, below 1e-6 here; 2% covers the peak's sampling (a row every 50 steps).
    assert!(
        (peak / at_lever - 1.0).abs() < 0.02,
        "first peak {peak} N, Hoek-Brown {at_lever} N ({want} N at the undeformed lever)"
    );
    assert_eq!(
        s["splits"]["hoek_brown"].as_u64().unwrap(),
        s["splits"]["total"].as_u64().unwrap()
    );
    // Hertz between the sphere and a platen (same material, as the contact law takes walls),
    // at the undeformed lever's force, which is how the strength is derived.
    let a = (3.0 * want * x_m / (4.0 * e_star)).cbrt();
    let q0 = 3.0 * want / (2.0 * std::f64::consts::PI * a * a);
    let edge = (1.0 - 2.0 * nu) / 3.0 * q0;
    assert!((edge / strength - 1.0).abs() < 1e-12, "{edge} {strength}");
}

/// The FMU's test of its Mason sand variant reads the shipped scene's 3 mm sample from a
/// committed sample-cache fixture (a quarter of an hour to prepare): the fixture must be the
/// one the scene's sample is kept under, as the FMU carries the scene (its grain file beside
/// it, the path rewritten by scripts/pack_fmu.sh). A change to the scene's sample, material or
/// neighbour tables, the grain file, the crate's version or the preparation's revision names
/// another file: remake it with scripts/mason_sample_fixture.sh.
#[test]
fn the_fmu_s_mason_sample_fixture_is_what_the_scene_prepares() {
    let want = fractum::models::granular::sample::cache_name(&shipped(&[]));
    let text = std::fs::read_to_string(repo().join(SCENE))
        .unwrap()
        .replace("\"../data/mason_sand_shpb/", "\"mason_sand_shpb/");
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("mason_sand_shpb")).unwrap();
    std::fs::copy(
        repo().join(ASSEMBLY),
        dir.path()
            .join("mason_sand_shpb/grains_mason_sand_ellipsoids.csv"),
    )
    .unwrap();
    let scene = dir.path().join("mason_sand_shpb.toml");
    std::fs::write(&scene, text).unwrap();
    let packed = Scene::read(&scene, &["seed=1".to_string()]).unwrap();
    assert_eq!(
        fractum::models::granular::sample::cache_name(&packed),
        want,
        "the FMU's copy of the scene names another sample"
    );
    let have: Vec<String> = std::fs::read_dir(repo().join("tests/data/mason_sand_sample"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().to_string())
        .collect();
    assert_eq!(
        have,
        vec![want],
        "tests/data/mason_sand_sample is stale: run scripts/mason_sample_fixture.sh"
    );
}

/// The six records' axial (one-wave) stress (MPa) on the loading branch at `strain`: each
/// record up to its peak, interpolated at its first crossing of the strain (read here from
/// data/mason_sand_shpb/ independently of examples/mason_sand.py).
fn records_at(strain: f64) -> Vec<f64> {
    ["026", "027", "028", "029", "030", "035"]
        .iter()
        .filter_map(|t| {
            let path = repo().join(format!("data/mason_sand_shpb/test_052212-{t}.csv"));
            let text = std::fs::read_to_string(path).unwrap();
            let rows: Vec<(f64, f64)> = text
                .lines()
                .skip(1)
                .map(|l| {
                    let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
                    (v[1], v[2])
                })
                .collect();
            let peak = (0..rows.len())
                .max_by(|&a, &b| rows[a].1.total_cmp(&rows[b].1))
                .unwrap();
            rows[..=peak].windows(2).find_map(|w| {
                let ((e0, s0), (e1, s1)) = (w[0], w[1]);
                (e0 <= strain && strain <= e1 && e1 > e0)
                    .then(|| s0 + (strain - e0) / (e1 - e0) * (s1 - s0))
            })
        })
        .collect()
}

/// The shipped scene against the records themselves: its own 3 mm sample of seed 1 (the
/// committed sample-cache fixture, so no quarter-hour preparation), run to 0.10 strain,
/// carries on the face opposite the driven one (the transmitted bar's face, which the
/// laboratory's one-wave stress measures) a stress inside the six records' min–max band
/// widened by 15% at 0.05 and 0.10 strain. The tolerance is the full-size check of the
/// calibration (docs/validation.md, "Against the experiments"), fixed there before any run;
/// this is the sample those full-size numbers were measured on, so a change to the physics,
/// the sample or the loading that breaks the agreement fails here. A test, not a fit: the
/// strengths were calibrated on these records (docs/validation.md says how and on what).
///
/// One thread, as every run of the calibration (examples/mason_sand.py). The same sample on
/// two threads (another summation order, so another trajectory after the first splits)
/// carried 8.23 and 17.77 MPa against one thread's 8.18 and 11.78: at 0.10 it missed the
/// widened band (17.71) by 0.3%. One trajectory's stress at 0.10 scatters by half its value
/// here, so this guards against a change that moves the model's stress, not against the
/// scatter of one run (docs/validation.md).
#[test]
fn the_shipped_scene_carries_the_records_stress_at_0_05_and_0_10_strain() {
    let cache = tempfile::tempdir().unwrap();
    for entry in std::fs::read_dir(repo().join("tests/data/mason_sand_sample")).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), cache.path().join(entry.file_name())).unwrap();
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = std::process::Command::new(common::fractum_bin())
        .args([
            "run",
            repo().join(SCENE).to_str().unwrap(),
            "--quiet",
            "--threads",
            "1",
            "--out",
            out.to_str().unwrap(),
            "--set",
            "loading.end_strain=0.1",
            "--set",
            "output.report_strains=[0.05,0.1]",
        ])
        .env(
            fractum::models::granular::sample::SAMPLE_CACHE,
            cache.path(),
        )
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    // The fixture's sample: seed 1's 606 grains, jammed at 0.5701.
    assert_eq!(s["sample"]["count"].as_u64(), Some(606), "{}", s["sample"]);
    for (strain, key) in [(0.05, "0.05"), (0.10, "0.1")] {
        let records = records_at(strain);
        assert_eq!(records.len(), 6);
        let lo = records.iter().cloned().fold(f64::INFINITY, f64::min) * 0.85;
        let hi = records.iter().cloned().fold(0.0, f64::max) * 1.15;
        let got = s["stress_opposite_at_strain"][key].as_f64().unwrap() / 1e6;
        assert!(
            (lo..=hi).contains(&got),
            "at strain {strain}: {got:.2} MPa on the opposite face, the records' band widened by 15% is {lo:.2}-{hi:.2} MPa"
        );
    }
}
