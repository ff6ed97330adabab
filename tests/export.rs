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
