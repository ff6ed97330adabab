//! Fractum: a discrete element solver for brittle fracture.
//!
//! A run is described by a scene file ([`scene::Scene`]); [`run::build`] makes the run of
//! its model (a [`run::Run`]): for `granular`, [`simulation::Simulation`] builds the sample,
//! the force pipeline of exactly the effects the scene names ([`effects::Pipeline`]), the
//! loading and the probes, and steps them. [`driver::run_to_end`] writes series.csv,
//! summary.json, VTK snapshots and checkpoints for any run.
//! SI units throughout. See docs/architecture.md for the map of the code.

pub mod beam2d;
pub mod bench;
pub mod bond;
pub mod contact;
pub mod dlsm;
pub mod driver;
pub mod effects;
pub mod error;
pub mod explain;
pub mod export;
pub mod fracture;
pub mod integrate;
pub mod loading;
pub mod output;
pub mod parallel;
pub mod probe;
pub mod run;
pub mod sample;
pub mod scene;
pub mod shape;
pub mod simulation;
pub mod state;

pub use error::{Error, Result};
pub use run::Run;
pub use scene::Scene;
pub use simulation::Simulation;
