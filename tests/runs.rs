//! Whole runs through the CLI: reproducibility, thread-count independence, checkpoint and
//! resume, effects that are never built, outputs that ParaView reads.

mod common;

use std::fs;
use std::path::Path;

use fractum::models::granular::Simulation;

fn run(dir: &Path, scene: &Path, out: &str, extra: &[&str]) {
    let out = dir.join(out);
    let mut args = vec![
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let o = common::fractum(dir, &args);
    assert!(
        o.status.success(),
        "run failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(o.stderr.is_empty(), "--quiet prints nothing");
}

fn read(p: &Path) -> Vec<u8> {
    fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// A result file without the summary's `wall_seconds` line, the one part that is timing
/// (summary.json must have exactly one).
fn read_results(p: &Path) -> String {
    if p.ends_with("summary.json") {
        let text = String::from_utf8(read(p)).unwrap();
        let timed = text
            .lines()
            .filter(|l| l.contains("\"wall_seconds\""))
            .count();
        assert_eq!(timed, 1, "summary.json has one wall_seconds line");
    }
    common::without_wall_seconds(p)
}

#[test]
fn same_scene_seed_and_thread_count_give_byte_identical_results() {
    // 3200 bodies: enough for two threads to take the parallel pair loop.
    let text = common::small_oedometer(3200, "\"contact\", \"damping\", \"friction\"", 0.004)
        .replace("box = [3e-3, 3e-3, 3e-3]", "box = [6e-3, 6e-3, 6e-3]");
    let (dir, scene) = common::scene_file(&text);
    for (a, b, threads) in [("a2", "b2", "2"), ("a1", "b1", "1")] {
        run(dir.path(), &scene, a, &["--threads", threads]);
        run(dir.path(), &scene, b, &["--threads", threads]);
        for file in ["summary.json", "series.csv"] {
            assert_eq!(
                read_results(&dir.path().join(a).join(file)),
                read_results(&dir.path().join(b).join(file)),
                "{file} with {threads} thread(s)"
            );
        }
    }
    // The run did something: contacts formed and the driven face carries a stress.
    let summary: serde_json::Value =
        serde_json::from_slice(&read(&dir.path().join("a2/summary.json"))).unwrap();
    assert_eq!(summary["bodies"], 3200);
    assert!(summary["contacts_final"].as_u64().unwrap() > 1000);
    // One and two threads sum forces in different orders but agree to round-off.
    let one: serde_json::Value =
        serde_json::from_slice(&read(&dir.path().join("a1/summary.json"))).unwrap();
    let (s1, s2) = (
        one["stress_final"].as_f64().unwrap(),
        summary["stress_final"].as_f64().unwrap(),
    );
    assert!(
        (s1 / s2 - 1.0).abs() < 1e-3,
        "1 thread {s1} Pa, 2 threads {s2} Pa"
    );
}

/// The main job's scene cut to about 400 poly-ellipsoid grains that break: on two threads its
/// step runs on the worker team (pair loop, force merge, integrator, fracture check, neighbour
/// rows, finiteness check).
const TEAM_SCENE: [&str; 6] = [
    "--set",
    "sample.box=[4.5e-3, 4.5e-3, 4.5e-3]",
    "--set",
    "sample.solid_fraction=0.5",
    "--set",
    "loading.end_strain=0.02",
];

#[test]
fn breaking_grains_on_the_worker_team_repeat_and_resume_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let scene = common::repo().join("scenes/shpb_sand.toml");
    let with = |threads: &'static str, extra: &[&'static str]| {
        let mut args = TEAM_SCENE.to_vec();
        args.extend_from_slice(&["--threads", threads]);
        args.extend_from_slice(extra);
        args
    };
    run(
        dir.path(),
        &scene,
        "a",
        &with("2", &["--checkpoint-every", "600"]),
    );
    run(dir.path(), &scene, "b", &with("2", &[]));
    run(dir.path(), &scene, "one", &with("1", &[]));
    let o = common::fractum(
        dir.path(),
        &[
            "resume",
            dir.path()
                .join("a/checkpoints/step_000000600.fcp")
                .to_str()
                .unwrap(),
            "--out",
            dir.path().join("resumed").to_str().unwrap(),
            "--quiet",
            "--threads",
            "2",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for file in ["summary.json", "series.csv"] {
        let a = read_results(&dir.path().join("a").join(file));
        assert_eq!(
            a,
            read_results(&dir.path().join("b").join(file)),
            "{file}: repeat"
        );
        assert_eq!(
            a,
            read_results(&dir.path().join("resumed").join(file)),
            "{file}: resume"
        );
    }
    let summary = |name: &str| -> serde_json::Value {
        serde_json::from_slice(&read(&dir.path().join(name).join("summary.json"))).unwrap()
    };
    let two = summary("a");
    // The team took the step (373 grains at the start), and grains broke on the way.
    assert!(two["bodies"].as_u64().unwrap() >= 400, "{}", two["bodies"]);
    assert!(
        two["broken_particles"].as_u64().unwrap() > 10,
        "{}",
        two["broken_particles"]
    );
    // One and two threads sum contact forces in different orders: round-off (seen: 4e-16 at
    // the first row) that grows through the breakage (chaotic), so only the first row after
    // loading starts is compared.
    let first = |name: &str| {
        let text = fs::read_to_string(dir.path().join(name).join("series.csv")).unwrap();
        common::column(&text, "stress_driven")[1]
    };
    let (s1, s2) = (first("one"), first("a"));
    assert!(
        s1 != 0.0 && (s1 / s2 - 1.0).abs() < 1e-9,
        "1 thread {s1} Pa, 2 threads {s2} Pa"
    );
}

#[test]
fn resumed_run_gives_the_same_summary_as_an_uninterrupted_one() {
    let text = common::small_oedometer(300, "\"contact\", \"damping\", \"friction\"", 0.02);
    let (dir, scene) = common::scene_file(&text);
    run(dir.path(), &scene, "whole", &["--checkpoint-every", "700"]);
    let checkpoints: Vec<_> = fs::read_dir(dir.path().join("whole/checkpoints"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert!(
        checkpoints.len() >= 2,
        "checkpoints written: {checkpoints:?}"
    );
    let middle = dir.path().join("whole/checkpoints/step_000000700.fcp");
    let out = dir.path().join("resumed");
    common::resume(dir.path(), &middle, &out);
    assert_eq!(
        read_results(&dir.path().join("whole/summary.json")),
        read_results(&out.join("summary.json"))
    );
    assert_eq!(
        read(&dir.path().join("whole/series.csv")),
        read(&out.join("series.csv"))
    );
}

#[test]
fn scene_without_friction_never_builds_the_tangential_model() {
    let text = common::small_oedometer(200, "\"contact\", \"damping\"", 0.005);
    let scene = fractum::Scene::from_toml(&text, "t", Path::new("."), &[]).unwrap();
    let before = fractum::contact::hertz_mindlin::mindlin_models_built();
    let mut sim = Simulation::new(scene, 1, &mut |_| {}).unwrap();
    sim.advance(200).unwrap();
    assert_eq!(
        fractum::contact::hertz_mindlin::mindlin_models_built(),
        before,
        "no Mindlin model constructed"
    );
    assert_eq!(
        sim.model.pipeline.history_len(),
        0,
        "no contact history allocated"
    );
    assert!(sim.model.pipeline.contacts() > 0, "contacts are active");
    assert!(!sim.model.pipeline.describe().join(" ").contains("Mindlin"));
    // The same scene with friction builds exactly one.
    let text = common::small_oedometer(200, "\"contact\", \"damping\", \"friction\"", 0.005);
    let scene = fractum::Scene::from_toml(&text, "t", Path::new("."), &[]).unwrap();
    let mut sim = Simulation::new(scene, 1, &mut |_| {}).unwrap();
    sim.advance(200).unwrap();
    assert_eq!(
        fractum::contact::hertz_mindlin::mindlin_models_built(),
        before + 1
    );
    assert!(sim.model.pipeline.history_len() > 0);
}

#[test]
fn explain_prints_the_pipeline_and_what_is_left_out() {
    let text = common::small_oedometer(50, "\"contact\", \"damping\"", 0.005);
    let (dir, scene) = common::scene_file(&text);
    let o = common::fractum(dir.path(), &["explain", scene.to_str().unwrap()]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success());
    assert!(s.contains("1. contact: Hertz normal force"), "{s}");
    assert!(s.contains("damping: viscous, restitution 0.5"), "{s}");
    assert!(!s.contains("friction: Mindlin"), "{s}");
    assert!(
        s.contains("not built (not in `effects`): friction, gravity"),
        "{s}"
    );
}

#[test]
fn vtk_snapshots_and_index_are_well_formed() {
    let text = common::small_oedometer(120, "\"contact\"", 0.01);
    let (dir, scene) = common::scene_file(&text);
    run(dir.path(), &scene, "v", &[]);
    let out = dir.path().join("v");
    let pvd = fs::read_to_string(out.join("particles.pvd")).unwrap();
    let files: Vec<&str> = pvd
        .lines()
        .filter_map(|l| l.split("file=\"").nth(1))
        .map(|l| l.split('"').next().unwrap())
        .collect();
    assert!(files.len() >= 2, "{pvd}");
    for f in &files {
        let vtu = fs::read_to_string(out.join(f)).unwrap();
        assert!(vtu.starts_with("<?xml"));
        let n: usize = vtu
            .split("NumberOfPoints=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(n, 120);
        // Every data array holds as many tuples as the piece says.
        let radius = vtu
            .split("Name=\"radius\" format=\"ascii\">")
            .nth(1)
            .unwrap();
        let radius = radius.split("</DataArray>").next().unwrap();
        assert_eq!(radius.split_whitespace().count(), n);
        assert_eq!(
            vtu.matches("<DataArray").count(),
            vtu.matches("</DataArray>").count()
        );
        assert!(vtu.trim_end().ends_with("</VTKFile>"));
    }
    // Nothing half-written is left behind.
    for e in fs::read_dir(&out)
        .unwrap()
        .chain(fs::read_dir(out.join("vtk")).unwrap())
    {
        let name = e.unwrap().file_name().to_string_lossy().to_string();
        assert!(!name.ends_with(".tmp"), "{name}");
    }
}

#[test]
fn progress_bar_only_on_a_terminal_and_never_with_quiet() {
    let text = common::small_oedometer(300, "\"contact\"", 0.05);
    let (dir, scene) = common::scene_file(&text);
    let bin = common::fractum_bin();
    let cmd = |out: &str, quiet: &str| {
        format!(
            "{} run {} --out {} {quiet}",
            bin.display(),
            scene.display(),
            dir.path().join(out).display()
        )
    };
    // `script` (util-linux) runs the command on a pseudo-terminal.
    let on_tty = |c: String| {
        let o = std::process::Command::new("script")
            .args(["-qec", &c, "/dev/null"])
            .output()
            .expect("`script` from util-linux runs");
        assert!(o.status.success());
        String::from_utf8_lossy(&o.stdout).to_string()
    };
    let tty = on_tty(cmd("tty", ""));
    assert!(
        tty.contains(" steps") && tty.contains("eta"),
        "bar on a terminal: {tty}"
    );
    assert!(
        tty.contains("done; outputs in"),
        "says where the outputs are: {tty}"
    );
    let quiet = on_tty(cmd("quiet", "--quiet"));
    assert!(!quiet.contains("eta"), "no bar with --quiet: {quiet}");
    // Not a terminal: plain messages, no bar.
    let o = common::fractum(
        dir.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            dir.path().join("pipe").to_str().unwrap(),
        ],
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success());
    assert!(
        !stderr.contains("eta") && !stderr.contains('\r'),
        "{stderr}"
    );
    assert!(stderr.contains("done; outputs in"), "{stderr}");
}

/// A breaking-grain run (splits, cohesive springs, the energy account, size distributions)
/// resumed from a checkpoint taken after grains broke gives the uninterrupted run's results.
#[test]
fn resumed_fracture_run_continues_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let scene = common::repo().join("scenes/shpb_sand.toml");
    let whole = dir.path().join("whole");
    let args = [
        "run",
        scene.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
        "--quiet",
        "--threads",
        "1",
        "--set",
        "sample.box=[3e-3, 3e-3, 3e-3]",
        "--set",
        "sample.solid_fraction=0.5",
        "--set",
        "loading.end_strain=0.05",
        "--checkpoint-every",
        "1500",
    ];
    let o = common::fractum(dir.path(), &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_slice(&read(&whole.join("summary.json"))).unwrap();
    let mut checkpoints: Vec<_> = fs::read_dir(whole.join("checkpoints"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    checkpoints.sort();
    // The last checkpoint, late enough that grains have broken and the step was shortened.
    let last = checkpoints.last().expect("checkpoints written").clone();
    let out = dir.path().join("resumed");
    common::resume(dir.path(), &last, &out);
    assert!(
        summary["broken_particles"].as_u64().unwrap() > 0,
        "{summary}"
    );
    let first_split = summary["first_split_time"].as_f64().unwrap();
    let dt = summary["dt"].as_f64().unwrap();
    assert!(
        first_split < 3000.0 * dt,
        "a grain broke before the checkpoint: {summary}"
    );
    assert_eq!(
        read_results(&whole.join("summary.json")),
        read_results(&out.join("summary.json"))
    );
    assert_eq!(
        read(&whole.join("series.csv")),
        read(&out.join("series.csv"))
    );
    assert_eq!(read(&whole.join("psd.csv")), read(&out.join("psd.csv")));
}

#[test]
fn the_team_follows_the_state_not_how_a_caller_cuts_the_run_into_calls() {
    // 373 spheres on two threads stay off the worker team (fewer than 1500 per thread) until
    // the first grain splits into poly-ellipsoids. The choice used to be made once per
    // `advance` call: a caller that advanced the whole run in one call (the accuracy sweep)
    // kept the team off to the end, and its "two threads" gave one thread's bits; a caller
    // that advanced in short calls switched at its next call. Now it is read after every step.
    use fractum::Run;
    let sets: Vec<String> = TEAM_SCENE
        .chunks(2)
        .map(|kv| kv[1].to_string())
        .chain(["output.vtk=0".to_string()])
        .collect();
    let scene =
        || fractum::Scene::load(&common::repo().join("scenes/shpb_sand.toml"), &sets).unwrap();
    let run = |threads: usize, chunk: u64| {
        let mut r =
            fractum::models::granular::Simulation::new(scene(), threads, &mut |_| {}).unwrap();
        while !Run::finished(&r) {
            Run::advance(&mut r, chunk).unwrap();
        }
        Run::summary(&r)
    };
    let whole = run(2, u64::MAX);
    assert!(whole["broken_particles"].as_u64().unwrap() > 10, "{whole}");
    assert_eq!(whole, run(2, 97), "one call against calls of 97 steps");
    // And the two-thread run is not the one-thread run (it was, with one call).
    assert_ne!(whole, run(1, u64::MAX));
}

#[test]
fn a_sample_prepared_in_parts_is_the_same_on_one_and_two_threads() {
    // 2128 spheres compacted without friction: above the 2048 grains from which preparation
    // cuts its pair loop into parts of 1024 rows and runs on the team. The parts, not the
    // threads, fix the order of every sum, so the sample (and the run from it) is the same;
    // with one part per thread, as a run's steps cut it, the two would differ.
    let sets = [
        "sample.box=[0.0078, 0.0078, 0.0078]",
        "sample.packing=\"compaction\"",
        "loading.end_strain=0.0002",
        "output.vtk=0",
    ]
    .map(String::from);
    let sample = |threads: usize| {
        let scene =
            fractum::Scene::load(&common::repo().join("scenes/shpb_sand.toml"), &sets).unwrap();
        let sim = Simulation::new(scene, threads, &mut |_| {}).unwrap();
        let b = &sim.model.state.bodies;
        assert!(
            b.len() >= 2 * fractum::sample::PREPARATION_PART_ROWS,
            "{} grains: too few for parts",
            b.len()
        );
        (b.pos.clone(), b.orientation.clone(), b.radius.clone())
    };
    assert!(sample(1) == sample(2), "the two-thread sample differs");
}
