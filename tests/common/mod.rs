//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use fractum::Scene;
use fractum::sample::{Sample, SampleInfo};
use fractum::state::{Bodies, Walls};

/// Path of the built `fractum` binary.
pub fn fractum_bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_fractum"))
}

/// Runs the binary with `args` in `cwd`.
pub fn fractum(cwd: &Path, args: &[&str]) -> Output {
    Command::new(fractum_bin())
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("fractum runs")
}

/// The repository root (where scenes/ lives).
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A scene of the given effects with E = 60 GPa, ν = 0.17, ρ = 2650 and no sample of its own
/// (tests place bodies themselves); it runs for `end_time` with a fixed `dt`.
pub fn scene(effects: &str, extra: &str, end_time: f64, dt: f64) -> Scene {
    let text = format!(
        r#"
name = "test"
effects = [{effects}]
[material]
young = 60e9
poisson = 0.17
density = 2650.0
friction = 0.5
restitution = 0.5
[sample]
kind = "text"
file = "unused.txt"
[loading]
kind = "none"
end_time = {end_time:e}
[time]
dt = {dt:e}
[output]
every = 1
{extra}
"#
    );
    Scene::from_toml(&text, "test", Path::new("."), &[]).expect("test scene is valid")
}

pub fn sample(bodies: Bodies, walls: Walls) -> Sample {
    let count = bodies.len();
    Sample {
        bodies,
        walls,
        info: SampleInfo {
            kind: "test".into(),
            count,
            ..Default::default()
        },
    }
}

/// Writes `text` to a fresh scene file in a temporary folder; returns (folder, file).
pub fn scene_file(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("scene.toml");
    std::fs::write(&file, text).unwrap();
    (dir, file)
}

/// `fractum resume CHECKPOINT --out OUT --quiet` in `cwd`; panics with its stderr on failure.
pub fn resume(cwd: &Path, checkpoint: &Path, out: &Path) {
    let o = resume_output(cwd, checkpoint, out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `fractum resume CHECKPOINT --out OUT --quiet` in `cwd`, as it ended.
pub fn resume_output(cwd: &Path, checkpoint: &Path, out: &Path) -> Output {
    fractum(
        cwd,
        &[
            "resume",
            checkpoint.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ],
    )
}

/// A result file's text without the summary's `wall_seconds` line, the one part that is timing.
pub fn without_wall_seconds(p: &Path) -> String {
    std::fs::read_to_string(p)
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
        .lines()
        .filter(|l| !l.contains("\"wall_seconds\""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// A small random oedometer scene: `count` spheres at solid fraction 0.5 (small walled boxes
/// cannot be packed much denser without compaction), compressed to `end_strain` at 200/s.
pub fn small_oedometer(count: usize, effects: &str, end_strain: f64) -> String {
    format!(
        r#"
name = "small_oedometer"
seed = 5
effects = [{effects}]
[material]
young = 60e9
poisson = 0.17
density = 2650.0
friction = 0.5
restitution = 0.5
[sample]
kind = "random"
count = {count}
radius_mean = 0.3e-3
radius_sd = 0.05e-3
radius_min = 0.15e-3
radius_max = 0.45e-3
box = [3e-3, 3e-3, 3e-3]
solid_fraction = 0.5
[loading]
kind = "oedometer"
strain_rate = 200.0
end_strain = {end_strain}
[time]
safety = 0.25
[output]
every = 50
vtk = 500
"#
    )
}

/// `fractum run` of a shipped scene (path relative to the repository) with extra CLI
/// arguments, into `out` under a fresh folder: the folder's owner and the process output.
fn run_shipped(scene: &str, extra: &[&str]) -> (tempfile::TempDir, Output) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let path = repo().join(scene);
    let mut args = vec![
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let o = fractum(dir.path(), &args);
    (dir, o)
}

/// Runs a shipped scene that must fail: its exit code, its stderr, and whether the output
/// folder exists.
pub fn run_scene_failing(scene: &str, extra: &[&str]) -> (Option<i32>, String, bool) {
    let (dir, o) = run_shipped(scene, extra);
    let stderr = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(!o.status.success(), "{scene} {extra:?} succeeded");
    (o.status.code(), stderr, dir.path().join("out").exists())
}

/// Runs a shipped scene (path relative to the repository) with extra CLI arguments; returns
/// the output folder's owner, summary.json and series.csv.
pub fn run_scene(scene: &str, extra: &[&str]) -> (tempfile::TempDir, serde_json::Value, String) {
    let (dir, o) = run_shipped(scene, extra);
    let out = dir.path().join("out");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    (dir, summary, series)
}

/// A column of series.csv by name.
pub fn column(series: &str, name: &str) -> Vec<f64> {
    let mut lines = series.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

/// No NaN or infinity anywhere in the series, and the energy account closes: the platen work
/// equals the kinetic and elastic energy, what contacts dissipated, what the springs spent and
/// what the splits released, to within `tolerance` of the work.
pub fn assert_stable_and_balanced(s: &serde_json::Value, series: &str, tolerance: f64) {
    for line in series.lines().skip(1) {
        assert!(
            line.split(',')
                .all(|v| v.parse::<f64>().is_ok_and(f64::is_finite)),
            "a series row is not finite: {line}"
        );
    }
    let e = &s["energy"];
    for key in [
        "kinetic",
        "elastic",
        "boundary_work",
        "dissipated",
        "fracture",
        "split_change",
        "balance_error",
    ] {
        assert!(
            e[key].as_f64().is_some_and(f64::is_finite),
            "energy.{key}: {e}"
        );
    }
    let work = e["boundary_work"].as_f64().unwrap();
    assert!(work > 0.0);
    let relative = e["balance_error_relative"].as_f64().unwrap();
    assert!(
        relative.abs() < tolerance,
        "energy balance off by {relative}: {e}"
    );
    // The same numbers, summed here: what the summary calls the error is what is missing.
    // A jammed sample starts with the elastic energy it carries (summary key energy.initial).
    let sum = -e["initial"].as_f64().unwrap()
        + e["kinetic"].as_f64().unwrap()
        + e["gravity_potential"].as_f64().unwrap()
        + e["elastic"].as_f64().unwrap()
        + e["dissipated"].as_f64().unwrap()
        + e["fracture"].as_f64().unwrap()
        - e["split_change"].as_f64().unwrap();
    assert!(((sum - work) / work - relative).abs() < 1e-9, "{e}");
}
