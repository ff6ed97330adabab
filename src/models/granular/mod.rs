//! The `granular` model (granular paper): spheres and poly-ellipsoids with
//! Hertz–Mindlin contacts in a box of walls, and, with `fracture`, grains that break into
//! sub-poly-ellipsoids held by cohesive springs.
//!
//! ```text
//! loading.apply            set wall velocities
//! kick_drift               v(t+dt/2), x(t+dt); walls move
//! pipeline.accumulate      forces at t+dt (only the effects the scene names)
//! kick                     v(t+dt)
//! after the step           fracture: energy account, breaking grains, size distributions
//! after every step          stability estimate (and, with fracture, a shorter step)
//! ```

pub mod accuracy;
pub mod bench;
mod build;
mod explain;
pub mod export;
mod faces;
mod fracture;
pub mod loading;
mod model;
mod report;
pub mod sample;
pub mod scene;
mod step;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use crate::effects::{BodyPipeline, ContactParams, StepContext};
use crate::error::{Error, Result};
use crate::fracture::{FractureParams, GrainFracture};
use crate::integrate::{StepControl, VelocityVerlet, rayleigh_time_step};
use crate::output::vtk;
use crate::probe::energy::{EnergyAccount, Mechanical};
use crate::probe::size_distribution;
use crate::probe::{self, Series};
pub use crate::run::Faces;
use crate::run::{Built, Clock, Model, RunInfo, Runner};
use crate::sample::{Sample, SampleInfo};
use crate::scene::{DtSpec, EffectKind, IntegratorKind, Scene};
use crate::state::{Bodies, BoxFace, Forces, Vec3, Walls};
use loading::{BoxLoading, DrivenFaces, Loading};
use scene::GranularScene;

pub use build::{contact_params, fracture_params, pipeline};
pub use explain::explain;
pub use fracture::Comminution;
pub use step::{ADAPT_PER_SAFETY, STABILITY_EVERY};

/// A granular run: the generic runner over the granular model.
pub type Simulation = Runner<Granular>;

/// The granular model: its scene section, the pipeline and integrator built from it, and the
/// persistent state.
pub struct Granular {
    pub cfg: GranularScene,
    pub pipeline: BodyPipeline,
    pub integrator: VelocityVerlet,
    /// Gravity (m/s²) with the `gravity` effect, for the energy account.
    pub gravity: Option<Vec3>,
    /// `output.report_strains` or the default list, before the loading picks those it
    /// reaches (see [`Granular::report_strains`]).
    strains_asked: Vec<f64>,
    /// The grains' total volume (m³) at a body count (see `fault`); not state.
    solid_volume: std::cell::Cell<Option<(usize, f64)>>,
    pub state: GranularState,
}

/// What a checkpoint keeps of a granular run (with the pipeline's contact history).
#[derive(Clone, Serialize, Deserialize)]
pub struct GranularState {
    pub bodies: Bodies,
    pub walls: Walls,
    /// Forces and torques of the last evaluation (at the current positions).
    pub forces: Forces,
    pub loading: Loading,
    pub sample: SampleInfo,
    /// Box height at the start of loading (m), the reference of the axial strain.
    pub height0: f64,
    /// The Rayleigh critical step the first step derives from (s).
    pub dt_rayleigh: f64,
    /// The step's policy and record: checked after every step, or with fracture and
    /// `time.dt = "auto"` every [`STABILITY_EVERY`] steps and shortened to
    /// [`ADAPT_PER_SAFETY`] × `time.safety` as pieces stiffen; the largest `ω dt` seen, the
    /// shortenings, a collapse.
    pub step_control: StepControl,
    /// Particle fracture and cohesion (the `fracture` effect), its energy account and the
    /// pieces' masses at the report strains.
    pub fracture: Option<GrainFracture>,
    pub energy: Option<EnergyAccount>,
    pub psd: Vec<(f64, Vec<(f64, f64)>)>,
    /// How far comminution has gone at the start and at each report strain reached.
    pub comminution: Vec<Comminution>,
    /// The state loading starts from: the mean stress on the walls (Pa, compression
    /// positive) and the mean coordination number (contacts per body, a wall contact counting
    /// once), at the first force evaluation.
    pub initial: [f64; 2],
    /// The faces a host drives from outside once it has set their speeds: from then on they,
    /// not `loading`, move the box (see [`GranularState::loading`]).
    pub driven: Option<DrivenFaces>,
}

impl GranularState {
    /// The scene's loading while it moves the boundaries; `None` once a host drives the faces.
    pub fn loading(&self) -> Option<&dyn BoxLoading> {
        self.driven.is_none().then(|| self.loading.as_loading())
    }

    /// Whether every per-body array (bodies, forces, fracture) has one entry per body, the
    /// springs and pieces point at bodies and grains that exist, and the bodies, walls and
    /// forces hold finite values; checked on a restored state before it is stepped.
    fn check_lengths(&self) -> std::result::Result<(), String> {
        let n = self.bodies.len();
        self.bodies.check_lengths()?;
        crate::state::check_lengths(
            n,
            &[
                ("force", self.forces.force.len()),
                ("torque", self.forces.torque.len()),
            ],
        )?;
        self.fracture
            .as_ref()
            .map_or(Ok(()), |f| f.check_lengths(n))?;
        self.bodies.check_values()?;
        self.walls.check_values()?;
        let finite = |v: &[Vec3]| v.iter().all(|x| x.iter().all(|c| c.is_finite()));
        if !(finite(&self.forces.force) && finite(&self.forces.torque)) {
            return Err("a force or torque is not finite".into());
        }
        if !(self.height0.is_finite() && self.dt_rayleigh.is_finite()) {
            return Err("the reference height or the Rayleigh step is not finite".into());
        }
        Ok(())
    }
}
