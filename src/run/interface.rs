//! A run of any model as its hosts see it (the driver, the CLI, the C ABI, checkpoints), and
//! the summary keys every model shares.

use serde_json::{Map, Value, json};

use crate::error::Result;
use crate::probe::Series;
use crate::scene::Scene;
use crate::state::Vec3;

use super::{CallLimits, Faces};

/// A run of any model, as the driver, the CLI, the C ABI and checkpoints see it.
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
    /// True at the end step or once the model stopped the run.
    fn finished(&self) -> bool;
    /// Takes up to `steps` steps (never past the end), recording series rows on the way.
    fn advance(&mut self, steps: u64) -> Result<()>;
    /// Advances to exactly `time` (s): whole steps, then one shorter step that lands on it;
    /// never past the end (a time beyond it stops there, as `advance` does).
    fn advance_to(&mut self, time: f64) -> Result<()>;
    /// The rows of series.csv so far.
    fn series(&self) -> &Series;
    /// The results so far: identical for identical scenes, seeds, thread counts and builds.
    fn summary(&self) -> Value;
    /// VTK files of the current state as (stem, .vtu text); each stem gets its own .pvd index.
    fn snapshot(&self) -> Vec<(&'static str, String)>;
    /// Further result files written at the end, as (file name, content).
    fn extra_outputs(&self) -> Vec<(String, Vec<u8>)>;
    /// The whole state, for a checkpoint; the registry's `restore` reads it back.
    fn save_state(&self) -> Vec<u8>;
    /// A short line for the progress bar (time, strain, ...).
    fn status(&self) -> String;
    /// Warnings for the user, in the order they arose.
    fn warnings(&self) -> &[String];
    /// Body centres, velocities and orientations (see [`super::BodiesView::positions`]).
    fn positions(&self) -> Vec<Vec3>;
    fn velocities(&self) -> Vec<Vec3>;
    fn orientations(&self) -> Vec<[f64; 4]>;
    /// Body radii (m), for models of round grains (see [`super::BodiesView::radii`]).
    fn radii(&self) -> Option<Vec<f64>>;
    /// The grains' loads at the last fracture check (see [`super::BodiesView::grain_loads`]).
    fn grain_loads(&self) -> Option<Vec<crate::fracture::GrainLoad>>;
    /// Body–body contacts now, for models that count them.
    fn contacts(&self) -> Option<usize>;
    /// Kinetic energy (J) now.
    fn kinetic_energy(&self) -> f64;
    /// The driven faces, for models that have them (granular samples in a box).
    fn faces(&self) -> Option<&dyn Faces>;
    /// Bounds every later `advance` / `advance_to` call (see [`CallLimits`]).
    fn set_call_limits(&mut self, limits: CallLimits);
    /// Drives the top (z+) and bottom (z-) faces from outside from now on, at `top` and
    /// `bottom` m/s into the sample (compression positive); the run then has no end of its
    /// own. Fails for a model without such faces.
    fn set_face_speeds(&mut self, top: f64, bottom: f64) -> Result<()>;
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
