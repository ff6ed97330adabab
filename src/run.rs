//! What the driver, the CLI and checkpoints need from a model's run, whatever the model.
//!
//! Each model (`granular` today; `dlsm` and `beam2d` to come) has its own run type holding its
//! state and stepping it; [`build`] and [`restore`] pick it from `model.kind`. The driver
//! ([`crate::driver::run_to_end`]) only talks to this trait.

use serde_json::{Map, Value, json};

use crate::beam2d::Beam2dRun;
use crate::dlsm::DlsmRun;
use crate::error::Result;
use crate::probe::Series;
use crate::scene::{ModelKind, Scene};
use crate::simulation::Simulation;

/// A run of any model.
pub trait Run: Send {
    fn scene(&self) -> &Scene;
    /// The model's scene name (`model.kind`).
    fn model(&self) -> &'static str;
    /// Number of bodies (particles, elements, polygons).
    fn bodies(&self) -> usize;
    fn step(&self) -> u64;
    /// The step at which the run ends.
    fn end_step(&self) -> u64;
    /// Time (s).
    fn time(&self) -> f64;
    /// Time step (s).
    fn dt(&self) -> f64;
    fn threads(&self) -> usize;
    fn finished(&self) -> bool {
        self.step() >= self.end_step()
    }
    /// Takes up to `steps` steps (never past the end), recording series rows on the way.
    fn advance(&mut self, steps: u64) -> Result<()>;
    /// The rows of series.csv so far.
    fn series(&self) -> &Series;
    /// The results so far: identical for identical scenes, seeds, thread counts and builds.
    fn summary(&self) -> Value;
    /// VTK files of the current state as (stem, .vtu text); each stem gets its own .pvd index.
    fn snapshot(&self) -> Vec<(&'static str, String)>;
    /// Further result files written at the end, as (file name, content).
    fn extra_outputs(&self) -> Vec<(String, Vec<u8>)> {
        Vec::new()
    }
    /// The whole state, for a checkpoint; [`restore`] reads it back.
    fn save_state(&self) -> Vec<u8>;
    /// A short line for the progress bar (time, strain, ...).
    fn status(&self) -> String {
        format!("t = {:.4e} s", self.time())
    }
    /// Warnings for the user, in the order they arose.
    fn warnings(&self) -> &[String] {
        &[]
    }
}

/// Builds the run a scene describes. `threads` = 0 uses every core.
pub fn build(
    scene: Scene,
    threads: usize,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<Box<dyn Run>> {
    match scene.model.kind {
        ModelKind::Granular => Ok(Box::new(Simulation::new(scene, threads, progress)?)),
        ModelKind::Beam2d => Ok(Box::new(Beam2dRun::new(scene, threads, progress)?)),
        ModelKind::Dlsm => Ok(Box::new(DlsmRun::new(scene, threads, progress)?)),
    }
}

/// Restores a run from the state [`Run::save_state`] wrote for this scene.
pub fn restore(scene: Scene, state: &[u8], threads: usize) -> Result<Box<dyn Run>> {
    match scene.model.kind {
        ModelKind::Granular => Ok(Box::new(Simulation::restore(scene, state, threads)?)),
        ModelKind::Beam2d => Ok(Box::new(Beam2dRun::restore(scene, state, threads)?)),
        ModelKind::Dlsm => Ok(Box::new(DlsmRun::restore(scene, state, threads)?)),
    }
}

/// The summary keys every model shares: name, model, version, seed, bodies, effects, steps,
/// time, dt, and warnings when there are any.
pub fn common_summary(run: &dyn Run) -> Map<String, Value> {
    let scene = run.scene();
    let mut m = Map::new();
    m.insert("name".into(), scene.name.clone().into());
    m.insert("model".into(), run.model().into());
    m.insert("fractum_version".into(), env!("CARGO_PKG_VERSION").into());
    m.insert("seed".into(), scene.seed.into());
    m.insert("bodies".into(), run.bodies().into());
    m.insert(
        "effects".into(),
        json!(scene.effects.iter().map(|e| e.as_str()).collect::<Vec<_>>()),
    );
    m.insert("steps".into(), run.step().into());
    m.insert("time".into(), run.time().into());
    m.insert("dt".into(), run.dt().into());
    if !run.warnings().is_empty() {
        m.insert("warnings".into(), json!(run.warnings()));
    }
    m
}
