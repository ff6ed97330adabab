//! What every model's run shares, written once: the clock, advancing by steps or to a time,
//! the output cadence, the finiteness watchdog, series rows, checkpoints and the thread pool.
//!
//! A model ([`Model`]) supplies its physics (build, one step, hooks at output steps), its
//! series row, summary and snapshot; [`Runner`] drives any model and implements [`Run`], the
//! interface of the driver, the CLI, the C ABI and checkpoints. The registry
//! (`crate::models`) picks the model from `model.kind`.
//!
//! ```text
//! advance:   while step < target and the model has not stopped:
//!              model.step(clock, dt)          the physics of one step
//!              clock: step + 1, time + dt
//!              model.after_step(clock)        e.g. granular fracture, which may shorten dt
//!              finite? -> model.fault -> model.check_step (stability, step adaptation)
//!              at output steps (every `output.every`, the last, and those the model asks):
//!                series row -> model.after_row
//! ```

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value, json};

use crate::error::{Error, Result};
use crate::parallel::Threads;
use crate::probe::Series;
use crate::scene::{EffectKind, IntegratorKind, Scene};
use crate::state::{Bodies, Vec3};

/// Where a run is in time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Clock {
    /// Time (s).
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// Time step (s).
    pub dt: f64,
    /// The step at which the run ends (`u64::MAX`: driven from outside, no end of its own).
    pub end_step: u64,
    /// The time (s) at which the run ends (infinite: driven from outside): a new step keeps
    /// it ([`Clock::set_dt`]).
    pub end_time: f64,
}

impl Clock {
    /// Steps of `dt` (s) from now on: the run still ends at its end time, in steps of the new
    /// length, none once the end time is reached (a shortening at the last step used to add
    /// one step, and another at that one another: runs overran their end strain).
    pub fn set_dt(&mut self, dt: f64) {
        self.dt = dt;
        if self.end_step == u64::MAX {
            return;
        }
        let remaining = self.end_time - self.time;
        self.end_step = if remaining > 1e-9 * dt {
            self.step.saturating_add(end_step(remaining, dt))
        } else {
            self.step
        };
    }

    /// The time (s) left to the end.
    pub fn remaining(&self) -> f64 {
        self.end_time - self.time
    }
}

/// The most steps a run may plan to its end: at a microsecond per step (a tiny scene) that is
/// 17 minutes, at the main job's milliseconds weeks. A scene that asks for more (a step of
/// 1e-300 s, or a Young's modulus of 1e308 Pa under `time.dt = "auto"`) used to plan
/// 18446744073709551615 steps and run forever.
pub const MAX_STEPS: f64 = 1e9;

/// Below this Young's modulus (Pa) a step too long for the loading is the material's fault
/// (softer than any solid that breaks); above it the loading is too short (a strain rate of
/// 1e308/s) or the grains or elements too large (a DLSM bar 1e9 m long), and the message says
/// so instead of asking for a stiffer material.
const YOUNG_SOFTEST: f64 = 1e6;

/// The fewest steps a run under `time.dt = "auto"` may plan to its end: its step may be at most
/// half the loading, so that the end is overshot by at most half of it.
pub const MIN_STEPS: f64 = 2.0;

/// Refuses a loading of `end_time` seconds at steps of `dt` seconds that needs more than
/// [`MAX_STEPS`] steps, naming `time.dt`; an endless loading (driven from outside) passes.
/// `young` is the model's `material.young` (Pa), which the critical step scales with as
/// 1/√young in every model: the messages name it when it is at fault.
pub fn check_planned_steps(scene: &Scene, young: f64, end_time: f64, dt: f64) -> Result<()> {
    if end_time.is_infinite() && end_time > 0.0 {
        return Ok(());
    }
    let steps = end_time / dt;
    let auto = matches!(scene.time.dt, crate::scene::DtSpec::Auto);
    if auto && steps.is_finite() && steps < MIN_STEPS && end_time > 0.0 {
        // A step across most of the loading is no run: shpb_sand with a Young's modulus of
        // 1e3 Pa and a short loading took one step to 7 times its end strain and exited 0
        // with a 72% energy error, and the advice named time.safety where the modulus was at
        // fault. Under "auto" the user did not choose the step: the material (or the
        // loading) is at fault. A step given in seconds is the user's own, and tests give a
        // long one on purpose to see a run go unstable.
        let longest = end_time / MIN_STEPS;
        // The critical step grows as 1/√young: the modulus that gives `longest`.
        let young_needed = (dt * young.sqrt() / longest).powi(2);
        return Err(if young >= YOUNG_SOFTEST {
            scene.key_error(
                "time.dt",
                format!(
                    "= \"auto\" gives a step of {dt:.3e} s (time.safety x the critical step of the \
                     material, material.young = {young:e} Pa, and the sample's grains or \
                     elements), and the loading ends at {end_time:.3e} s: {steps:.2} steps, fewer \
                     than {MIN_STEPS}; the loading is too short or the grains or elements too large \
                     for this material: allowed: a loading that lasts at least {:.3e} s (check its \
                     rate and its end), or time.dt in seconds of at most {longest:.3e} s",
                    dt * MIN_STEPS
                ),
            )
        } else if !dt.is_finite() || !young_needed.is_finite() {
            // A modulus such as 5e-324 Pa gives an infinite step: "material.young >= inf
            // Pa" said nothing.
            scene.key_error(
                "material.young",
                format!(
                    "= {young:e} Pa is too soft for time.dt = \"auto\": the step comes out as \
                     {dt:e} s (it grows as 1/√young), and the loading ends at {end_time:.3e} s; \
                     allowed: a material.young for which the step is at most half the loading \
                     (a solid's modulus, 1e6 Pa and up)"
                ),
            )
        } else {
            scene.key_error(
                "material.young",
                format!(
                    "= {young:e} Pa is too soft for this loading under time.dt = \"auto\": the step comes out as {dt:.3e} s, and the loading (its end at {end_time:.3e} s) would take {steps:.2} steps, fewer than {MIN_STEPS}; allowed: material.young >= {young_needed:.3e} Pa at this loading and time.safety, or a loading that lasts at least {:.3e} s",
                    dt * MIN_STEPS
                ),
            )
        });
    }
    if steps.is_finite() && steps <= MAX_STEPS {
        return Ok(());
    }
    if auto && !dt.is_normal() {
        // The critical step scales as 1/sqrt(young): a modulus near the largest double gives a
        // zero or denormal step, and "time.dt = 0 s needs inf steps" blamed the wrong key.
        return Err(scene.key_error(
            "material.young",
            format!(
                "= {young:e} Pa is too stiff for time.dt = \"auto\": the critical step of the material and sample comes out as {dt:e} s (zero or denormal), which cannot reach the end of the loading at {end_time:.4e} s within the limit of 1e9 steps; lower material.young"
            ),
        ));
    }
    let how = match scene.time.dt {
        crate::scene::DtSpec::Auto => {
            " (auto: time.safety x the critical step of the material and sample)"
        }
        crate::scene::DtSpec::Seconds(_) => "",
    };
    Err(scene.key_error(
        "time.dt",
        format!(
            "= {dt:.4e} s{how} needs {steps:.2e} steps to reach the end of the loading at {end_time:.4e} s, more than the limit of 1e9 steps: check time.dt, the material's stiffness and the loading"
        ),
    ))
}

/// A restored clock against the limits a built run is held to: a run with an end ends within
/// [`MAX_STEPS`] steps of its step and at the step its end time gives (to 1% and two steps:
/// a variable step moves both); one without an end (driven from outside) has neither. A
/// re-sealed checkpoint with `end_step = 2^64 − 1` resumed past the limit, `step > end_step`
/// printed a wrapped step count, and `dt = 1e-300` exited 0 without advancing.
fn check_restored_clock(c: &Clock) -> std::result::Result<(), String> {
    let endless = c.end_time.is_infinite() && c.end_time > 0.0;
    if endless != (c.end_step == u64::MAX) {
        return Err(format!(
            "ends at step {} but at t = {:e} s (a run driven from outside has neither end, any \
             other both)",
            c.end_step, c.end_time
        ));
    }
    if endless {
        return Ok(());
    }
    if !c.end_time.is_finite() {
        return Err(format!("ends at t = {:e} s", c.end_time));
    }
    if c.step > c.end_step {
        return Err(format!(
            "is at step {}, past the run's end at step {}",
            c.step, c.end_step
        ));
    }
    let left = (c.end_step - c.step) as f64;
    let planned = (c.remaining() / c.dt).max(0.0);
    if left > MAX_STEPS || planned > MAX_STEPS {
        return Err(format!(
            "has {left:.4e} steps of {:e} s left to its end at t = {:e} s, more than the limit \
             of 1e9 steps",
            c.dt, c.end_time
        ));
    }
    if (left - planned).abs() > 2.0 + 0.01 * left.max(planned) {
        return Err(format!(
            "has {left} steps left to its end at step {}, but {planned:.4e} steps of {:e} s to \
             its end at t = {:e} s",
            c.end_step, c.dt, c.end_time
        ));
    }
    Ok(())
}

/// The step at which a loading of `end_time` seconds ends (unbounded for an endless one).
pub fn end_step(end_time: f64, dt: f64) -> u64 {
    if end_time.is_finite() {
        (end_time / dt - 1e-9).ceil().max(1.0) as u64
    } else {
        u64::MAX
    }
}

/// A model as built from its scene, with what the runner needs to start it.
pub struct Built<M> {
    pub model: M,
    /// Time step (s), the step and the time (s) at which the run ends.
    pub dt: f64,
    pub end_step: u64,
    pub end_time: f64,
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
    /// positive). Use [`Run::set_face_speeds`], which also lifts the run's end.
    fn set_face_speeds(&mut self, top: f64, bottom: f64) -> Result<()>;
    /// Compressive normal force (N) on the top and bottom faces.
    fn face_forces(&self) -> (f64, f64);
    /// Compressive normal stress (Pa) on the top and bottom faces.
    fn face_stresses(&self) -> (f64, f64);
    /// Area (m²) of the top and bottom faces.
    fn face_area(&self) -> f64;
    /// Axial strain of the box between the faces (compression positive).
    fn axial_strain(&self) -> f64;
}

/// A model's physics, as the runner drives it. Everything about time, outputs and
/// checkpoints is the runner's.
pub trait Model: Send + Sized {
    /// `model.kind` of its scenes.
    const KIND: &'static str;
    /// What one body is called in messages ("body", "element", "polygon").
    const BODY: &'static str;
    /// The model's own tables of a scene (material, sample, loading, ...) as serde reads
    /// them, before any check: only the registry reads this form (to name a key another
    /// model has), and only [`Model::config`] turns it into the model's scene.
    type Raw: DeserializeOwned;
    /// The model's scene, typed and checked: what [`Model::build`], [`Model::restore`] and
    /// [`Model::explain`] take, read once per run ([`Model::read`]).
    type Config: Send;
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

    /// How many of the run's `threads` the step's parallel regions run on, as the run's worker
    /// team ([`crate::parallel::Team`], awake while the run advances); 1: on rayon or the
    /// caller alone. As many as pay, not all or none: a step with work for five threads on a
    /// run of sixteen takes five.
    fn team_members(&self, _threads: usize) -> usize {
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
    /// The model rebuilt from its scene, its typed scene and the bytes [`Model::save`] wrote.
    fn restore(scene: &Scene, cfg: Self::Config, bytes: &[u8]) -> Result<Self>;

    /// Number of bodies (particles, elements, polygons).
    fn bodies(&self) -> usize;
    /// One step of `dt` from `clock` (the clock is advanced by the runner afterwards).
    fn step(&mut self, clock: &Clock, dt: f64);
    /// After the clock has moved: work that needs the new time and may change the step or
    /// the end (granular fracture).
    fn after_step(&mut self, _clock: &mut Clock, _dt: f64) {}
    /// True once the model has ended the run early (failure, quiet steps).
    fn stopped(&self) -> bool {
        false
    }
    /// Output steps of the model's own besides the regular ones (a phase's end).
    fn output_due(&self, _clock: &Clock) -> bool {
        false
    }
    /// After every step, once the state is known to be finite and before any row: stability
    /// checks and step adaptation. Every step, not at output steps only: a granular run that
    /// adapted its step at output steps only took 50 steps between checks with the scene's
    /// `output.every = 50`, its contacts stiffened unseen, and its step collapsed from
    /// 1.1e-7 s to 1.8e-12 s (a run that never ended) where `output.every = 1` finished in
    /// 1.3 s: the result depended on how often one wrote output.
    fn check_step(
        &mut self,
        _scene: &Scene,
        _clock: &mut Clock,
        _warn: &mut Vec<String>,
    ) -> Result<()> {
        Ok(())
    }
    /// The series row now.
    fn row(&mut self, clock: &Clock) -> Vec<f64>;
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
    /// Body centres, velocities and orientations (see [`Model::positions`]).
    fn positions(&self) -> Vec<Vec3>;
    fn velocities(&self) -> Vec<Vec3>;
    fn orientations(&self) -> Vec<[f64; 4]>;
    /// Body radii (m), for models of round grains (see [`Model::radii`]).
    fn radii(&self) -> Option<Vec<f64>>;
    /// The grains' loads at the last fracture check (see [`Model::grain_loads`]).
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

/// Bounds on each `advance` / `advance_to` call, for hosts that embed a run (the C ABI):
/// a call stops with [`Error::Interrupted`] before a step once it has taken `max_steps` steps
/// or run `max_seconds` of wall time, or once `cancel` is set (from any thread; the stop
/// clears it). Always at a whole step: the run stays consistent and the next call goes on.
/// Not part of the saved state.
#[derive(Debug, Clone, Default)]
pub struct CallLimits {
    /// Most steps one call takes (0: no bound).
    pub max_steps: u64,
    /// Most wall-clock seconds one call runs (0: no bound).
    pub max_seconds: f64,
    /// Set to stop the call in progress, or the next one, before its next step.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl CallLimits {
    /// Whether a call ends by itself, whatever the run: a bound on its steps or its time.
    fn bounded(&self) -> bool {
        self.max_steps > 0 || self.max_seconds > 0.0
    }
}

/// One call's account against its [`CallLimits`].
struct Budget<'a> {
    limits: &'a CallLimits,
    start: std::time::Instant,
    steps: u64,
}

impl<'a> Budget<'a> {
    fn start(limits: &'a CallLimits) -> Self {
        Budget {
            limits,
            start: std::time::Instant::now(),
            steps: 0,
        }
    }

    /// Before each step: an interruption when a bound has run out, else counts the step.
    fn before_step(&mut self, clock: &Clock) -> Result<()> {
        let l = self.limits;
        let why = if l
            .cancel
            .as_ref()
            .is_some_and(|c| c.swap(false, Ordering::AcqRel))
        {
            Some("it was cancelled".to_string())
        } else if l.max_steps > 0 && self.steps >= l.max_steps {
            Some(format!(
                "its bound of {} steps per call ran out",
                l.max_steps
            ))
        } else if l.max_seconds > 0.0 && self.start.elapsed().as_secs_f64() >= l.max_seconds {
            Some(format!(
                "its bound of {} s of wall time per call ran out",
                l.max_seconds
            ))
        } else {
            None
        };
        if let Some(why) = why {
            return Err(Error::Interrupted(format!(
                "the call stopped after {} steps at step {} (t = {:e} s) because {why}; the run is consistent and the next call goes on from here",
                self.steps, clock.step, clock.time
            )));
        }
        self.steps += 1;
        Ok(())
    }
}

/// What a run's saved state ([`Run::save_state`]) starts with, and its format version.
const STATE_MAGIC: &[u8; 8] = b"FRACTUMS";
/// 2: dlsm states gained the Brazilian platens, the drop's size and the ground's total force.
/// 3: the ground contact gained its surface (plane or jaw), velocity and reach, the
/// Brazilian loading its arcs' pressure.
/// 4: the state names the scene it belongs to ([`SceneIdentity`]); grain fracture keeps the
/// seed of its keyed draws instead of a sequential stream.
/// 6: fracture constants gained the size exponent, the particle-strength reading and the
/// comminution limit; granular states keep how far comminution has gone at each report strain.
const STATE_VERSION: u32 = 6;

/// Which scene a saved state belongs to: a state restored under another scene took that
/// scene's parameters with its own bodies (a dlsm state of E = 1 GPa went on under a handle of
/// 20 GPa, a granular state of 58 bodies into a handle of 101, without a word).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SceneIdentity {
    /// `model.kind`, the scene's name and seed, and its effects (the FMU's fracture switch
    /// among them): what the refusal names.
    pub model: String,
    pub name: String,
    pub seed: u64,
    pub effects: Vec<String>,
    /// FNV-1a of everything that makes the run: the model, seed, effects, time and gravity
    /// keys and the model's own tables, overrides applied (not the output keys, nor comments
    /// and layout of the file).
    pub hash: u64,
}

impl SceneIdentity {
    pub fn of(scene: &Scene) -> SceneIdentity {
        let effects: Vec<String> = scene.effects.iter().map(|e| e.as_str().into()).collect();
        let tables = toml::to_string(&scene.tables).unwrap_or_default();
        let text = format!(
            "{}\n{}\n{:?}\n{:?}\n{:?}\n{tables}",
            scene.model.kind, scene.seed, effects, scene.time, scene.gravity
        );
        SceneIdentity {
            model: scene.model.kind.clone(),
            name: scene.name.clone(),
            seed: scene.seed,
            effects,
            hash: crate::output::sealed::checksum(text.as_bytes()),
        }
    }
}

impl std::fmt::Display for SceneIdentity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "a {} run of scene \"{}\" (seed {}, effects [{}], scene hash {:016x})",
            self.model,
            self.name,
            self.seed,
            self.effects.join(", "),
            self.hash
        )
    }
}

/// The runner's part of a checkpoint; the model's own bytes ride along.
#[derive(Serialize, Deserialize)]
struct RunnerState {
    scene: SceneIdentity,
    clock: Clock,
    series: Series,
    warnings: Vec<String>,
    last_row: Option<u64>,
    model: Vec<u8>,
}

/// One generic run over any [`Model`].
pub struct Runner<M> {
    pub scene: Scene,
    pub clock: Clock,
    pub series: Series,
    pub warnings: Vec<String>,
    pub model: M,
    /// The step of the last series row (rows are recorded once per step at most).
    last_row: Option<u64>,
    /// The run's worker threads (none: everything runs on the caller's thread).
    threads: Threads,
    /// Bounds on each advance call (not saved).
    limits: CallLimits,
}

impl<M> std::ops::Deref for Runner<M> {
    type Target = M;
    fn deref(&self) -> &M {
        &self.model
    }
}

impl<M> std::ops::DerefMut for Runner<M> {
    fn deref_mut(&mut self) -> &mut M {
        &mut self.model
    }
}

impl<M: Model> Runner<M> {
    /// Builds the model a scene describes and records the first row. `threads` = 0 uses
    /// every core.
    pub fn new(
        scene: Scene,
        threads: usize,
        progress: &mut (dyn FnMut(&str) + Send),
    ) -> Result<Self> {
        let cfg = M::read(&scene)?;
        let threads = Threads::new(threads)?;
        let built = threads.run(1, || M::build(&scene, cfg, progress))?;
        Runner::start(scene, built, threads)
    }

    /// Sets a run up on a model built elsewhere.
    pub fn from_built(scene: Scene, built: Built<M>, threads: usize) -> Result<Self> {
        Runner::start(scene, built, Threads::new(threads)?)
    }

    fn start(scene: Scene, built: Built<M>, threads: Threads) -> Result<Self> {
        let mut run = Runner {
            scene,
            clock: Clock {
                time: 0.0,
                step: 0,
                dt: built.dt,
                end_step: built.end_step,
                end_time: built.end_time,
            },
            series: Series::new(&built.columns),
            warnings: built.warnings,
            model: built.model,
            last_row: None,
            limits: CallLimits::default(),
            threads,
        };
        run.record_row()?;
        Ok(run)
    }

    /// Restores a run from the bytes [`Run::save_state`] wrote for this scene.
    pub fn restore(scene: Scene, bytes: &[u8], threads: usize) -> Result<Self> {
        let bytes =
            crate::output::sealed::open(bytes, STATE_MAGIC, STATE_VERSION).map_err(|why| {
                Error::run(format!(
                    "the saved {} state is not usable: it {why}",
                    M::KIND
                ))
            })?;
        let s: RunnerState = postcard::from_bytes(bytes).map_err(|e| {
            Error::run(format!(
                "the checkpoint's {} state is damaged ({e})",
                M::KIND
            ))
        })?;
        let ours = SceneIdentity::of(&scene);
        if s.scene != ours {
            let differs = if s.scene.name == ours.name && s.scene.seed == ours.seed {
                " with other keys or overrides"
            } else {
                ""
            };
            return Err(Error::run(format!(
                "the saved state belongs to another scene: it is the state of {}, this run is {ours}{differs}; restore a state into a run of the scene that saved it",
                s.scene
            )));
        }
        let c = &s.clock;
        if !(c.time.is_finite() && c.time >= 0.0 && c.dt.is_finite() && c.dt > 0.0) {
            return Err(Error::run(format!(
                "the saved {} state is inconsistent: its clock reads t = {:e} s with a step of {:e} s (a finite time from 0 and a positive finite step expected)",
                M::KIND,
                c.time,
                c.dt
            )));
        }
        check_restored_clock(c).map_err(|why| {
            Error::run(format!(
                "the saved {} state is inconsistent: its clock {why}",
                M::KIND
            ))
        })?;
        let cfg = M::read(&scene)?;
        let threads = Threads::new(threads)?;
        let model = threads.run(1, || M::restore(&scene, cfg, &s.model))?;
        if let Some(i) = model.first_non_finite() {
            return Err(Error::run(format!(
                "the saved {} state is inconsistent: {} {i} has a non-finite position or velocity",
                M::KIND,
                M::BODY
            )));
        }
        Ok(Runner {
            scene,
            clock: s.clock,
            series: s.series,
            warnings: s.warnings,
            model,
            last_row: s.last_row,
            limits: CallLimits::default(),
            threads,
        })
    }

    pub fn threads(&self) -> usize {
        self.threads.count()
    }

    /// Takes steps with `one` (which returns false when there is none left to take) on the
    /// run's threads, against one call's [`CallLimits`]. The model's choice of the worker team
    /// ([`Model::team_members`]) is read again after every step and the threads re-entered when it
    /// changes (a granular run of spheres gets its first poly-ellipsoid at a split): it follows
    /// the state, not how the caller cuts its run into `advance` calls. Before, it was read
    /// once per call: one `advance` over a whole run of spheres that break kept the pieces off
    /// the team to the end (the accuracy sweep's "two threads" ran on one), and a run's bits
    /// depended on where its calls began.
    fn stepping(
        &mut self,
        mut one: impl FnMut(&mut Self, &mut Budget) -> Result<bool> + Send,
    ) -> Result<()> {
        let threads = self.threads.clone();
        let limits = self.limits.clone();
        let mut budget = Budget::start(&limits);
        loop {
            let team = self.model.team_members(threads.count());
            let done = threads.run(team, || -> Result<bool> {
                loop {
                    if !one(self, &mut budget)? {
                        return Ok(true);
                    }
                    if self.model.team_members(threads.count()) != team {
                        return Ok(false);
                    }
                }
            })?;
            if done {
                return Ok(());
            }
        }
    }

    pub fn finished(&self) -> bool {
        self.clock.step >= self.clock.end_step || self.model.stopped()
    }

    /// Takes up to `steps` steps (never past the end), recording series rows on the way.
    /// Fails when the state stops being finite.
    pub fn advance(&mut self, steps: u64) -> Result<()> {
        // The end is read at every step, not once per call: a run that shortens its step
        // (granular fracture) moves its end step later while it advances, and a call for
        // `u64::MAX` steps stopped at the old end and returned with the run unfinished.
        let target = self.clock.step.saturating_add(steps);
        if self.clock.end_step == u64::MAX && steps as f64 > MAX_STEPS && !self.limits.bounded() {
            return Err(Error::run(format!(
                "cannot take {steps} steps in one call: this run has no end of its own (its faces are driven from outside) and more than the limit of 1e9 steps would run for days; advance by fewer steps, advance to a time, or bound the call (max_steps, max_seconds)"
            )));
        }
        self.stepping(|run, budget| {
            if run.clock.step >= target.min(run.clock.end_step) || run.model.stopped() {
                return Ok(false);
            }
            budget.before_step(&run.clock)?;
            run.step_by(run.clock.dt);
            run.after_step()?;
            Ok(true)
        })
    }

    /// Advances to exactly `time` (s): whole steps, then one shorter step that lands on it.
    /// The step size, not the distance to `time`, sets the accuracy. Series rows are recorded
    /// as in [`Runner::advance`]. Never past the end, as [`Runner::advance`]: a time beyond it
    /// stops at the end step ([`Runner::finished`]), short of `time`.
    pub fn advance_to(&mut self, time: f64) -> Result<()> {
        if !time.is_finite() || time < self.clock.time {
            return Err(Error::run(format!(
                "cannot advance to t = {time:e} s from t = {:e} s",
                self.clock.time
            )));
        }
        if !self.model.variable_step() {
            // Whole steps only: refuse a time off the grid before taking any step.
            let steps = (time - self.clock.time) / self.clock.dt;
            if (steps - steps.round()).abs() > 1e-9 * steps.max(1.0) {
                return Err(Error::run(format!(
                    "cannot land on t = {time:e} s: this run's integrator takes whole steps of {:e} s only, and t is {steps:.6} steps away",
                    self.clock.dt
                )));
            }
            return self.advance(steps.round() as u64);
        }
        // A remainder below this is rounding, not a step to take.
        let tiny = 1e-9 * self.clock.dt;
        self.stepping(|run, budget| {
            // The scene's end stops it as it stops `advance`: a time past the end used to drive
            // the loading on beyond it (platens past their end displacement).
            if time - run.clock.time <= tiny || run.finished() {
                return Ok(false);
            }
            budget.before_step(&run.clock)?;
            let h = (time - run.clock.time).min(run.clock.dt);
            if time - run.clock.time - h <= tiny {
                run.step_by(time - run.clock.time);
                run.clock.time = time;
            } else {
                run.step_by(h);
            }
            run.after_step()?;
            Ok(true)
        })
    }

    /// One step of `dt` (the run's step, or a shorter one that lands on a requested time).
    fn step_by(&mut self, dt: f64) {
        self.model.step(&self.clock, dt);
        self.clock.step += 1;
        self.clock.time += dt;
        self.model.after_step(&mut self.clock, dt);
    }

    /// After every step: check the state is finite (a pass over the bodies, cheap beside the
    /// step; at output steps only, a run driven with a long output interval went on stepping
    /// NaN and reported success), and let the model check its stability and adapt its step
    /// ([`Model::check_step`]). At output steps: record a series row. What a run computes
    /// does not depend on `output.every`, only what it writes.
    fn after_step(&mut self) -> Result<()> {
        if let Some(i) = self.model.first_non_finite() {
            return Err(Error::run(format!(
                "the run became unstable at step {} (t = {:e} s): {} {i} has a non-finite position or velocity; {}",
                self.clock.step,
                self.clock.time,
                M::BODY,
                self.model.instability_hint(&self.scene, &self.clock)
            )));
        }
        if let Some(why) = self.model.fault(&self.clock) {
            return Err(Error::run(format!(
                "the run stopped at step {} (t = {:e} s): {why}",
                self.clock.step, self.clock.time
            )));
        }
        self.model
            .check_step(&self.scene, &mut self.clock, &mut self.warnings)?;
        let c = &self.clock;
        let due = c.step % self.scene.output.every == 0
            || c.step == c.end_step
            || self.model.stopped()
            || self.model.output_due(c);
        if !due {
            return Ok(());
        }
        self.record_row()?;
        self.model.after_row(&self.clock, &self.series);
        Ok(())
    }

    /// Records the series row of this step. A row with a non-finite value stops the run: the
    /// bodies can be finite while what is measured from them is not (a beam2d projectile at
    /// 1e308 m/s has a finite velocity and an infinite kinetic energy), and series.csv got `inf`
    /// with exit code 0.
    fn record_row(&mut self) -> Result<()> {
        if self.last_row == Some(self.clock.step) {
            return Ok(());
        }
        self.last_row = Some(self.clock.step);
        let row = self.model.row(&self.clock);
        if let Some(c) = row.iter().position(|v| !v.is_finite()) {
            let hint = if self.clock.step == 0 {
                "the scene's initial state overflows: check the loading's speeds and energies"
                    .to_string()
            } else {
                self.model.instability_hint(&self.scene, &self.clock)
            };
            return Err(Error::run(format!(
                "the run stopped at step {} (t = {:e} s): the series column `{}` is {}, not a number series.csv can hold; {hint}",
                self.clock.step, self.clock.time, self.series.columns[c], row[c],
            )));
        }
        self.series.rows.push(row);
        Ok(())
    }
}

impl<M: Model> Run for Runner<M> {
    fn scene(&self) -> &Scene {
        &self.scene
    }
    fn model(&self) -> &'static str {
        M::KIND
    }
    fn bodies(&self) -> usize {
        self.model.bodies()
    }
    fn step(&self) -> u64 {
        self.clock.step
    }
    fn end_step(&self) -> u64 {
        self.clock.end_step
    }
    fn time(&self) -> f64 {
        self.clock.time
    }
    fn dt(&self) -> f64 {
        self.clock.dt
    }
    fn threads(&self) -> usize {
        Runner::threads(self)
    }
    fn finished(&self) -> bool {
        Runner::finished(self)
    }
    fn advance(&mut self, steps: u64) -> Result<()> {
        Runner::advance(self, steps)
    }
    fn advance_to(&mut self, time: f64) -> Result<()> {
        Runner::advance_to(self, time)
    }
    fn series(&self) -> &Series {
        &self.series
    }
    fn summary(&self) -> Value {
        let mut m = common_summary(self);
        let info = RunInfo {
            scene: &self.scene,
            clock: &self.clock,
            series: &self.series,
        };
        self.model.summary(&info, &mut m);
        Value::Object(m)
    }
    fn snapshot(&self) -> Vec<(&'static str, String)> {
        self.model.snapshot()
    }
    fn extra_outputs(&self) -> Vec<(String, Vec<u8>)> {
        self.model.extra_outputs()
    }
    fn save_state(&self) -> Vec<u8> {
        let state = RunnerState {
            scene: SceneIdentity::of(&self.scene),
            clock: self.clock,
            series: self.series.clone(),
            warnings: self.warnings.clone(),
            last_row: self.last_row,
            model: self.model.save(),
        };
        crate::output::sealed::seal(
            STATE_MAGIC,
            STATE_VERSION,
            &postcard::to_stdvec(&state).expect("the run's state serialises"),
        )
    }
    fn status(&self) -> String {
        self.model.status(&self.clock)
    }
    fn warnings(&self) -> &[String] {
        &self.warnings
    }
    fn positions(&self) -> Vec<Vec3> {
        self.model.positions()
    }
    fn velocities(&self) -> Vec<Vec3> {
        self.model.velocities()
    }
    fn orientations(&self) -> Vec<[f64; 4]> {
        self.model.orientations()
    }
    fn radii(&self) -> Option<Vec<f64>> {
        self.model.radii()
    }
    fn grain_loads(&self) -> Option<Vec<crate::fracture::GrainLoad>> {
        self.model.grain_loads()
    }
    fn contacts(&self) -> Option<usize> {
        self.model.contacts()
    }
    fn kinetic_energy(&self) -> f64 {
        self.model.kinetic_energy()
    }
    fn faces(&self) -> Option<&dyn Faces> {
        self.model.faces()
    }
    fn set_call_limits(&mut self, limits: CallLimits) {
        self.limits = limits;
    }
    fn set_face_speeds(&mut self, top: f64, bottom: f64) -> Result<()> {
        let faces = self.model.faces_mut().ok_or_else(|| {
            Error::run(format!(
                "a {} run has no driven faces: face speeds need a granular sample in a box",
                M::KIND
            ))
        })?;
        faces.set_face_speeds(top, bottom)?;
        self.clock.end_step = u64::MAX;
        self.clock.end_time = f64::INFINITY;
        Ok(())
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
