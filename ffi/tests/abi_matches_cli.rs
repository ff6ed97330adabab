//! The C ABI drives any scene to the same results as the command line: a C program
//! (ffi/examples/run_scene.c, compiled with gcc -Werror) creates the run from a scene file,
//! overrides and a thread count, advances it to its end in calls of 777 steps and prints
//! `fractum_summary_json`; `fractum run` runs the same scene on the same threads and writes
//! summary.json. The two must be the same, key by key and as text, but for `wall_seconds`
//! (the one timing key, which only the program writes). One test per model, each on one and
//! on two threads, at the reduced sizes of tests/golden_summaries.rs, and the granular model
//! also where its loops go parallel.
//!
//! The program advances in chunks of its own (up to its progress, snapshot and checkpoint
//! cadences) and the C program in others: chunking a run does not change it.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use serde_json::Value;

/// Steps per `fractum_advance` call: not a divisor of anything the scenes use.
const CHUNK: &str = "777";

fn run_scene_exe() -> &'static Path {
    static EXE: OnceLock<PathBuf> = OnceLock::new();
    EXE.get_or_init(|| common::compile("gcc", "ffi/examples/run_scene.c", "-std=c11"))
}

fn scene_path(scene: &str) -> PathBuf {
    common::repo().join("scenes").join(scene)
}

/// `fractum run`'s summary.json, parsed.
fn cli_summary(scene: &str, sets: &[&str], threads: usize) -> Value {
    let dir = tempfile_dir(&format!("{scene}.t{threads}"));
    let out = dir.join("out");
    let mut cmd = Command::new(common::fractum_bin());
    cmd.arg("run")
        .arg(scene_path(scene))
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--threads", &threads.to_string()])
        .current_dir(&dir);
    for s in sets {
        cmd.args(["--set", s]);
    }
    let o = cmd.output().expect("fractum runs");
    assert!(
        o.status.success(),
        "fractum run {scene} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("summary.json is JSON")
}

/// A fresh folder under the target's test scratch space.
fn tempfile_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("abi_matches_cli")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The C program's summary text (stdout without the final newline).
fn abi_summary(scene: &str, sets: &[&str], threads: usize) -> String {
    let o = Command::new(run_scene_exe())
        .arg(scene_path(scene))
        .arg(threads.to_string())
        .arg(CHUNK)
        .args(sets)
        .output()
        .expect("run_scene runs");
    assert!(
        o.status.success(),
        "run_scene {scene} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = String::from_utf8(o.stdout).expect("UTF-8");
    text.strip_suffix('\n').unwrap_or(&text).to_string()
}

fn same_summary(scene: &str, sets: &[&str], threads: usize) {
    let mut cli = cli_summary(scene, sets, threads);
    let cli_map = cli.as_object_mut().expect("an object");
    assert!(
        cli_map.shift_remove("wall_seconds").is_some(),
        "summary.json has wall_seconds"
    );
    let text = abi_summary(scene, sets, threads);
    let abi: Value = serde_json::from_str(&text).expect("the ABI's summary is JSON");
    let abi_map = abi.as_object().expect("an object");
    assert!(
        !abi_map.contains_key("wall_seconds"),
        "the ABI's summary has no timing"
    );

    let mut differences = Vec::new();
    for (key, value) in cli_map.iter() {
        match abi_map.get(key) {
            None => differences.push(format!("{key}: only in summary.json")),
            Some(v) if v != value => {
                differences.push(format!("{key}: summary.json {value}, ABI {v}"))
            }
            Some(_) => {}
        }
    }
    for key in abi_map.keys().filter(|k| !cli_map.contains_key(*k)) {
        differences.push(format!("{key}: only in the ABI's summary"));
    }
    assert!(
        differences.is_empty(),
        "{scene} on {threads} thread(s): the ABI and `fractum run` differ:\n{}",
        differences.join("\n")
    );
    let keys = |m: &serde_json::Map<String, Value>| m.keys().cloned().collect::<Vec<_>>();
    assert_eq!(keys(cli_map), keys(abi_map), "{scene}: the keys' order");
    let cli_text = serde_json::to_string_pretty(&cli).unwrap();
    assert!(
        cli_text == text,
        "{scene} on {threads} thread(s): the same values but not the same text"
    );
    eprintln!(
        "{scene} on {threads} thread(s): {} keys, identical ({} bytes)",
        abi_map.len(),
        text.len()
    );
}

#[test]
fn granular_through_the_abi_matches_the_cli() {
    // The reduced SHPB sand scene: 111 grains, 18 of which break by 5% strain.
    let sets = [
        "sample.box=[3e-3, 3e-3, 3e-3]",
        "sample.solid_fraction=0.5",
        "loading.end_strain=0.05",
    ];
    for threads in [1, 2] {
        same_summary("shpb_sand.toml", &sets, threads);
    }
}

/// At the sizes above one and two threads give the same numbers (no loop is big enough to
/// go parallel); 3375 spheres take the parallel contact loop on two threads, whose results
/// differ from one thread's.
#[test]
fn granular_on_parallel_loops_through_the_abi_matches_the_cli() {
    let sets = ["sample.layers=[15, 15, 15]", "loading.end_strain=0.005"];
    same_summary("shpb_cubic.toml", &sets, 2);
}

#[test]
fn dlsm_through_the_abi_matches_the_cli() {
    for threads in [1, 2] {
        same_summary("dlsm_tensile.toml", &["sample.elements=300"], threads);
    }
}

#[test]
fn beam2d_through_the_abi_matches_the_cli() {
    let sets = [
        "sample.cells=[8, 12]",
        "loading.strain_rate=0.4",
        "loading.ramp_time=0.001",
    ];
    for threads in [1, 2] {
        same_summary("beam2d_moduli.toml", &sets, threads);
    }
}
