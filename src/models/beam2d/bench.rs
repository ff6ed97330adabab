//! beam2d throughput: polygon-steps per second on whole runs of its scenes. Used by
//! `cargo bench --bench beam2d_throughput`; it prints figures and asserts nothing.

use std::path::Path;
use std::time::Instant;

use crate::bench::Timed;
use crate::error::Result;
use crate::scene::Scene;

/// Runs the beam2d scene `path` (with `overrides`) to its end on `threads` threads and times
/// the stepping (not the lattice construction).
pub fn time_beam2d_scene(path: &Path, overrides: &[String], threads: usize) -> Result<Timed> {
    let scene = Scene::load(path, overrides)?;
    let name = scene.name.clone();
    let mut run = super::Beam2dRun::new(scene, threads, &mut |_| {})?;
    let start = Instant::now();
    while !run.finished() {
        run.advance(1000)?;
    }
    Ok(Timed {
        case: name,
        bodies: run.model.state.polygons.len(),
        contacts: None,
        threads,
        steps: run.clock.step,
        seconds: start.elapsed().as_secs_f64(),
    })
}
