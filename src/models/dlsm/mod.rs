//! The `dlsm` model's run: Voronoi elements joined by the distinct lattice spring model
//! (dlsm paper).
//!
//! ```text
//! loading.prescribe        prescribed velocity components for the step
//! kick_drift               Tchamwa–Wielgosz first stage (Eq. 37–38)
//! bonds.evaluate           cohesive forces and moments (Eq. 1–34), breaking (Eq. 36)
//! pipeline.accumulate      broken contacts (fracture), ground (contact, friction), gravity
//! loading.constrain        reactions out of the prescribed components
//! kick                     second stage
//! every output.every steps: check finite, a row of series.csv, stop after failure
//! ```
//!
//! Only the effects the scene lists are built: without `fracture` no contact can break and
//! no polyhedron contact is looked for; without `contact` there is no ground.

pub mod accuracy;
pub mod bench;
mod build;
mod explain;
pub mod loading;
mod model;
pub mod pipeline;
mod report;
pub mod sample;
pub mod scene;
mod step;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use crate::bond::dlsm::DlsmBonds;
use crate::error::{Error, Result};
use crate::integrate::TchamwaWielgosz;
use crate::output::vtk;
use crate::run::{Built, Clock, Model, RunInfo, Runner};
use crate::sample::voronoi::Domain;
use crate::scene::{DtSpec, EffectKind, IntegratorKind, Scene};
use crate::shape::polyhedron::Polyhedron;
use crate::state::{Bodies, Forces, Vec3};
use loading::{Brazilian, DlsmLoading, RowInputs, Setting};
use pipeline::ElementPipeline;
use sample::{DlsmSample, DlsmSampleInfo};
use scene::DlsmScene;

pub use build::lattice_highest_frequency;
pub use explain::explain;
pub use loading::JAW_RADIUS;

/// A dlsm run: the generic runner over the dlsm model.
pub type DlsmRun = Runner<Dlsm>;

/// φ of the Tchamwa–Wielgosz scheme when the scene does not give one. The paper uses
/// 1 ≤ φ ≤ 1.3; the lattice's flutter modes need about 2 at a third of the critical step
/// (docs/validation.md).
pub const DEFAULT_PHI: f64 = 2.0;

/// How far the total energy of a run without work input may rise above its start before the
/// run stops. The strain energy is an estimate, exact for uniform strain: released from static
/// torsion, stable runs at φ = 2 rose to 1.49x their start at 150 elements (1.38x at 300,
/// 1.15x at 1500), so a margin of 10% stopped good runs. A growing mode grows exponentially
/// (undamped at 2000 elements: 2x at 2.5e-4 s, 4x at 3.3e-4 s, NaN at 1.9e-3 s), so the
/// margin costs it a few hundred steps.
pub const ENERGY_GROWTH_LIMIT: f64 = 4.0;

/// Where and when the first contact broke.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct FirstBreak {
    pub step: u64,
    pub contact: usize,
    /// Midpoint of the two seeds (m).
    pub position: Vec3,
    /// Time of the step it broke in (s).
    pub time: f64,
}

/// The dlsm model: what its scene builds (rebuilt on restore) and the persistent state.
pub struct Dlsm {
    pub cfg: DlsmScene,
    pub bonds: DlsmBonds,
    pub shapes: Vec<Polyhedron>,
    pub domain: Domain,
    /// Undeformed centroids.
    pub reference: Vec<Vec3>,
    pub sample: DlsmSampleInfo,
    pub integrator: TchamwaWielgosz,
    /// `fracture`: the tensile strength of the cohesive contacts.
    pub tensile_strength: Option<f64>,
    /// Eq. 39 without its factor (s), and the rotational counterpart.
    pub dt_critical: f64,
    pub dt_rotational: f64,
    /// Set by a series row whose energy grew without work put in (see `after_row`); the run
    /// stops with it at the next step. Not state: a restored run finds it again.
    energy_fault: Option<String>,
    pub state: DlsmState,
}

/// What a checkpoint keeps of a dlsm run; the sample is rebuilt from the scene.
#[derive(Clone, Serialize, Deserialize)]
pub struct DlsmState {
    pub bodies: Bodies,
    /// Forces and torques of the last evaluation.
    pub forces: Forces,
    /// Broken contacts in the order they broke, with the step and the midpoint of the two
    /// seeds at breaking.
    pub broken_order: Vec<u32>,
    pub break_log: Vec<(u64, Vec3)>,
    pub first_break: Option<FirstBreak>,
    /// The effects after the cohesive lattice: broken contacts, ground, gravity (only those
    /// the scene names; the contacts' history is kept, gravity is not written).
    pub pipeline: ElementPipeline,
    pub loading: DlsmLoading,
    /// True once the loading has found the specimen failed.
    pub stopped: bool,
}
