//! `fractum export lammps|yade`: the scene's packing at full precision, which both import
//! kinds (`lammps_data`, `yade_text`) read back bit for bit, box included.

mod common;

use std::path::Path;

use fractum::Scene;

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
        // Without a `box` key the import takes the box from the file.
        let import_text = text.replace("box = [3e-3, 3e-3, 3e-3]\n", "");
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
    let import_text = text.replace("box = [3e-3, 3e-3, 3e-3]\n", "");
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
