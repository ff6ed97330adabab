//! The `beam2d` model's run (Kun, D'Addetta, Herrmann and Ramm, 1999): rigid Voronoi
//! polygons that repel where they overlap and are held together by breakable beams.
//!
//! ```text
//! predict / kick_drift     positions at t + dt (Gear5 or velocity Verlet)
//! loading.prescribe        driven boundary layers to their exact place
//! pipeline.evaluate        contact and beam forces at t + dt; beams break by Eq. 13
//! correct / kick           velocities (and Gear's higher derivatives) at t + dt
//! probes                   a row of series.csv every `output.every` steps
//! ```
//!
//! The explosion and the projectile stop once `quiet_steps` steps pass without a beam
//! breaking; the moduli test stretches the sample, then starts again from the same initial
//! state and compresses it.

pub mod accuracy;
pub mod bench;
mod build;
mod explain;
pub mod loading;
mod model;
pub mod pipeline;
mod report;
pub mod scene;

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value, json};

use crate::bond::beam2d::Beams;
use crate::contact::overlap_area_2d::characteristic_length;
use crate::error::{Error, Result};
use crate::integrate::{Gear5, kick_dofs, kick_drift_dofs};
use crate::output::vtk_polygons::{beams_vtu, polygons_vtu};
use crate::probe::Series;
use crate::probe::fragments::{
    PowerLawFit, bootstrap_interval, components, mass_histogram, sum_by_component,
};
use crate::run::{Built, Clock, Model, RunInfo, Runner};
use crate::sample::lattice2d::{
    LatticeInfo, LatticeSpec, PolygonSample, STREAM_LATTICE, vectorizable_random_lattice,
};
use crate::scene::{EffectKind, IntegratorKind, Scene};
use crate::shape::polygon::Vec2;
use crate::state::Vec3;
use crate::state::polygons::Polygons;
use loading::Beam2dLoading;
use pipeline::PolygonPipeline;
use scene::Beam2dScene;

pub use explain::explain;
pub use report::{
    averaged_power_law, averaged_power_law_by, averaged_power_law_interval, mean_polygon_mass,
    pooled_fragment_masses,
};
pub use scene::EFFECTS as BEAM2D_EFFECTS;

/// A beam2d run: the generic runner over the beam2d model.
pub type Beam2dRun = Runner<Beam2d>;

/// The integrator of a beam2d run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Integrator2d {
    VelocityVerlet,
    Gear5(Gear5),
}

/// The initial positions and velocities, kept for the moduli test's second phase.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StartState {
    q: Vec<[f64; 3]>,
    v: Vec<[f64; 3]>,
}

/// The beam2d model: its scene section and force pipeline, and the persistent state.
pub struct Beam2d {
    pub cfg: Beam2dScene,
    pub pipeline: PolygonPipeline,
    pub state: Beam2dState,
}

/// What a checkpoint keeps of a beam2d run.
#[derive(Clone, Serialize, Deserialize)]
pub struct Beam2dState {
    pub polygons: Polygons,
    pub beams: Beams,
    /// Forces and torques `[F_x, F_y, M]` of the last evaluation.
    pub forces: Vec<[f64; 3]>,
    pub integrator: Integrator2d,
    pub loading: Beam2dLoading,
    pub info: LatticeInfo,
    /// Mean polygon mass of the sample as built (kg): the unit of fragment masses.
    pub mean_polygon_mass: f64,
    /// Estimated stability limit of velocity Verlet, 2/ω of the stiffest polygon (s).
    pub dt_critical: f64,
    pub steps_since_break: u64,
    /// Overlapping pairs in the last evaluation.
    pub contacts: usize,
    /// Total momentum at the start, Σ m|v| at the start, and the largest |P − P0| / Σ m|v|
    /// seen at the output steps (free loadings).
    pub momentum0: Vec2,
    pub momentum_scale: f64,
    pub max_momentum_drift: f64,
    pub initial_kinetic_energy: f64,
    start: Option<StartState>,
}

impl Beam2d {
    /// Forces at the current state (time `time`, step `dt`), and Gear's derivatives started
    /// from them.
    fn restart_dynamics(&mut self, time: f64, dt: f64) {
        let st = &mut self.state;
        st.loading.as_loading().prescribe(time, &mut st.polygons);
        let counts = self
            .pipeline
            .evaluate(&st.polygons, &mut st.beams, time, &mut st.forces);
        st.contacts = counts.contacts;
        if let Integrator2d::Gear5(g) = &mut st.integrator {
            g.start(
                st.forces.as_flattened(),
                st.polygons.inv_m.as_flattened(),
                dt,
            );
        }
    }

    /// Whether the loading's current phase ends at this step and another follows.
    fn phase_ends(&self, clock: &Clock) -> bool {
        let loading = self.state.loading.as_loading();
        loading.phase_end(clock.end_step) == Some(clock.step)
    }

    /// The loading's next phase: back to the initial state, then on from there (the moduli
    /// test's compression).
    fn start_next_phase(&mut self, clock: &Clock) {
        let st = &mut self.state;
        let start = st.start.as_ref().expect("kept for a loading that restarts");
        st.polygons.q.clone_from(&start.q);
        st.polygons.v.clone_from(&start.v);
        st.loading.as_loading_mut().next_phase(clock.time);
        self.restart_dynamics(clock.time, clock.dt);
    }
}
