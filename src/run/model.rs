//! What a model supplies to the runner: its physics, its reports and, for embedders, its
//! bodies and driven faces.

use serde::de::DeserializeOwned;
use serde_json::{Map, Value};

use crate::error::Result;
use crate::probe::Series;
use crate::scene::{EffectKind, IntegratorKind, Scene};
use crate::state::{Bodies, Vec3};

use super::Clock;

/// A model as built from its scene, with what the runner needs to start it.
pub struct Built<M> {
    pub model: M,
    /// The clock the run starts from ([`Clock::planned`]: its step, end step and end time).
    pub clock: Clock,
    /// The columns of series.csv.
    pub columns: Vec<&'static str>,
    /// Warnings found while building.
    pub warnings: Vec<String>,
}

/// What a model's summary may read besides the model.
pub struct RunInfo<'a> {
    pub scene: &'a Scene,
    pub clock: &'a Clock,
    pub series: &'a Series,
}

/// The top (z+) and bottom (z-) faces of a box that a host drives from outside (the SHPB
/// bars of the FMU and the C ABI). Only models with such faces have them.
pub trait Faces {
    /// Drives the faces from now on at `top` and `bottom` m/s into the sample (compression
    /// positive). Use [`super::Run::set_face_speeds`], which also lifts the run's end.
    fn drive(&mut self, top: f64, bottom: f64) -> Result<()>;
    /// Compressive normal force (N) on the top and bottom faces.
    fn face_forces(&self) -> (f64, f64);
    /// Compressive normal stress (Pa) on the top and bottom faces.
    fn face_stresses(&self) -> (f64, f64);
    /// Area (m²) of the top and bottom faces.
    fn face_area(&self) -> f64;
    /// Axial strain of the box between the faces (compression positive).
    fn axial_strain(&self) -> f64;
}

/// A model: the scene it reads (its kind, its keys, their checks) and, through its parts, its
/// physics ([`Physics`]), its reports ([`Report`]) and its bodies as embedders see them
/// ([`BodiesView`]). Everything about time, outputs and checkpoints is the runner's.
pub trait Model: Physics + Report + BodiesView {
    /// `model.kind` of its scenes.
    const KIND: &'static str;

    /// What one body is called in messages ("body", "element", "polygon").
    const BODY: &'static str;

    /// The model's own tables of a scene (material, sample, loading, ...) as serde reads
    /// them, before any check: only the registry reads this form (to name a key another
    /// model has), and only [`Model::config`] turns it into the model's scene.
    type Raw: DeserializeOwned;

    /// The effects, integrators and shared model-specific keys (`time.phi`,
    /// `output.report_strains`) the model has; the registry refuses the others by name.
    const EFFECTS: &'static [EffectKind];

    const INTEGRATORS: &'static [IntegratorKind];

    const SHARED_KEYS: &'static [&'static str];

    /// Range checks and what goes with what, once the raw tables have been read: the typed
    /// scene, or the first failing key named.
    fn config(scene: &Scene, raw: &Self::Raw) -> Result<Self::Config>;

    /// The model's typed scene of `scene`: its tables read and checked. The one place a
    /// model's scene is read: the runner reads it once, when it builds or restores a run.
    fn read(scene: &Scene) -> Result<Self::Config> {
        Self::config(scene, &scene.section()?)
    }

    /// `fractum explain`: what the scene builds, without building it.
    fn explain(scene: &Scene, cfg: &Self::Config) -> Result<String>;
}

/// A model's physics as the runner drives it: built from its typed scene, saved and restored,
/// one step at a time and the checks after each; a step it needs changed is returned, never
/// written (the runner alone writes the clock).
pub trait Physics: Send + Sized {
    /// The model's scene, typed and checked: what [`Physics::build`], [`Physics::restore`] and
    /// [`Model::explain`] take, read once per run ([`Model::read`]).
    type Config: Send;

    /// How many of the run's `threads` the step's parallel regions run on, as the run's worker
    /// team ([`crate::parallel::Team`], awake while the run advances); 1: on rayon or the
    /// caller alone. As many as pay, not all or none: a step with work for five threads on a
    /// run of sixteen takes five.
    fn team_members(&self, _threads: usize) -> usize {
        1
    }

    /// How many of the run's `threads` build the model as its worker team (the sample's
    /// preparation); 1: on rayon or the caller alone.
    fn build_members(_threads: usize) -> usize {
        1
    }

    /// Builds the model a scene describes, from its typed scene (runs on the run's threads).
    fn build(
        scene: &Scene,
        cfg: Self::Config,
        progress: &mut (dyn FnMut(&str) + Send),
    ) -> Result<Built<Self>>;

    /// The model's own persistent state, for a checkpoint.
    fn save(&self) -> Vec<u8>;

    /// The model rebuilt from its scene, its typed scene and the bytes [`Physics::save`] wrote.
    fn restore(scene: &Scene, cfg: Self::Config, bytes: &[u8]) -> Result<Self>;

    /// Number of bodies (particles, elements, polygons).
    fn bodies(&self) -> usize;

    /// One step of `dt` from `clock` (the clock is advanced by the runner afterwards).
    fn step(&mut self, clock: &Clock, dt: f64);

    /// After the clock has moved: work that needs the new time (granular fracture). Returns
    /// the step (s) to take from now on when it must change (pieces stiffer than the step),
    /// which the runner writes into its clock; `None`: keep it.
    fn after_step(&mut self, _clock: &Clock, _dt: f64) -> Option<f64> {
        None
    }

    /// True once the model has ended the run early (failure, quiet steps).
    fn stopped(&self) -> bool {
        false
    }

    /// Output steps of the model's own besides the regular ones (a phase's end).
    fn output_due(&self, _clock: &Clock) -> bool {
        false
    }

    /// After every step, once the state is known to be finite and before any row: stability
    /// checks and step adaptation, the new step returned as by [`Physics::after_step`]. Every step, not at output steps only: a granular run that
    /// adapted its step at output steps only took 50 steps between checks with the scene's
    /// `output.every = 50`, its contacts stiffened unseen, and its step collapsed from
    /// 1.1e-7 s to 1.8e-12 s (a run that never ended) where `output.every = 1` finished in
    /// 1.3 s: the result depended on how often one wrote output.
    fn check_step(
        &mut self,
        _scene: &Scene,
        _clock: &Clock,
        _warn: &mut Vec<String>,
    ) -> Result<Option<f64>> {
        Ok(None)
    }

    /// After a row is recorded (stop on failure, switch phases).
    fn after_row(&mut self, _clock: &Clock, _series: &Series) {}

    /// The first body whose position or velocity is not finite.
    fn first_non_finite(&self) -> Option<usize>;

    /// What to change when the run turned non-finite (one clause).
    fn instability_hint(&self, scene: &Scene, clock: &Clock) -> String;

    /// Checked after every step, after the finiteness check: a state the model cannot
    /// describe any more though still finite (granular: grains packed beyond full density),
    /// as a clause saying what and what to change. Must be cheap.
    fn fault(&self, _clock: &Clock) -> Option<String> {
        None
    }

    /// Whether a step may be shortened to land on a requested time.
    fn variable_step(&self) -> bool {
        true
    }
}

/// What a model reports: the series row (its columns are given at build, [`Built::columns`]),
/// its own summary keys, VTK snapshots, extra result files and a status line.
pub trait Report {
    /// The series row now.
    fn row(&mut self, clock: &Clock) -> Vec<f64>;

    /// The model's summary keys, after those every model shares.
    fn summary(&self, run: &RunInfo, m: &mut Map<String, Value>);

    /// VTK files of the current state as (stem, .vtu text).
    fn snapshot(&self) -> Vec<(&'static str, String)>;

    /// Further result files written at the end, as (file name, content).
    fn extra_outputs(&self) -> Vec<(String, Vec<u8>)> {
        Vec::new()
    }

    /// A short line for the progress bar.
    fn status(&self, clock: &Clock) -> String {
        format!("t = {:.4e} s", clock.time)
    }
}

/// A model's bodies as hosts that embed a run see them (the C ABI, the FMU, exports): centres,
/// velocities, orientations, radii, grain loads, contacts, kinetic energy, and the driven faces
/// for models that have them. Each has a default from [`BodiesView::rigid_bodies`] or none.
pub trait BodiesView {
    /// The bodies of a model whose elements are rigid 3D bodies ([`Bodies`]); the per-body
    /// copies below come from them unless a model gives its own.
    fn rigid_bodies(&self) -> Option<&Bodies> {
        None
    }

    /// Body centres (m), velocities (m/s) and orientations (unit quaternions w, x, y, z);
    /// a 2D model gives z = 0 and rotations about z.
    fn positions(&self) -> Vec<Vec3> {
        self.rigid_bodies().map_or_else(Vec::new, |b| b.pos.clone())
    }

    fn velocities(&self) -> Vec<Vec3> {
        self.rigid_bodies().map_or_else(Vec::new, |b| b.vel.clone())
    }

    fn orientations(&self) -> Vec<[f64; 4]> {
        self.rigid_bodies().map_or_else(Vec::new, |b| {
            b.orientation.iter().map(|q| [q.w, q.i, q.j, q.k]).collect()
        })
    }

    /// Body radii (m; the bounding radius of non-spherical bodies), for models of round
    /// grains.
    fn radii(&self) -> Option<Vec<f64>> {
        None
    }

    /// What each grain's contacts loaded it with at the last fracture check (see
    /// [`crate::fracture::GrainFracture::loads`]), one per body, for models with grain
    /// fracture.
    fn grain_loads(&self) -> Option<Vec<crate::fracture::GrainLoad>> {
        None
    }

    /// Body–body contacts now, for models that count them.
    fn contacts(&self) -> Option<usize> {
        None
    }

    /// Kinetic energy (J) now.
    fn kinetic_energy(&self) -> f64 {
        self.rigid_bodies().map_or(f64::NAN, |b| b.kinetic_energy())
    }

    /// The driven faces, for models that have them.
    fn faces_mut(&mut self) -> Option<&mut dyn Faces> {
        None
    }

    fn faces(&self) -> Option<&dyn Faces> {
        None
    }
}
