//! Golden summaries: every shipped scene, shrunk to run in about a second, on one and on two
//! threads, must write the summary.json it wrote when the goldens were made, byte for byte,
//! less `wall_seconds` (the one timing key).
//!
//! What it guards: changes that must not move a single number, such as moving a model into
//! another module, splitting files, renaming or reordering code. The comparison is exact: one
//! float differing in its last bit, a key added, dropped or renamed, all fail. A deliberate
//! change of physics or of the summary's keys changes the goldens too; regenerate them with
//!
//! ```sh
//! FRACTUM_BLESS=1 cargo test --release --test golden_summaries
//! ```
//!
//! and say in that commit that the goldens moved and why. `FRACTUM_BIN=/path/to/fractum` runs
//! that binary instead of the one cargo built, e.g. to bless with a build of the code before a
//! refactor and then check the refactored code against it.
//!
//! series.csv is not compared: at these sizes the goldens would hold about 4 MB of it
//! (crush_grain writes a row every 50 of its 500,000 steps), and `output.every` cannot be
//! raised to thin it out without changing the runs themselves (the granular model adapts its
//! step, and dlsm checks for failure, at output steps). The summaries carry the final state,
//! counters and energy account, which an earlier difference reaches anyway.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use serde_json::Value;

/// Every file of scenes/ with the `--set` overrides that shrink it. Each keeps all the scene's
/// effects, and the loading goes far enough that what the scene is about happens (grains,
/// beams or contacts break; waves make a few periods).
const SCENES: &[(&str, &[&str])] = &[
    // 10 x 16 polygons, four times the strain rate, to 3%: past the peak, about 20 beams broken.
    (
        "beam2d_compression.toml",
        &[
            "sample.cells=[10, 16]",
            "loading.strain_rate=8",
            "loading.end_strain=0.03",
        ],
    ),
    // The reduced sample and loading of tests/beam2d.rs, on 8 x 12 polygons.
    (
        "beam2d_moduli.toml",
        &[
            "sample.cells=[8, 12]",
            "loading.strain_rate=0.4",
            "loading.ramp_time=0.001",
        ],
    ),
    // About the fewest elements the disc's packing reaches (300 and 400 fail); it takes 3 s
    // of the run. Between the scene's flat platens at four times the speed, until the disc
    // fails and the force has halved (about 1300 broken contacts, 5400 steps).
    (
        "brazilian.toml",
        &["sample.elements=600", "loading.speed=0.4"],
    ),
    // Past both force peaks (0.057 and 0.085 mm): the grain splits, then a half breaks.
    ("crush_grain.toml", &["loading.end_displacement=0.09e-3"]),
    ("dlsm_tensile.toml", &["sample.elements=300"]),
    // Runs until failure stops it, about 270 contacts broken.
    ("dlsm_tensile_failure.toml", &["sample.elements=300"]),
    // Four periods each.
    (
        "dlsm_wave_tension.toml",
        &["sample.elements=150", "loading.end_time=0.0036"],
    ),
    (
        "dlsm_wave_torsion.toml",
        &["sample.elements=150", "loading.end_time=0.006"],
    ),
    // About 600 polygons (above the 512 items from which the polygon loops go parallel) and
    // 800 steps, in which about 1000 beams break.
    (
        "explosion_disc.toml",
        &["sample.diameter=0.3", "loading.end_time=0.0008"],
    ),
    // Full size (800 polygons), the first 1000 steps.
    ("impact_block.toml", &["loading.end_time=0.001"]),
    // 100 spheres: a walled box this small cannot be packed to 0.55 (docs/scenes.md), so 0.5,
    // then servo-compacted to 100 kPa as shipped (most of the run), then loaded to 0.2%.
    (
        "oedometer_spheres.toml",
        &[
            "sample.count=100",
            "sample.solid_fraction=0.5",
            "loading.end_strain=0.002",
        ],
    ),
    // The ball lands (0.01 m at 5 m/s) and starts to roll.
    (
        "rolling_ball.toml",
        &["sample.elements=300", "loading.end_time=0.05"],
    ),
    // About 200 Mason sand ellipsoids compacted to 0.574 in a 2 mm box, to 2% strain.
    (
        "mason_sand_shpb.toml",
        &["sample.box=[2e-3, 2e-3, 2e-3]", "loading.end_strain=0.02"],
    ),
    // The whole specimen's scene in a 2 mm sleeve: about 140 Mason sand ellipsoids jammed at
    // 0.574, to 2% strain.
    (
        "mason_sand_specimen.toml",
        &["sample.box=[2e-3, 2e-3, 2e-3]", "loading.end_strain=0.02"],
    ),
    // The parallel case: 3375 spheres, above the 2 x 1500 bodies from which the contact loop
    // goes parallel on two threads; to 0.5% strain, about 220 grains broken.
    (
        "shpb_cubic.toml",
        &["sample.layers=[15, 15, 15]", "loading.end_strain=0.005"],
    ),
    (
        "shpb_hcp.toml",
        &["sample.layers=[5, 5, 5]", "loading.end_strain=0.05"],
    ),
    // About 120 spheres. Packing to 0.55 takes seconds even in a box this small (and
    // tends to jam short of it); to 0.5 it is quick. About 20 grains break by 5% strain.
    (
        "shpb_random_mono.toml",
        &[
            "sample.box=[3e-3, 3e-3, 3e-3]",
            "sample.solid_fraction=0.5",
            "loading.end_strain=0.05",
        ],
    ),
    // Likewise, about 110 polydisperse grains.
    (
        "shpb_sand.toml",
        &[
            "sample.box=[3e-3, 3e-3, 3e-3]",
            "sample.solid_fraction=0.5",
            "loading.end_strain=0.05",
        ],
    ),
];

/// Results depend on the thread count (only repeats on the same count are bit for bit), so
/// each count has its own goldens; two threads take dlsm's and beam2d's parallel passes (the
/// granular scenes here are too small for the worker team: tests/runs.rs covers it).
const THREADS: [usize; 2] = [1, 2];

const BLESS_HINT: &str = "if the change is deliberate, regenerate the goldens with \
     `FRACTUM_BLESS=1 cargo test --release --test golden_summaries` and say so in the commit";

/// The binary under test: `FRACTUM_BIN`, else the one cargo built. Paths come from cargo
/// rather than tests/common, which imports library types: this test compiles whatever the
/// library's modules are called.
fn fractum_bin() -> PathBuf {
    std::env::var_os("FRACTUM_BIN").map_or_else(
        || PathBuf::from(env!("CARGO_BIN_EXE_fractum")),
        PathBuf::from,
    )
}

/// The repository root (where scenes/ lives).
fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn blessing() -> bool {
    std::env::var_os("FRACTUM_BLESS").is_some_and(|v| v == "1")
}

/// A golden file, relative to the repository (as the messages name it).
fn golden_name(stem: &str, threads: usize) -> String {
    format!("tests/golden/{stem}.t{threads}.json")
}

/// Runs `scene` with `sets` on `threads` threads and returns its summary.json without
/// `wall_seconds`, serialised as the program writes it (pretty, with a final newline).
fn summary(bin: &Path, scene: &str, sets: &[&str], threads: usize) -> Result<String, String> {
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let out = dir.path().join("out");
    let mut cmd = Command::new(bin);
    cmd.arg("run")
        .arg(repo().join("scenes").join(scene))
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--threads", &threads.to_string()])
        .current_dir(dir.path());
    for s in sets {
        cmd.args(["--set", s]);
    }
    let o = cmd
        .output()
        .map_err(|e| format!("{} does not run: {e}", bin.display()))?;
    if !o.status.success() {
        return Err(format!(
            "the run failed ({}): {}",
            o.status,
            String::from_utf8_lossy(&o.stderr).trim()
        ));
    }
    let path = out.join("summary.json");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut value: Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    value
        .as_object_mut()
        .ok_or("summary.json is not an object")?
        // shift_remove keeps the order of the other keys (serde_json's preserve_order).
        .shift_remove("wall_seconds");
    let mut text = serde_json::to_string_pretty(&value).expect("a parsed value serialises");
    text.push('\n');
    Ok(text)
}

/// Where `now` first departs from `golden`, line by line, for the failure message.
fn first_difference(golden: &str, now: &str) -> String {
    let (g, n): (Vec<&str>, Vec<&str>) = (golden.lines().collect(), now.lines().collect());
    let k = g
        .iter()
        .zip(&n)
        .position(|(a, b)| a != b)
        .unwrap_or(g.len().min(n.len()));
    fn line<'a>(v: &[&'a str], k: usize) -> &'a str {
        v.get(k).map_or("<end of file>", |l| l.trim())
    }
    let differing = g.iter().zip(&n).filter(|(a, b)| a != b).count() + g.len().abs_diff(n.len());
    format!(
        "first difference at line {}:\n    golden: {}\n    now:    {}\n  \
         ({differing} of {} lines differ)",
        k + 1,
        line(&g, k),
        line(&n, k),
        g.len().max(n.len())
    )
}

/// Each shipped scene on one thread and on two: two tests, so that the harness runs the
/// one-thread runs beside the two-thread ones (most granular runs here use one core whatever
/// they are given) instead of after them.
#[test]
fn every_shipped_scene_gives_its_golden_summary_on_one_thread() {
    goldens(THREADS[0]);
}

#[test]
fn every_shipped_scene_gives_its_golden_summary_on_two_threads() {
    goldens(THREADS[1]);
}

/// Runs every shipped scene on `threads` and compares its summary with its golden (or writes
/// it when blessing).
fn goldens(threads: usize) {
    let bin = fractum_bin();
    let bless = blessing();
    if bless {
        std::fs::create_dir_all(repo().join("tests/golden")).unwrap();
    }
    let start = Instant::now();
    let mut failures = Vec::new();
    for (scene, sets) in SCENES {
        let stem = scene.trim_end_matches(".toml");
        let name = golden_name(stem, threads);
        let golden = repo().join(&name);
        let t0 = Instant::now();
        let result = summary(&bin, scene, sets, threads);
        eprintln!(
            "{scene} on {threads} thread(s): {:.2} s",
            t0.elapsed().as_secs_f64()
        );
        let now = match result {
            Ok(text) => text,
            Err(e) => {
                failures.push(format!("{scene} on {threads} thread(s): {e}"));
                continue;
            }
        };
        if bless {
            std::fs::write(&golden, &now).unwrap_or_else(|e| panic!("{name}: {e}"));
            continue;
        }
        match std::fs::read_to_string(&golden) {
            Err(e) => failures.push(format!("{name}: {e} (a new scene has no golden yet)")),
            Ok(expected) if expected != now => failures.push(format!(
                "{name} differs from this run of {scene} on {threads} thread(s), {}",
                first_difference(&expected, &now)
            )),
            Ok(_) => {}
        }
    }
    eprintln!(
        "{} runs of {} on {threads} thread(s) in {:.1} s{}",
        SCENES.len(),
        bin.display(),
        start.elapsed().as_secs_f64(),
        if bless { ", goldens written" } else { "" }
    );
    assert!(
        failures.is_empty(),
        "{} of {} runs on {threads} thread(s) differ from their goldens:\n\n{}\n\n{BLESS_HINT}",
        failures.len(),
        SCENES.len(),
        failures.join("\n\n")
    );
}

/// A scene added to scenes/ must get a row in the table (and goldens), a scene removed loses
/// its row: the goldens cover exactly what is shipped.
#[test]
fn the_table_lists_every_shipped_scene() {
    let mut shipped: Vec<String> = std::fs::read_dir(repo().join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".toml"))
        .collect();
    shipped.sort();
    let mut listed: Vec<String> = SCENES.iter().map(|(s, _)| s.to_string()).collect();
    listed.sort();
    assert_eq!(listed, shipped, "SCENES against scenes/*.toml");
}
