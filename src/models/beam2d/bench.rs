//! beam2d throughput: polygon-steps per second on whole runs of its scenes. Used by
//! `cargo bench --bench beam2d_throughput`; it prints figures and asserts nothing.

use std::path::Path;
use std::time::Instant;

use crate::error::Result;
use crate::scene::Scene;

/// One timed run of a beam2d scene.
#[derive(Debug, Clone)]
pub struct PolygonCase {
    pub scene: String,
    pub polygons: usize,
    pub threads: usize,
    pub steps: u64,
    pub seconds: f64,
}

impl PolygonCase {
    pub fn polygon_steps_per_second(&self) -> f64 {
        self.polygons as f64 * self.steps as f64 / self.seconds
    }
}

/// Runs the beam2d scene `path` (with `overrides`) to its end on `threads` threads and times
/// the stepping (not the lattice construction).
pub fn time_beam2d_scene(path: &Path, overrides: &[String], threads: usize) -> Result<PolygonCase> {
    let scene = Scene::load(path, overrides)?;
    let name = scene.name.clone();
    let mut run = super::Beam2dRun::new(scene, threads, &mut |_| {})?;
    let start = Instant::now();
    while !run.finished() {
        run.advance(1000)?;
    }
    Ok(PolygonCase {
        scene: name,
        polygons: run.polygons.len(),
        threads,
        steps: run.clock.step,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The beam2d results as a Markdown table.
pub fn polygon_table(cases: &[PolygonCase]) -> String {
    let mut s = String::from(
        "| scene | polygons | threads | steps | wall s | polygon-steps/s |\n|---|---:|---:|---:|---:|---:|\n",
    );
    for c in cases {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.3} | {:.3e} |\n",
            c.scene,
            c.polygons,
            c.threads,
            c.steps,
            c.seconds,
            c.polygon_steps_per_second()
        ));
    }
    s
}
