//! `fractum export lammps|yade`: the scene's packing at full precision, which both import
//! kinds (`lammps_data`, `yade_text`) read back bit for bit, box included.

mod common;

use std::path::Path;
use std::process::Output;

use fractum::Scene;

/// A random sample's scene without the keys a packing file's sample refuses: the amount
/// (`count`, `solid_fraction`) the file fixes, and `box`, so that the import takes the box from
/// the file.
fn as_file_sample(text: &str) -> String {
    let dropped = ["box = ", "count = ", "solid_fraction = "];
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| !dropped.iter().any(|d| l.starts_with(d)))
        .collect();
    assert_eq!(kept.len() + 3, text.lines().count(), "{text}");
    kept.join("\n")
}

#[test]
fn exported_packings_read_back_bit_for_bit() {
    let text = common::small_oedometer(150, "\"contact\"", 0.001);
    let (dir, scene_path) = common::scene_file(&text);
    let scene = Scene::from_toml(&text, "t", dir.path(), &[]).unwrap();
    let original = fractum::models::granular::sample::from_scene(&scene, &mut |_| {}).unwrap();
    for (format, file, kind) in [
        ("lammps", "packing.data", "lammps_data"),
        ("yade", "packing.txt", "yade_text"),
    ] {
        let out = dir.path().join(format);
        let o = common::fractum(
            dir.path(),
            &[
                "export",
                format,
                scene_path.to_str().unwrap(),
                out.to_str().unwrap(),
                "--quiet",
            ],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let overrides = vec![
            format!("sample.kind={kind}"),
            format!("sample.file=\"{}\"", out.join(file).display()),
        ];
        let import_text = as_file_sample(&text);
        let imported_scene =
            Scene::from_toml(&import_text, "t", Path::new("."), &overrides).unwrap();
        let imported =
            fractum::models::granular::sample::from_scene(&imported_scene, &mut |_| {}).unwrap();
        assert_eq!(imported.bodies.len(), original.bodies.len(), "{format}");
        assert_eq!(
            imported.bodies.pos, original.bodies.pos,
            "{format}: positions"
        );
        assert_eq!(
            imported.bodies.radius, original.bodies.radius,
            "{format}: radii"
        );
        assert_eq!(
            imported.walls.box_size(),
            original.walls.box_size(),
            "{format}: box"
        );
        assert_eq!(
            imported.info.solid_fraction, original.info.solid_fraction,
            "{format}"
        );
    }
}

#[test]
fn export_of_a_bad_scene_writes_nothing() {
    let text = common::small_oedometer(50, "\"contact\"", 0.001)
        .replace("poisson = 0.17", "poisson = 0.6");
    let (dir, scene_path) = common::scene_file(&text);
    let out = dir.path().join("out");
    let o = common::fractum(
        dir.path(),
        &[
            "export",
            "lammps",
            scene_path.to_str().unwrap(),
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("material.poisson"));
    assert!(!out.exists());
}

/// A data file that carries the Fractum LAMMPS plugin's sections (`fractum export lammps
/// --plugin`, or LAMMPS's `write_data` in a plugin run) reads back as the bodies the plugin
/// holds: poly-ellipsoids with their semi-axes, octant origins and frames, orientations and
/// inertia bit for bit, masses through LAMMPS's density column (the mass over the bounding
/// sphere's volume and back: two roundings, 2 ulps at most).
#[test]
fn plugin_data_reads_back_as_the_bodies_it_holds() {
    let text = common::small_oedometer(60, "\"contact\"", 0.001);
    let (dir, scene_path) = common::scene_file(&text);
    let shaped = ["sample.shape=\"poly_ellipsoid\"".to_string()];
    let scene = Scene::from_toml(&text, "t", dir.path(), &shaped).unwrap();
    let original = fractum::models::granular::sample::from_scene(&scene, &mut |_| {}).unwrap();
    let out = dir.path().join("plugin");
    let o = common::fractum(
        dir.path(),
        &[
            "export",
            "lammps",
            scene_path.to_str().unwrap(),
            out.to_str().unwrap(),
            "--plugin",
            "--set",
            &shaped[0],
            "--quiet",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let overrides = vec![
        "sample.kind=lammps_data".to_string(),
        format!("sample.file=\"{}\"", out.join("packing.data").display()),
    ];
    let import_text = as_file_sample(&text);
    let imported_scene = Scene::from_toml(&import_text, "t", Path::new("."), &overrides).unwrap();
    let imported =
        fractum::models::granular::sample::from_scene(&imported_scene, &mut |_| {}).unwrap();
    let (a, b) = (&original.bodies, &imported.bodies);
    assert_eq!(a.len(), b.len());
    assert!(a.shape.iter().all(|s| !s.is_sphere()), "poly-ellipsoids");
    assert_eq!(a.pos, b.pos);
    assert_eq!(a.radius, b.radius);
    assert_eq!(a.orientation, b.orientation);
    assert_eq!(a.inertia, b.inertia);
    assert_eq!(a.shape, b.shape);
    for (m, n) in a.mass.iter().zip(&b.mass) {
        assert!(
            (m - n).abs() <= 2.0 * f64::EPSILON * m,
            "mass {m} read back as {n}"
        );
    }
    // A file with only some of the plugin's sections is refused, naming what it lacks.
    let data = std::fs::read_to_string(out.join("packing.data")).unwrap();
    let cut = data.find("\nFractumInertia").unwrap();
    let rest = data[cut + 1..].find("\nFractumGrain").unwrap();
    let partial = format!("{}{}", &data[..cut], &data[cut + 1 + rest..]);
    std::fs::write(out.join("partial.data"), partial).unwrap();
    let overrides = vec![
        "sample.kind=lammps_data".to_string(),
        format!("sample.file=\"{}\"", out.join("partial.data").display()),
    ];
    let partial_scene = Scene::from_toml(&import_text, "t", Path::new("."), &overrides).unwrap();
    let err = fractum::models::granular::sample::from_scene(&partial_scene, &mut |_| {})
        .err()
        .expect("refused")
        .to_string();
    assert!(
        err.contains("sample.file") && err.contains("not FractumInertia"),
        "{err}"
    );
}

/// `fractum export FORMAT SCENE OUT [extra]` of a shipped scene into a fresh folder: the
/// process output and the folder.
fn export_shipped(format: &str, scene: &str, extra: &[&str]) -> (Output, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = common::repo().join("scenes").join(scene);
    let mut args = vec![
        "export",
        format,
        scene.to_str().unwrap(),
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    (common::fractum(dir.path(), &args), dir)
}

#[test]
fn plain_exports_of_grains_that_are_not_spheres_are_refused_naming_the_plugin() {
    // The plain exports wrote each poly-ellipsoid as its bounding sphere (crush_grain's grain a
    // sphere taller than its box; the Mason sand ellipsoids 1.4 times their box) with exit 0.
    for format in ["lammps", "yade"] {
        let (o, dir) = export_shipped(format, "crush_grain.toml", &[]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{format}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(
            stderr.contains("crush_grain.toml")
                && stderr.contains("1 of the sample's 1 grains are not spheres")
                && stderr.contains("--plugin"),
            "{stderr}"
        );
        assert!(!dir.path().join("out").exists(), "nothing written");
    }
    let (o, dir) = export_shipped("lammps", "crush_grain.toml", &["--plugin", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.path().join("out/packing.data").is_file());
}

#[test]
fn plain_exports_say_that_they_leave_the_fracture_effects_out() {
    let small = [
        "--set",
        "sample.box=[3e-3,3e-3,3e-3]",
        "--set",
        "sample.solid_fraction=0.45",
    ];
    for (format, script) in [("lammps", "in.fractum"), ("yade", "fractum_yade.py")] {
        let (o, dir) = export_shipped(format, "shpb_sand.toml", &small);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{stderr}");
        let said = "not exported: the effects \"fracture\", \"cohesion\", \"weibull\"";
        assert!(
            stderr.contains(said) && stderr.contains("--plugin"),
            "{stderr}"
        );
        let text = std::fs::read_to_string(dir.path().join("out").join(script)).unwrap();
        assert!(
            text.lines().next().unwrap().contains(said),
            "{script}: {}",
            text.lines().next().unwrap()
        );
    }
    // A scene without them says nothing of the kind.
    let (o, _dir) = export_shipped("lammps", "oedometer_spheres.toml", &[]);
    assert!(o.status.success());
    assert!(!String::from_utf8_lossy(&o.stderr).contains("not exported"));
}

#[test]
fn plain_exports_of_a_sleeve_are_refused_naming_the_plugin_which_writes_it() {
    let sleeve = [
        "--set",
        "walls.sleeve=true",
        "--set",
        "sample.box=[3e-3,3e-3,3e-3]",
        "--set",
        "sample.solid_fraction=0.45",
    ];
    for format in ["lammps", "yade"] {
        let (o, dir) = export_shipped(format, "shpb_sand.toml", &sleeve);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{format}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(
            stderr.contains("walls.sleeve") && stderr.contains("--plugin"),
            "{stderr}"
        );
        assert!(!dir.path().join("out").exists(), "nothing written");
    }
    let mut plugin = sleeve.to_vec();
    plugin.extend(["--plugin", "--quiet"]);
    let (o, dir) = export_shipped("lammps", "shpb_sand.toml", &plugin);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let script = std::fs::read_to_string(dir.path().join("out/in.fractum")).unwrap();
    // The sleeve inscribed in the 3 mm box's x-y section, the side faces left out.
    assert!(
        script.contains(" sleeve 1.5") && !script.contains(" xlo ") && script.contains(" zhi "),
        "{script}"
    );
}
