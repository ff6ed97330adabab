//! An output folder that cannot lie: a run or resume marks its folder in progress before its
//! first write, a second live run into the folder is refused naming the first, a killed run's
//! lock is taken over, and the files of two runs are never mixed.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A small oedometer scene that a single thread runs in under a second at `end_strain` 0.05
/// and for several seconds at 0.4.
fn scene(dir: &Path) -> PathBuf {
    let file = dir.join("oedometer.toml");
    fs::write(&file, common::small_oedometer(200, "", 0.05)).unwrap();
    file
}

fn args<'a>(scene: &'a Path, out: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec![
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--threads",
        "1",
        "--checkpoint-every",
        "500",
    ];
    a.extend_from_slice(extra);
    a
}

fn spawn(cwd: &Path, args: &[&str]) -> Child {
    Command::new(common::fractum_bin())
        .args(args)
        .current_dir(cwd)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("fractum starts")
}

fn summary(out: &Path) -> serde_json::Value {
    let text = fs::read_to_string(out.join("summary.json")).expect("summary.json is there");
    serde_json::from_str(&text).expect("summary.json is whole JSON")
}

/// Whether a summary is a finished run's: all its results, without the `"complete": false` of a
/// run in progress or failed.
fn finished(s: &serde_json::Value) -> bool {
    s.get("complete").is_none() && s.get("dt").is_some() && s.get("contacts_final").is_some()
}

/// Waits until `child` has rewritten series.csv (its text is no longer `before`), then kills it
/// with SIGKILL, as a host killing a run without a word would.
fn kill_after_first_write(mut child: Child, out: &Path, before: &str) {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before it could be killed: lengthen it");
        }
        let now = fs::read_to_string(out.join("series.csv")).unwrap_or_default();
        if !now.is_empty() && now != before {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the run wrote no series in 120 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
}

/// The seed of every checkpoint in `out/checkpoints`.
fn checkpoint_seeds(out: &Path) -> Vec<(String, u64)> {
    let mut seeds: Vec<(String, u64)> = fs::read_dir(out.join("checkpoints"))
        .map(|entries| {
            entries
                .flatten()
                .filter(|e| e.file_name().to_string_lossy().ends_with(".fcp"))
                .map(|e| {
                    let saved = fractum::output::checkpoint::load(&e.path()).unwrap();
                    (
                        e.file_name().to_string_lossy().to_string(),
                        saved.scene.seed,
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    seeds.sort();
    seeds
}

/// Every snapshot a .pvd index lists is a file of the folder.
fn assert_indexes_list_existing_frames(out: &Path) {
    for entry in fs::read_dir(out).unwrap().flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        if !name.ends_with(".pvd") {
            continue;
        }
        let text = fs::read_to_string(entry.path()).unwrap();
        for file in text.split("file=\"").skip(1) {
            let file = &file[..file.find('"').unwrap()];
            assert!(
                out.join(file).is_file(),
                "{name} lists {file}, not in the folder"
            );
        }
    }
}

#[test]
fn a_run_killed_in_a_finished_runs_folder_leaves_it_marked_incomplete_and_unmixed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene(dir.path());
    let out = dir.path().join("X");
    let o = common::fractum(dir.path(), &args(&scene, &out, &[]));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(finished(&summary(&out)));
    assert!(checkpoint_seeds(&out).len() >= 5);
    let first_series = fs::read_to_string(out.join("series.csv")).unwrap();

    // Another seed into the same folder, for longer, killed once it has written.
    let child = spawn(
        dir.path(),
        &args(
            &scene,
            &out,
            &["--set", "seed=6", "--set", "loading.end_strain=0.4"],
        ),
    );
    kill_after_first_write(child, &out, &first_series);
    let s = summary(&out);
    assert_eq!(
        s["complete"], false,
        "a killed run's folder must not keep the earlier run's complete summary: {s}"
    );
    assert_eq!(s["seed"], 6, "the summary is the killed run's: {s}");
    let seeds = checkpoint_seeds(&out);
    assert!(
        seeds.iter().all(|(_, seed)| *seed == 6),
        "checkpoints of two runs side by side: {seeds:?}"
    );
    assert_indexes_list_existing_frames(&out);
    let vtk: Vec<String> = fs::read_dir(out.join("vtk"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().to_string())
        .collect();
    let listed = fs::read_to_string(out.join("particles.pvd")).unwrap();
    // A snapshot is written before the index that lists it: killed between the two, the run
    // leaves its newest frame unlisted. Any other unlisted frame would be the earlier run's.
    let step = |f: &str| -> u64 {
        f.trim_start_matches("particles_")
            .trim_end_matches(".vtu")
            .parse()
            .unwrap()
    };
    let frames: Vec<&String> = vtk.iter().filter(|f| f.starts_with("particles_")).collect();
    let newest_listed = frames
        .iter()
        .filter(|f| listed.contains(f.as_str()))
        .map(|f| step(f))
        .max();
    let unlisted: Vec<&&String> = frames
        .iter()
        .filter(|f| !listed.contains(f.as_str()))
        .collect();
    assert!(
        unlisted.len() <= 1
            && unlisted
                .iter()
                .all(|f| newest_listed.is_none_or(|n| step(f) > n)),
        "{unlisted:?} are another run's snapshots (listed up to step {newest_listed:?})"
    );
    // The killed run's lock is taken over by the next run.
    assert!(out.join(".fractum.lock").exists());
    let o = common::fractum(dir.path(), &args(&scene, &out, &[]));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(finished(&summary(&out)));
    assert!(!out.join(".fractum.lock").exists(), "a run leaves no lock");
}

#[test]
fn a_resume_killed_in_its_own_folder_leaves_it_marked_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene(dir.path());
    let out = dir.path().join("X");
    let o = common::fractum(
        dir.path(),
        &args(&scene, &out, &["--set", "loading.end_strain=0.4"]),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(finished(&summary(&out)));
    let whole = fs::read_to_string(out.join("series.csv")).unwrap();
    let checkpoint = out.join("checkpoints/step_000000500.fcp");
    let child = spawn(
        dir.path(),
        &[
            "resume",
            checkpoint.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--threads",
            "1",
            "--checkpoint-every",
            "500",
        ],
    );
    kill_after_first_write(child, &out, &whole);
    let s = summary(&out);
    assert_eq!(
        s["complete"], false,
        "a resume killed in its folder leaves a cut series under a complete summary: {s}"
    );
    assert!(checkpoint.is_file(), "the resumed checkpoint stays");
    assert_indexes_list_existing_frames(&out);
    // The folder resumes from its own latest checkpoint to the uninterrupted run's end.
    let latest = fs::read_dir(out.join("checkpoints"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "fcp"))
        .max()
        .unwrap();
    common::resume(dir.path(), &latest, &out);
    assert!(finished(&summary(&out)));
    assert_eq!(fs::read_to_string(out.join("series.csv")).unwrap(), whole);
}

#[test]
fn a_second_live_run_into_the_same_folder_is_refused_naming_the_first() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene(dir.path());
    let out = dir.path().join("X");
    let long = ["--set", "loading.end_strain=0.4"];
    let first = spawn(dir.path(), &args(&scene, &out, &long));
    let pid = first.id();
    kill_after_first_write_or_keep(first, &out, |first| {
        let o = common::fractum(dir.path(), &args(&scene, &out, &["--set", "seed=7"]));
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(
            o.status.code(),
            Some(2),
            "a second run into a folder being written: {stderr}"
        );
        assert!(
            stderr.contains(&format!("process {pid}")) && stderr.contains("--out"),
            "the refusal names the other process: {stderr}"
        );
        assert_eq!(stderr.trim().lines().count(), 1, "one sentence: {stderr}");
        assert!(
            first.try_wait().unwrap().is_none(),
            "the first run is still writing"
        );
    });
    // The first run was killed: its lock is stale and a new run takes the folder.
    let o = common::fractum(dir.path(), &args(&scene, &out, &["--set", "seed=7"]));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    assert!(finished(&s) && s["seed"] == 7, "{s}");
    assert!(checkpoint_seeds(&out).iter().all(|(_, seed)| *seed == 7));
}

/// Waits until `child` has written series.csv, calls `check` while it still runs, then kills it.
fn kill_after_first_write_or_keep(mut child: Child, out: &Path, check: impl FnOnce(&mut Child)) {
    let start = Instant::now();
    while fs::read_to_string(out.join("series.csv"))
        .unwrap_or_default()
        .is_empty()
    {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before the check: lengthen it");
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no series in 120 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    check(&mut child);
    let _ = child.kill();
    child.wait().unwrap();
}

#[test]
fn a_lock_left_by_a_process_that_is_gone_is_taken_over() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene(dir.path());
    let out = dir.path().join("X");
    fs::create_dir_all(&out).unwrap();
    // The id of a process that has ended (and was reaped).
    let mut gone = Command::new("true").spawn().unwrap();
    let pid = gone.id();
    gone.wait().unwrap();
    fs::write(out.join(".fractum.lock"), format!("{pid}\n")).unwrap();
    let o = common::fractum(dir.path(), &args(&scene, &out, &[]));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(finished(&summary(&out)));
    assert!(!out.join(".fractum.lock").exists());
}
