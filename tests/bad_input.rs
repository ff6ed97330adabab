//! Bad input: one sentence naming the file, the key and the allowed range, exit code 2, and
//! no output folder left behind.

mod common;

use std::path::Path;

fn base() -> String {
    common::small_oedometer(50, "\"contact\"", 0.001)
}

/// Runs `fractum run` on `text` (with `extra` arguments), checks that it was refused (exit
/// code 2, one line, no output folder) and returns that line and the scene file.
fn refused(text: &str, extra: &[&str]) -> (String, std::path::PathBuf) {
    let (dir, file) = common::scene_file(text);
    let out = dir.path().join("out");
    let mut args = vec![
        "run",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let o = common::fractum(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "exit code, stderr: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "one line: {stderr}");
    assert!(!out.exists(), "no output folder for bad input");
    (lines[0].to_string(), file)
}

/// Runs `fractum run` on `text` (with `extra` arguments) and checks the failure: refused,
/// naming the file and each of `wanted`.
fn fails(text: &str, extra: &[&str], wanted: &[&str]) {
    let (line, file) = refused(text, extra);
    assert!(
        line.contains(file.to_str().unwrap()),
        "names the file: {line}"
    );
    for w in wanted {
        assert!(line.contains(w), "mentions `{w}`: {line}");
    }
}

fn replace(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "test scene has `{from}`");
    text.replacen(from, to, 1)
}

#[test]
fn unknown_key() {
    let t = replace(&base(), "young = 60e9", "young = 60e9\nyoungs = 1.0");
    fails(
        &t,
        &[],
        &["material.youngs", "unknown key", "allowed keys", "young"],
    );
}

#[test]
fn unknown_key_via_set() {
    fails(
        &base(),
        &["--set", "material.yung=70e9"],
        &["material.yung", "unknown key", "--set"],
    );
}

#[test]
fn wrong_type() {
    let t = replace(&base(), "young = 60e9", "young = \"stiff\"");
    fails(&t, &[], &["material.young", "wrong type", "a number"]);
}

#[test]
fn poisson_out_of_range() {
    let t = replace(&base(), "poisson = 0.17", "poisson = 0.5");
    fails(&t, &[], &["material.poisson", "0.5", "(-1, 0.5)"]);
    fails(
        &base(),
        &["--set", "material.poisson=-1.2"],
        &["material.poisson", "(-1, 0.5)"],
    );
}

#[test]
fn non_positive_radius_density_young() {
    let t = replace(&base(), "radius_mean = 0.3e-3", "radius_mean = 0.0");
    fails(&t, &[], &["sample.radius_mean", "(0, ∞)"]);
    let t = replace(&base(), "density = 2650.0", "density = -2650.0");
    fails(&t, &[], &["material.density", "(0, ∞)", "kg/m³"]);
    let t = replace(&base(), "young = 60e9", "young = 0");
    fails(&t, &[], &["material.young", "(0, ∞)", "Pa"]);
}

#[test]
fn missing_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = common::fractum(
        dir.path(),
        &["run", "no_such_scene.toml", "--out", out.to_str().unwrap()],
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(stderr.lines().count(), 1);
    assert!(
        stderr.contains("no_such_scene.toml") && stderr.contains("no such file"),
        "{stderr}"
    );
    assert!(!out.exists());
}

#[test]
fn checkpoint_every_zero_is_refused_before_anything_is_written() {
    // It divided by zero in the driver (a panic and a partial output folder). A command-line
    // option, not a scene key: the sentence names the option, not the file.
    let (line, _) = refused(&base(), &["--checkpoint-every", "0"]);
    assert!(
        line.contains("--checkpoint-every") && line.contains("at least 1"),
        "{line}"
    );
}

#[test]
fn missing_packing_file() {
    let t = replace(
        &base(),
        "kind = \"random\"",
        "kind = \"text\"\nfile = \"nowhere.txt\"",
    );
    // A file's sample refuses the amount keys of a random one.
    let t = replace(&t, "count = 50\n", "");
    let t = replace(&t, "solid_fraction = 0.5\n", "");
    fails(&t, &[], &["sample.file", "nowhere.txt", "no such file"]);
}

#[test]
fn unknown_effect_lists_the_allowed_ones() {
    let t = replace(
        &base(),
        "effects = [\"contact\"]",
        "effects = [\"contact\", \"frction\"]",
    );
    fails(&t, &[], &["effects", "frction", "friction"]);
}

#[test]
fn bad_toml_names_the_line() {
    let t = replace(&base(), "young = 60e9", "young = = 60e9");
    fails(&t, &[], &["line"]);
}

#[test]
fn set_without_equals() {
    fails(&base(), &["--set", "material.young"], &["KEY=VALUE"]);
}

#[test]
fn a_good_scene_passes_these_checks() {
    // The base scene itself is valid: the failures above come from the one change each makes.
    let (dir, file) = common::scene_file(&base());
    let o = common::fractum(dir.path(), &["explain", file.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(Path::new(&file).exists());
}

#[test]
fn brazilian_loadings_refuse_keys_that_do_not_go_with_them() {
    let b = std::fs::read_to_string(common::repo().join("scenes/brazilian.toml")).unwrap();
    for (by, arc) in [("flat_platens", "20"), ("curved_jaws", "12")] {
        fails(
            &b,
            &[
                "--set",
                &format!("loading.load_by=\"{by}\""),
                "--set",
                &format!("loading.arc_degrees={arc}"),
            ],
            &["loading.arc_degrees", arc, "[0, 0]", by],
        );
    }
    fails(
        &b,
        &["--set", "loading.load_by=\"arc_pressure\""],
        &["loading.arc_degrees", "arc_pressure", "(0, 90]"],
    );
    fails(
        &b,
        &["--set", "loading.servo_stiffness=1e9"],
        &["loading.servo_stiffness", "arc_pressure", "flat_platens"],
    );
    fails(
        &b,
        &[
            "--set",
            "loading.load_by=\"arc_pressure\"",
            "--set",
            "loading.arc_degrees=20",
            "--set",
            "loading.servo_stiffness=-1",
        ],
        &["loading.servo_stiffness", "(0, ∞)", "N/m"],
    );
}

// beam2d: its keys, and keys that belong to one model only.

fn beam2d_base() -> String {
    std::fs::read_to_string(common::repo().join("scenes/explosion_disc.toml")).unwrap()
}

#[test]
fn beam2d_keys_name_their_ranges() {
    let b = beam2d_base();
    fails(
        &b,
        &["--set", "sample.disorder=0.02"],
        &["sample.disorder", "0.02", "[0, 0.0108]"],
    );
    fails(
        &replace(&b, "beam_young = 5e8", "beam_young = -5e8"),
        &[],
        &["material.beam_young", "(0, ∞)", "Pa"],
    );
    fails(
        &replace(&b, "beam_young = 5e8                     # E (Pa)\n", ""),
        &[],
        &["material.beam_young", "required", "beams"],
    );
    fails(
        &b,
        &["--set", "material.beam_bending_threshold=0"],
        &["material.beam_bending_threshold", "(0, ∞)", "rad"],
    );
    fails(
        &b,
        &["--set", "fragments.fit_range=[20.0, 2.0]"],
        &["fragments.fit_range", "must exceed"],
    );
    fails(
        &b,
        &["--set", "loading.quiet_steps=0"],
        &["loading.quiet_steps", "[1, ∞)"],
    );
    fails(
        &b,
        &["--set", "sample.diameter=0.02"],
        &["sample.diameter", "three lattice spacings"],
    );
    fails(
        &b,
        &["--set", "material.beam_breaking_rule=\"von_mises\""],
        &[
            "material.beam_breaking_rule",
            "von_mises",
            "eq13, squared, mean_angle, either_sign",
        ],
    );
    fails(
        &b,
        &["--set", "loading.explosive=\"gone\""],
        &["loading.explosive", "gone", "spent, kept"],
    );
}

#[test]
fn beam2d_combinations_that_do_not_go_together() {
    let b = beam2d_base();
    fails(
        &b,
        &["--set", "effects=[\"beam_breaking\"]"],
        &["effects", "beam_breaking", "without \"beams\""],
    );
    fails(
        &b,
        &["--set", "effects=[\"beams\", \"gravity\"]"],
        &["effects", "gravity", "beam2d"],
    );
    fails(
        &b,
        &[
            "--set",
            "loading.kind=\"projectile\"",
            "--set",
            "loading.speed=400",
        ],
        &["sample.outline", "disc", "rectangle"],
    );
    fails(
        &b,
        &["--set", "loading.projectile=\"free\""],
        &["loading.projectile", "explosion", "\"projectile\" only"],
    );
    fails(
        &b,
        &["--set", "loading.kind=\"oedometer\""],
        &["loading.kind", "oedometer", "beam2d", "explosion"],
    );
    fails(
        &b,
        &["--set", "model.kind=\"granular\""],
        &["sample.kind", "vectorizable_random_lattice", "granular"],
    );
    // A sphere scene asked for Gear's integrator, or for a Poisson's ratio it lacks.
    fails(
        &base(),
        &["--set", "time.integrator=\"gear5\""],
        &["time.integrator", "gear5", "beam2d"],
    );
    let t = replace(&base(), "poisson = 0.17\n", "");
    fails(&t, &[], &["material.poisson", "required", "granular"]);
}

/// A key of another model is refused by name, naming the model that has it and the keys
/// this scene's model allows; the shipped scenes of each model are checked both ways.
#[test]
fn key_of_another_model() {
    let t = replace(
        &base(),
        "kind = \"oedometer\"",
        "kind = \"oedometer\"\narc_degrees = 20.0",
    );
    fails(
        &t,
        &[],
        &[
            "`loading.arc_degrees`",
            "model.kind = \"dlsm\"",
            "model.kind = \"granular\"",
            "allowed keys: kind, strain_rate",
        ],
    );
    fails(
        &base(),
        &["--set", "fragments.bins_per_decade=4"],
        &["`fragments`", "model.kind = \"beam2d\"", "--set"],
    );
    for (scene, key, owner) in [
        ("brazilian.toml", "sample.count=10", "granular"),
        ("explosion_disc.toml", "loading.arc_degrees=20", "dlsm"),
        ("dlsm_tensile.toml", "material.beam_young=1e9", "beam2d"),
    ] {
        let text = std::fs::read_to_string(common::repo().join("scenes").join(scene)).unwrap();
        let key_name = key.split('=').next().unwrap();
        fails(
            &text,
            &["--set", key],
            &[
                &format!("`{key_name}`"),
                &format!("model.kind = \"{owner}\""),
            ],
        );
    }
}

#[test]
fn unknown_model() {
    fails(
        &base(),
        &["--set", "model.kind=lattice"],
        &["model.kind", "\"lattice\"", "granular, dlsm, beam2d"],
    );
}

#[test]
fn a_name_that_is_not_a_plain_file_name_is_refused() {
    // Without --out the name becomes out/NAME: "../../x" or an absolute name wrote outside
    // out/, and a NUL byte failed late with exit 1.
    for bad in ["../../x", "/tmp/x", "a/b", ".hidden", "a\\u0000b", "a b"] {
        let t = replace(
            &base(),
            "name = \"small_oedometer\"",
            &format!("name = \"{bad}\""),
        );
        fails(&t, &[], &["name", "plain file name", "out/NAME"]);
    }
}

#[test]
fn more_threads_than_cores_is_refused() {
    // `--threads 100000` made rayon start them and the run hang with no message.
    let (line, _) = refused(&base(), &["--threads", "100000"]);
    assert!(
        line.contains("--threads") && line.contains("100000") && line.contains("cores"),
        "{line}"
    );
}

#[test]
fn a_run_of_more_steps_than_the_limit_is_refused() {
    // A step of 1e-300 s, or a Young's modulus of 1e308 Pa under the automatic step, planned
    // 18446744073709551615 steps and ran forever.
    // 80 spheres: a sample that builds (the check needs the sample's step).
    let t = common::small_oedometer(80, "\"contact\"", 0.001);
    for set in ["time.dt=1e-300", "material.young=1e308"] {
        let (line, _) = refused(&t, &["--set", set]);
        assert!(
            line.contains("time.dt") && line.contains("limit of 1e9 steps"),
            "{set}: {line}"
        );
    }
}

#[test]
fn sizes_beyond_the_body_limit_are_refused_before_allocating() {
    // 10^9 spheres allocated until the process aborted (exit 134, 4 GB); hcp layers of 10^7
    // each panicked on capacity overflow; 10^9 dlsm elements likewise.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for (scene, set, key) in [
        (
            "oedometer_spheres.toml",
            "sample.count=1000000000",
            "sample.count",
        ),
        ("shpb_sand.toml", "sample.box=[1,1,1]", "sample.box"),
        (
            "shpb_hcp.toml",
            "sample.layers=[10000000,10000000,10000000]",
            "sample.layers",
        ),
        (
            "dlsm_tensile.toml",
            "sample.elements=1000000000",
            "sample.elements",
        ),
    ] {
        let file = common::repo().join("scenes").join(scene);
        let o = common::fractum(
            dir.path(),
            &[
                "run",
                file.to_str().unwrap(),
                "--set",
                set,
                "--out",
                out.to_str().unwrap(),
            ],
        );
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{scene} {set}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains(key) && stderr.contains("10^7"), "{stderr}");
        assert!(!out.exists());
    }
}

/// A small oedometer of `count` spheres run with a checkpoint every 50 steps: its folder and
/// the checkpoint it wrote at step 50.
fn checkpoint_at_step_50(count: usize) -> (tempfile::TempDir, std::path::PathBuf) {
    let (dir, file) = common::scene_file(&common::small_oedometer(count, "\"contact\"", 0.002));
    let whole = dir.path().join("whole");
    let o = common::fractum(
        dir.path(),
        &[
            "run",
            file.to_str().unwrap(),
            "--out",
            whole.to_str().unwrap(),
            "--quiet",
            "--checkpoint-every",
            "50",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (dir, whole.join("checkpoints/step_000000050.fcp"))
}

/// a checkpoint carries a format version and a checksum; damaged
/// copies (single bit flips spread over the file, truncations) are refused by `resume` with one
/// sentence naming the file, exit code 2 and no output folder, never resumed, never a panic.
#[test]
fn damaged_checkpoints_are_refused() {
    let (dir, good) = checkpoint_at_step_50(300);
    let bytes = std::fs::read(&good).unwrap();
    let damaged = dir.path().join("damaged.fcp");
    let out = dir.path().join("resumed");
    let mut tries: Vec<Vec<u8>> = (0..60)
        .map(|k| {
            let mut b = bytes.clone();
            b[(k * 7919 + 11) % bytes.len()] ^= 1 << (k % 8);
            b
        })
        .collect();
    tries.extend([0, 8, bytes.len() / 2, bytes.len() - 1].map(|cut| bytes[..cut].to_vec()));
    for (k, b) in tries.iter().enumerate() {
        std::fs::write(&damaged, b).unwrap();
        let o = common::resume_output(dir.path(), &damaged, &out);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "try {k}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "try {k}: {stderr}");
        assert!(
            stderr.contains(damaged.to_str().unwrap())
                && (stderr.contains("not a usable checkpoint")
                    || stderr.contains("not a Fractum checkpoint")),
            "try {k}: {stderr}"
        );
        assert!(!out.exists(), "try {k}: no output folder");
    }
    // The undamaged copy resumes.
    std::fs::write(&damaged, &bytes).unwrap();
    common::resume(dir.path(), &damaged, &out);
}

#[test]
fn a_packing_that_jams_names_the_key_to_change() {
    // 50 spheres in a box, with their loose layer along the walls, do not reach 0.64 (random
    // close packing in bulk).
    fails(
        &replace(&base(), "solid_fraction = 0.5", "solid_fraction = 0.64"),
        &[],
        &[
            "sample.solid_fraction = 0.640 could not be reached",
            "jammed at about 0.",
        ],
    );
    // dlsm places its Voronoi seeds on a packing at solid fraction 0.5, which 20 spheres in the
    // tensile bar's box do not reach: the message names the element count, not a fraction the
    // user never set.
    let dlsm = std::fs::read_to_string(common::repo().join("scenes/dlsm_tensile.toml")).unwrap();
    fails(
        &replace(&dlsm, "elements = 11000", "elements = 20"),
        &[],
        &[
            "sample.elements = 20 cannot seed the Voronoi cells",
            "below the 0.5 the seeds are placed at",
            "ask for more elements",
        ],
    );
}

#[test]
fn a_projectile_speed_at_or_above_the_speed_of_light_is_refused() {
    // A projectile at 1e308 m/s has a finite velocity but an infinite kinetic energy: the run
    // wrote `inf` into series.csv and ended with exit code 0.
    let b = std::fs::read_to_string(common::repo().join("scenes/impact_block.toml")).unwrap();
    for speed in ["1e308", "299792458"] {
        fails(
            &b,
            &["--set", &format!("loading.speed={speed}")],
            &["loading.speed", "(0, 299792458)", "m/s", "speed of light"],
        );
    }
}

#[test]
fn a_non_finite_series_value_stops_the_run_instead_of_being_written() {
    // A state with finite velocities and a kinetic energy that is not must not reach
    // series.csv as `inf` or NaN with exit code 0. (An explosion of 1e308 J did this; its
    // energy is now refused at build, see explosion_energy_is_bounded_as_the_projectile_speed_is:
    // a packing file's velocity of 1e200 m/s still gets here.)
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("fast.data");
    std::fs::write(
        &data,
        "LAMMPS data\n\n2 atoms\n1 atom types\n\n0 2e-3 xlo xhi\n0 2e-3 ylo yhi\n0 2e-3 zlo zhi\n\n\
         Atoms # sphere\n\n1 1 6e-4 2650 5e-4 5e-4 5e-4\n2 1 6e-4 2650 1.5e-3 1.5e-3 1.5e-3\n\n\
         Velocities\n\n1 1e200 0 0 0 0 0\n2 0 0 0 0 0 0\n",
    )
    .unwrap();
    let text = base();
    let (head, rest) = text.split_once("[sample]").unwrap();
    let tail = &rest[rest.find("[loading]").unwrap()..];
    let (_keep, scene) = common::scene_file(&format!(
        "{head}[sample]\nkind = \"lammps_data\"\nfile = \"{}\"\n{tail}",
        data.display()
    ));
    let out = dir.path().join("out");
    let o = common::fractum(
        dir.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ],
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("kinetic_energy")
            && stderr.contains("step 0")
            && stderr.contains("energies"),
        "{stderr}"
    );
}

#[test]
fn export_of_a_dlsm_or_beam2d_scene_says_export_takes_granular_scenes() {
    // Export read any scene as a granular one and refused the other model's keys (`loading.kind
    // = "tension" is not allowed`, `unknown key fragments`), never saying what was wrong.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for (scene, kind) in [
        ("dlsm_tensile.toml", "dlsm"),
        ("impact_block.toml", "beam2d"),
        ("explosion_disc.toml", "beam2d"),
    ] {
        for format in ["lammps", "yade"] {
            let file = common::repo().join("scenes").join(scene);
            let o = common::fractum(
                dir.path(),
                &[
                    "export",
                    format,
                    file.to_str().unwrap(),
                    out.to_str().unwrap(),
                ],
            );
            let stderr = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{scene} {format}: {stderr}");
            assert_eq!(stderr.lines().count(), 1, "{stderr}");
            assert!(
                stderr.contains(file.to_str().unwrap())
                    && stderr.contains(&format!("model.kind = \"{kind}\""))
                    && stderr.contains("granular scenes only"),
                "{scene} {format}: {stderr}"
            );
            assert!(!out.exists());
        }
    }
}

#[test]
fn a_young_modulus_that_gives_a_zero_automatic_step_is_named() {
    // dlsm with material.young = 1e308: the automatic step underflowed to 0 s and the message
    // said "time.dt = 0.0000e0 s needs inf steps", not which key to change.
    let (code, stderr, out) = common::run_scene_failing(
        "scenes/dlsm_tensile.toml",
        &["--set", "material.young=1e308"],
    );
    assert_eq!(code, Some(2), "{stderr}");
    assert!(!out);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("material.young (set with --set) = 1e308 Pa is too stiff")
            && stderr.contains("lower material.young")
            && !stderr.contains("inf steps"),
        "{stderr}"
    );
}

#[test]
fn an_explosion_disc_is_refused_by_its_printed_bound_and_builds_above_it() {
    // Discs of 0.033-0.036 m (3.1-3.3 spacings) passed the printed range "more than three
    // lattice spacings" and were then refused at build by a sentence naming neither key nor
    // bound ("its centre polygon lies on the outline"), depending on the seed.
    let b = beam2d_base();
    for d in ["0.033", "0.034", "0.035", "0.036", "0.129"] {
        fails(
            &b,
            &["--set", &format!("sample.diameter={d}")],
            &["sample.diameter", "[0.1296, ∞) m", "12 lattice spacings"],
        );
    }
    for seed in 1..=5 {
        let (dir, file) = common::scene_file(&b);
        let o = common::fractum(
            dir.path(),
            &[
                "run",
                file.to_str().unwrap(),
                "--set",
                "sample.diameter=0.1296",
                "--set",
                &format!("seed={seed}"),
                "--set",
                "loading.end_time=1e-6",
                "--out",
                dir.path().join("out").to_str().unwrap(),
                "--quiet",
            ],
        );
        assert!(
            o.status.success(),
            "seed {seed}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

/// The counting fracture keys are refused at the library's bounds (`fracture::CRITICAL_CONTACTS`
/// and `SPRINGS`), the bounds the kernels and the LAMMPS plugin's arguments take from there
/// too (their own tests check those layers).
#[test]
fn fracture_counts_are_refused_at_the_librarys_bounds() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/crush_grain.toml"),
    )
    .unwrap();
    let (c, s) = (
        fractum::fracture::CRITICAL_CONTACTS,
        fractum::fracture::SPRINGS,
    );
    for (key, (lo, hi)) in [("fracture.critical_contacts", c), ("fracture.springs", s)] {
        let range = format!("[{lo}, {hi}]");
        for bad in [lo - 1, hi + 1] {
            let set = format!("{key}={bad}");
            fails(&text, &["--set", &set], &[key, &range]);
        }
    }
}

/// The dlsm strain measure and the tension grips: a wrong value, or a grip on a loading that
/// has none, is refused at build with one line naming the key.
#[test]
fn dlsm_strain_measure_and_grip_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for (scene, set, key) in [
        (
            "dlsm_tensile.toml",
            "material.strain_measure=\"cubic\"",
            "strain_measure",
        ),
        ("dlsm_tensile.toml", "loading.grip=\"glued\"", "grip"),
        ("brazilian.toml", "loading.grip=\"clamped\"", "loading.grip"),
    ] {
        let file = common::repo().join("scenes").join(scene);
        let o = common::fractum(
            dir.path(),
            &[
                "run",
                file.to_str().unwrap(),
                "--set",
                set,
                "--out",
                out.to_str().unwrap(),
            ],
        );
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{scene} {set}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains(key), "{stderr}");
        assert!(!out.exists());
    }
}

#[test]
fn an_automatic_step_longer_than_half_the_loading_is_refused_naming_the_material() {
    // A Young's modulus of 1e3 Pa gave a reduced shpb_sand an automatic step of several times
    // its loading: one step to 7x the end strain, exit code 0, a 72% energy error, and advice
    // naming time.safety. Under time.dt = "auto" the modulus is at fault.
    let (code, stderr, out) = common::run_scene_failing(
        "scenes/shpb_sand.toml",
        &[
            "--set",
            "material.young=1e3",
            "--set",
            "loading.end_strain=0.05",
        ],
    );
    assert_eq!((code, out), (Some(2), false), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("shpb_sand.toml: material.young (set with --set) = 1e3 Pa")
            && stderr.contains("allowed: material.young >= ")
            && stderr.contains("fewer than 2"),
        "{stderr}"
    );
    assert!(!stderr.contains("time.safety ("), "{stderr}");
}

#[test]
fn a_scene_or_checkpoint_that_is_not_a_regular_file_is_refused() {
    // A FIFO given as a scene blocked for ever; /dev/zero was read until memory ran out.
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("scene.toml");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let out = dir.path().join("out");
    for (command, path) in [
        ("run", fifo.as_path()),
        ("run", Path::new("/dev/zero")),
        ("resume", Path::new("/dev/zero")),
        ("resume", fifo.as_path()),
        ("run", dir.path()),
    ] {
        let o = common::fractum(
            dir.path(),
            &[
                command,
                path.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--quiet",
            ],
        );
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{command} {path:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.contains(path.to_str().unwrap())
                && (stderr.contains("not a regular file") || stderr.contains("is a folder")),
            "{stderr}"
        );
        assert!(!out.exists());
    }
}

#[test]
fn a_huge_value_is_not_echoed_whole() {
    // A 10 MB value came back whole in the error message.
    let value = "g".repeat(10_000_000);
    let text = format!("{}\n[model]\nkind = \"{value}\"\n", base());
    let (line, _) = refused(&text, &[]);
    assert!(line.len() < 1000, "{} bytes", line.len());
    assert!(
        line.contains("model.kind") && line.contains('…') && line.contains("granular"),
        "{line}"
    );
}

#[test]
fn a_resealed_checkpoint_with_a_nan_inside_is_refused_not_a_panic() {
    // A checkpoint whose checksums were made again over a NaN position passed the seal and
    // panicked in the neighbour search (index out of bounds) at the first step.
    let (dir, good) = checkpoint_at_step_50(60);
    let (run, _) = fractum::models::resume(&good, 1).unwrap();
    let x = run.positions()[0].x.to_le_bytes();
    let mut bytes = std::fs::read(&good).unwrap();
    let at = bytes
        .windows(8)
        .position(|w| w == x)
        .expect("the first body's x in the checkpoint");
    bytes[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    // Seal again: the run's state (magic FRACTUMS) inside, then the whole file.
    let reseal = |b: &mut [u8]| {
        let end = b.len() - 8;
        let sum = fractum::output::sealed::checksum(&b[..end]);
        b[end..].copy_from_slice(&sum.to_le_bytes());
    };
    let inner = bytes
        .windows(8)
        .position(|w| w == b"FRACTUMS")
        .expect("the run's state");
    let len = u64::from_le_bytes(bytes[inner + 12..inner + 20].try_into().unwrap()) as usize;
    reseal(&mut bytes[inner..inner + 20 + len + 8]);
    reseal(&mut bytes);
    let forged = dir.path().join("forged.fcp");
    std::fs::write(&forged, &bytes).unwrap();
    let out = dir.path().join("resumed");
    let o = common::resume_output(dir.path(), &forged, &out);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(forged.to_str().unwrap())
            && stderr.contains("body 0")
            && stderr.contains("non-finite"),
        "{stderr}"
    );
    assert!(!out.exists());
}

#[test]
fn compaction_pressure_of_any_sample_kind_names_its_range() {
    // `pressure` compacts lattices and files too; there its range went unchecked.
    let file = common::repo().join("scenes").join("shpb_hcp.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    fails(
        &text,
        &["--set", "sample.pressure=-1e6"],
        &["sample.pressure", "(0, ∞)"],
    );
    fails(
        &text,
        &[
            "--set",
            "sample.pressure=1e6",
            "--set",
            "sample.compaction_friction=-0.1",
        ],
        &["sample.compaction_friction", "[0, ∞)"],
    );
}

/// An ellipsoid assembly scene over the header and `rows` (written to a file of its own; the
/// scene names it by its absolute path). Returns the scene text and the folder that keeps the
/// file.
fn assembly_scene(rows: &[String]) -> (String, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("grains.csv");
    let header = fractum::sample::ELLIPSOID_COLUMNS.join(",");
    std::fs::write(&file, format!("{header}\n{}\n", rows.join("\n"))).unwrap();
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
file = "{}"
[loading]
kind = "none"
end_time = 1e-7
"#,
        file.display()
    );
    (text, dir)
}

/// The rows of the shipped Mason sand assembly (without its header).
fn mason_rows() -> Vec<String> {
    let text = std::fs::read_to_string(
        common::repo().join("data/mason_sand_shpb/grains_mason_sand_ellipsoids.csv"),
    )
    .unwrap();
    text.lines().skip(1).map(str::to_string).collect()
}

#[test]
fn assembly_grains_that_overlap_are_refused_naming_both_lines() {
    // Two grains at one centre stopped the run at its first step with advice to lower
    // time.safety; a file of repeated rows ran out of memory building its pair list.
    let rows = mason_rows();
    let mut two = rows[..3].to_vec();
    two.push(rows[1].clone());
    let (text, _keep) = assembly_scene(&two);
    fails(&text, &[], &["sample.file", "lines 3 and 5", "overlap"]);
    let twice: Vec<String> = rows.iter().chain(rows.iter()).cloned().collect();
    let (text, _keep) = assembly_scene(&twice);
    fails(
        &text,
        &[],
        &["sample.file", &format!("lines 2 and {}", rows.len() + 2)],
    );
}

#[test]
fn an_assembly_grain_far_from_the_others_is_refused_naming_its_line() {
    // One centre at 1 m (or 1e300 m) among sub-millimetre grains made the box that large, and
    // the run went through it to exit 0.
    for far in ["1.0", "1e300"] {
        let rows = mason_rows();
        let mut some = rows[..3].to_vec();
        let mut cols: Vec<String> = rows[3].split(',').map(str::to_string).collect();
        cols[4] = far.to_string();
        some.push(cols.join(","));
        let (text, _keep) = assembly_scene(&some);
        fails(
            &text,
            &[],
            &["sample.file", "line 5", "solid fraction", "0.01"],
        );
    }
}

#[test]
fn needle_and_flake_grains_are_refused_naming_the_line_and_the_range() {
    // A grain file of 5e-4 × 1e-6 m needles planned hundreds of thousands of grains and showed
    // nothing for minutes; the generated grains' aspect_ratio_max is bounded, files were not.
    let rows = mason_rows();
    let mut cols: Vec<String> = rows[1].split(',').map(str::to_string).collect();
    cols[1] = "5e-4".into();
    cols[2] = "1e-6".into();
    cols[3] = "1e-6".into();
    let some = vec![rows[0].clone(), cols.join(",")];
    let (text, _keep) = assembly_scene(&some);
    fails(&text, &[], &["sample.file", "line 3", "[1, 10]"]);
    // The same file as the grain file of a compacted random sample.
    let file = text
        .split("file = \"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap();
    let scene = std::fs::read_to_string(common::repo().join("scenes/mason_sand_shpb.toml"))
        .unwrap()
        .replace(
            "../data/mason_sand_shpb/grains_mason_sand_ellipsoids.csv",
            file,
        );
    fails(&scene, &[], &["sample.grain_file", "line 3", "[1, 10]"]);
}

#[test]
fn a_grain_file_with_a_byte_order_mark_reads_as_without() {
    // Editors on Windows start a UTF-8 file with a byte-order mark; it was taken for part of
    // the header ("expected the header"). A bad row after it is named by its own line.
    let rows = mason_rows();
    let mut cols: Vec<String> = rows[1].split(',').map(str::to_string).collect();
    cols[1] = "-1e-4".into();
    let (text, keep) = assembly_scene(&[rows[0].clone(), cols.join(",")]);
    let file = keep.path().join("grains.csv");
    let csv = std::fs::read_to_string(&file).unwrap();
    std::fs::write(&file, format!("\u{feff}{csv}")).unwrap();
    fails(&text, &[], &["sample.file", "line 3", "semi-axis"]);
    let (text, keep) = assembly_scene(&rows);
    let file = keep.path().join("grains.csv");
    let csv = std::fs::read_to_string(&file).unwrap();
    std::fs::write(&file, format!("\u{feff}{csv}")).unwrap();
    let scene = fractum::Scene::from_toml(&text, "assembly", Path::new("."), &[]).unwrap();
    let sample = fractum::models::granular::sample::from_scene(&scene, &mut |_| {}).unwrap();
    assert_eq!(sample.bodies.len(), rows.len());
}

fn shipped(scene: &str) -> String {
    std::fs::read_to_string(common::repo().join("scenes").join(scene)).unwrap()
}

#[test]
fn explosion_energy_is_bounded_as_the_projectile_speed_is() {
    // 1e300 J ran to exit 0 with pieces at 1e151 m/s; the projectile's speed was already held
    // below the speed of light.
    for energy in ["1e300", "1.7e308"] {
        let (line, _) = refused(
            &shipped("explosion_disc.toml"),
            &[
                "--set",
                "sample.diameter=0.15",
                "--set",
                "loading.explosive=\"kept\"",
                "--set",
                &format!("loading.energy={energy}"),
            ],
        );
        assert!(
            line.contains("loading.energy")
                && line.contains("allowed range (0, ")
                && line.contains("faster than light"),
            "{line}"
        );
        // The bound it names is one the scene runs under.
        let top: f64 = line.split("allowed range (0, ").nth(1).unwrap()[..line
            .split("allowed range (0, ")
            .nth(1)
            .unwrap()
            .find(')')
            .unwrap()]
            .parse()
            .unwrap();
        assert!(top > 1e3 && top < 1e30, "{line}");
    }
}

#[test]
fn sample_keys_that_do_not_apply_are_refused() {
    // They were ignored without a word.
    let text = shipped("oedometer_spheres.toml").replace("pressure = 1e5", "# no pressure");
    fails(
        &text,
        &[],
        &[
            "sample.compaction_friction",
            "without sample.pressure",
            "remove it",
        ],
    );
    let rows = mason_rows();
    let (assembly, _keep) = assembly_scene(&rows[..50]);
    for (key, value) in [
        ("sample.box", "[3e-3,3e-3,3e-3]"),
        ("sample.solid_fraction", "0.5"),
        ("sample.count", "10"),
    ] {
        fails(
            &assembly,
            &["--set", &format!("{key}={value}")],
            &[key, "sample.kind = \"ellipsoid_assembly\"", "remove it"],
        );
    }
    let hcp = shipped("shpb_hcp.toml");
    fails(
        &hcp,
        &["--set", "sample.box=[3e-3,3e-3,3e-3]"],
        &["sample.box", "sample.kind = \"hcp\"", "remove it"],
    );
}

#[test]
fn beam_breaking_rule_without_beam_breaking_is_refused() {
    fails(
        &shipped("beam2d_moduli.toml"),
        &["--set", "material.beam_breaking_rule=\"squared\""],
        &[
            "material.beam_breaking_rule",
            "without the \"beam_breaking\" effect",
        ],
    );
}

/// `fractum resume CHECKPOINT --out OUT --quiet`, killed (and the test failed) if it is still
/// running after `seconds`: a forged clock used to run without an end.
fn resume_within(cwd: &Path, checkpoint: &Path, out: &Path, seconds: u64) -> std::process::Output {
    let mut child = std::process::Command::new(common::fractum_bin())
        .args([
            "resume",
            checkpoint.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .current_dir(cwd)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs() >= seconds {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{}: still resuming after {seconds} s", checkpoint.display());
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn forged_checkpoint_clocks_are_checked_against_the_limits() {
    // Re-sealed checkpoints (their checksums made again) whose clocks were changed:
    // end_step = 2^64 - 1 resumed without the 1e9-step limit, step > end_step printed a
    // wrapped step count, and dt = 1e-300 exited 0 without advancing.
    let (dir, good) = checkpoint_at_step_50(60);
    let saved = fractum::output::checkpoint::load(&good).unwrap();
    type Forge = fn(&mut fractum::run::Clock);
    let cases: [(&str, Forge, &str); 4] = [
        (
            "end_step",
            |c| c.end_step = u64::MAX,
            "ends at step 18446744073709551615",
        ),
        ("past", |c| c.step = c.end_step + 5, "past the run's end"),
        ("dt", |c| c.dt = 1e-300, "more than the limit of 1e9 steps"),
        (
            "far",
            |c| c.end_step = c.step + 2_000_000_000,
            "more than the limit",
        ),
    ];
    for (name, forge, said) in cases {
        let mut sim =
            fractum::models::granular::Simulation::restore(saved.scene.clone(), &saved.state, 1)
                .unwrap();
        forge(&mut sim.clock);
        let forged = dir.path().join(format!("{name}.fcp"));
        std::fs::write(
            &forged,
            fractum::output::checkpoint::encode(&sim, &saved.frames),
        )
        .unwrap();
        let out = dir.path().join(format!("out_{name}"));
        let o = resume_within(dir.path(), &forged, &out, 60);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.contains(forged.to_str().unwrap())
                && stderr.contains("clock")
                && stderr.contains(said),
            "{name}: {stderr}"
        );
        assert!(!out.exists());
    }
    // The unforged state resumes.
    let o = resume_within(dir.path(), &good, &dir.path().join("out_good"), 60);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Runs a shipped scene with overrides that must be refused as bad input (exit 2, one line, no
/// folder); returns the line.
fn refused_shipped(scene: &str, extra: &[&str]) -> String {
    let (code, stderr, out) = common::run_scene_failing(scene, extra);
    assert_eq!((code, out), (Some(2), false), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    stderr.trim().to_string()
}

#[test]
fn messages_name_the_key_at_fault_with_a_range_that_can_be_met() {
    // "allowed: material.young >= inf Pa"
    let line = refused_shipped("scenes/shpb_sand.toml", &["--set", "material.young=5e-324"]);
    assert!(
        line.contains("material.young (set with --set) = 5e-324 Pa") && !line.contains("inf Pa"),
        "{line}"
    );
    // "set time.dt to at most 0.000e0 s"
    let line = refused_shipped(
        "scenes/beam2d_moduli.toml",
        &["--set", "material.density=1e-300"],
    );
    assert!(
        line.contains("material.density (set with --set) = 1e-300") && !line.contains("0.000e0"),
        "{line}"
    );
    // A DLSM bar 1e9 m long, and a strain rate of 1e308/s, blamed material.young.
    for (scene, set) in [
        ("scenes/dlsm_tensile.toml", "sample.length=1e9"),
        ("scenes/shpb_sand.toml", "loading.strain_rate=1e308"),
    ] {
        let line = refused_shipped(scene, &["--set", set]);
        assert!(
            line.contains(": time.dt = \"auto\" gives a step of")
                && line.contains("the loading is too short or the grains or elements too large")
                && !line.contains("material.young >="),
            "{line}"
        );
    }
    // A named choice given as a number: "expected string only, found unit variant".
    let line = refused_shipped("scenes/shpb_sand.toml", &["--set", "sample.packing=1"]);
    assert!(
        line.contains("`sample.packing` (given with --set) has the wrong type: expected a string")
            && !line.contains("unit variant"),
        "{line}"
    );
    // One grain at a solid fraction: the box is scaled to the count, so the count is at fault,
    // not "sample.box is too small".
    let line = refused_shipped("scenes/mason_sand_shpb.toml", &["--set", "sample.count=1"]);
    assert!(
        line.contains("sample.count (set with --set) = 1 grains at sample.solid_fraction = 0.574")
            && line.contains("allowed: sample.count >= about"),
        "{line}"
    );
    // The same for spheres packed geometrically (the main job's sand), which still blamed the
    // box.
    let line = refused_shipped("scenes/shpb_sand.toml", &["--set", "sample.count=1"]);
    assert!(
        line.contains("sample.count (set with --set) = 1 grains at sample.solid_fraction = 0.55")
            && line.contains("allowed: sample.count >= about"),
        "{line}"
    );
}

#[test]
fn a_packing_file_body_outside_its_box_is_refused_naming_it() {
    // A centre far outside the box ran on, out of the walls' reach.
    let dir = tempfile::tempdir().unwrap();
    let packing = dir.path().join("p.txt");
    let scene = |box_comment: &str, extra: &str| {
        std::fs::write(
            &packing,
            format!("{box_comment}5e-4 5e-4 5e-4 1e-4\n1.0 5e-4 5e-4 1e-4\n"),
        )
        .unwrap();
        let text = base();
        let (head, rest) = text.split_once("[sample]").unwrap();
        let tail = &rest[rest.find("[loading]").unwrap()..];
        format!(
            "{head}[sample]\nkind = \"text\"\nfile = \"{}\"\n{extra}{tail}",
            packing.display()
        )
    };
    fails(
        &scene("# box 0 0 0 1e-3 1e-3 1e-3\n", ""),
        &[],
        &[
            "sample.file",
            "the file's box",
            "does not hold body 2",
            "centre (1e0",
        ],
    );
    fails(
        &scene("", "box = [1e-3, 1e-3, 1e-3]\n"),
        &[],
        &["sample.box", "does not hold body 2"],
    );
}

#[test]
fn sleeves_that_do_not_fit_their_sample_are_refused_naming_the_key() {
    let base = base();
    // The sleeve is the cylinder inscribed in the box's x-y section: x and y must be equal.
    let t = replace(&base, "[loading]", "[walls]\nsleeve = true\n[loading]");
    fails(
        &replace(&t, "box = [3e-3, 3e-3, 3e-3]", "box = [3e-3, 2e-3, 3e-3]"),
        &[],
        &["sample.box", "x and y edges must be equal"],
    );
    // Its friction without it.
    fails(
        &replace(
            &base,
            "[loading]",
            "[walls]\nsleeve_friction = 0.3\n[loading]",
        ),
        &[],
        &["walls.sleeve_friction", "walls.sleeve = true only"],
    );
    fails(
        &replace(
            &t,
            "[walls]\nsleeve = true",
            "[walls]\nsleeve = true\nsleeve_friction = -1",
        ),
        &[],
        &["walls.sleeve_friction", "-1"],
    );
    // Compaction to a pressure moves the side faces the sleeve replaces.
    fails(
        &replace(
            &t,
            "solid_fraction = 0.5",
            "solid_fraction = 0.5\npressure = 1e5",
        ),
        &[],
        &["sample.pressure", "walls.sleeve = true"],
    );
    // Grains that are not placed in it or read into it.
    fails(
        &replace(
            &std::fs::read_to_string(common::repo().join("scenes/crush_grain.toml")).unwrap(),
            "[loading]",
            "[walls]\nsleeve = true\n[loading]",
        ),
        &[],
        &["walls.sleeve", "sample.kind = \"single\""],
    );
}

#[test]
fn a_grain_outside_the_sleeve_or_too_large_for_it_is_refused_at_build() {
    let text = r#"
name = "outside"
effects = ["contact"]
[material]
young = 60e9
poisson = 0.17
density = 2650.0
[sample]
kind = "text"
file = "packing.txt"
box = [2e-3, 2e-3, 2e-3]
[walls]
sleeve = true
[loading]
kind = "none"
end_time = 1e-6
"#;
    // Two spheres in a 2 mm box: the second in a corner, outside the inscribed cylinder;
    // then one sphere longer than the sleeve is wide.
    for (packing, wanted) in [
        (
            "1.0e-3 1.0e-3 1.0e-3 0.2e-3\n1.8e-3 1.8e-3 1.0e-3 0.15e-3\n",
            ["body 2", "outside the sleeve"],
        ),
        (
            "1.0e-3 1.0e-3 1.0e-3 1.05e-3\n",
            ["wider than the largest grain", "2.100e-3 m"],
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("packing.txt"), packing).unwrap();
        let file = dir.path().join("scene.toml");
        std::fs::write(&file, text).unwrap();
        let out = dir.path().join("out");
        let o = common::fractum(
            dir.path(),
            &[
                "run",
                file.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--quiet",
            ],
        );
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        for w in ["walls.sleeve"].iter().chain(wanted.iter()) {
            assert!(stderr.contains(w), "mentions `{w}`: {stderr}");
        }
        assert!(!out.exists());
    }
}
