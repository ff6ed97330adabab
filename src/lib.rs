//! Fractum: a discrete element solver for brittle fracture.
//!
//! A run is described by a scene file ([`scene::Scene`], loaded and checked by
//! [`Scene::load`]). The registry ([`models`]) picks the model from `model.kind`
//! (`granular`, `dlsm`, `beam2d`; one folder each under `models/`) and builds its run: the
//! generic [`run::Runner`] over the model, which implements [`run::Run`] once for every
//! model (clock, advancing, outputs, checkpoints, thread pool). [`driver::run_to_end`]
//! writes series.csv, summary.json, VTK snapshots and checkpoints for any run.
//! SI units throughout. See docs/architecture.md for the map of the code.

pub mod accuracy;
pub mod bench;
pub mod bond;
pub mod contact;
pub mod driver;
pub mod effects;
pub mod error;
pub mod explain;
pub mod fracture;
pub mod integrate;
pub mod linalg;
pub mod models;
pub mod output;
pub mod parallel;
pub mod probe;
pub mod run;
pub mod sample;
pub mod scene;
pub mod shape;
pub mod state;

pub use error::{Error, Result};
// A run of any model from its scene, or from a saved state: what embedders (the C ABI) call.
pub use models::{build, restore};
pub use run::Run;
pub use scene::Scene;
