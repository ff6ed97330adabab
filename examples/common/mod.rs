//! What the beam2d examples share: one run of a shipped scene at given thresholds, and the
//! pool that runs many of them on the two cores.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use fractum::Scene;
use fractum::models::beam2d::Beam2dRun;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// scenes/`file` with `seed`, the beam thresholds `strain` (%) and `bending` (degrees) and the
/// `extra` overrides, run to its end on one thread.
pub fn run(file: &str, seed: u64, strain: f64, bending: f64, extra: &[&str]) -> Beam2dRun {
    let mut sets = vec![
        format!("seed={seed}"),
        format!("material.beam_strain_threshold={}", strain / 100.0),
        format!("material.beam_bending_threshold={}", bending.to_radians()),
    ];
    sets.extend(extra.iter().map(|s| s.to_string()));
    let scene = Scene::load(&root().join("scenes").join(file), &sets).expect("scene");
    let mut r = Beam2dRun::new(scene, 1, &mut |_| {}).expect("run");
    while !r.finished() {
        r.advance(5000).expect("step");
    }
    r
}

/// `work` of every job on two workers (two cores), each job on one thread, its count on
/// stderr; the results in job order.
pub fn on_two_workers<J: Sync, R: Send>(jobs: &[J], work: impl Fn(&J) -> R + Sync) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let total = jobs.len();
    let done: Vec<Vec<(usize, R)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..2)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let j = next.fetch_add(1, Ordering::Relaxed);
                        if j >= total {
                            return mine;
                        }
                        mine.push((j, work(&jobs[j])));
                        eprint!("\r{} / {total} runs", j + 1);
                    }
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    eprintln!();
    let mut results: Vec<Option<R>> = (0..total).map(|_| None).collect();
    for (j, r) in done.into_iter().flatten() {
        results[j] = Some(r);
    }
    results.into_iter().map(Option::unwrap).collect()
}
