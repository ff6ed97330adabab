//! A run: state, force pipeline, integrator, loading and probes, and the step that ties them.
//!
//! ```text
//! loading.apply            set wall velocities
//! kick_drift               v(t+dt/2), x(t+dt); walls move
//! pipeline.accumulate      forces at t+dt (only the effects the scene names)
//! kick                     v(t+dt)
//! probes                   a row of series.csv every `output.every` steps
//! ```

use std::sync::Arc;

use serde_json::Value;

use crate::effects::{Pipeline, StepContext};
use crate::error::{Error, Result};
use crate::integrate::{VelocityVerlet, rayleigh_time_step};
use crate::loading::Loading;
use crate::output::vtk;
use crate::probe::{self, Series};
use crate::run::{self, Run};
use crate::sample::{self, Sample, SampleInfo};
use crate::scene::{DtSpec, Scene};
use crate::state::{Bodies, BoxFace, Forces, Walls};

pub struct Simulation {
    pub scene: Scene,
    pub bodies: Bodies,
    pub walls: Walls,
    /// Forces and torques of the last evaluation (at the current positions).
    pub forces: Forces,
    pub pipeline: Pipeline,
    pub integrator: VelocityVerlet,
    pub loading: Loading,
    pub series: Series,
    pub sample: SampleInfo,
    /// Time (s) and steps taken.
    pub time: f64,
    pub step: u64,
    /// Time step (s) and the Rayleigh critical step it derives from.
    pub dt: f64,
    pub dt_rayleigh: f64,
    /// The step at which the loading ends.
    pub end_step: u64,
    /// Box height at the start of loading (m), the reference of the axial strain.
    pub height0: f64,
    /// The largest `ω dt` seen at the output steps (see [`Simulation::check_stability`]).
    pub max_omega_dt: f64,
    /// Warnings for the user, in the order they arose.
    pub warnings: Vec<String>,
    /// The run's worker threads; `None` runs everything on the caller's thread.
    pool: Option<Arc<rayon::ThreadPool>>,
}

/// The persistent parts of a run, as a checkpoint stores them.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct RunState {
    pub bodies: Bodies,
    pub walls: Walls,
    pub forces: Forces,
    pub loading: Loading,
    pub series: Series,
    pub sample: SampleInfo,
    pub time: f64,
    pub step: u64,
    pub dt: f64,
    pub height0: f64,
    pub max_omega_dt: f64,
    pub warnings: Vec<String>,
    pub effects: Vec<(String, Vec<u8>)>,
}

/// The step at which a loading of `end_time` seconds ends (unbounded for an endless one).
fn end_step(end_time: f64, dt: f64) -> u64 {
    if end_time.is_finite() {
        (end_time / dt - 1e-9).ceil().max(1.0) as u64
    } else {
        u64::MAX
    }
}

/// Above this estimated `ω dt` a run stops, above the second it warns.
const OMEGA_DT_LIMIT: f64 = 2.0;
const OMEGA_DT_WARN: f64 = 1.6;

/// A pool of `threads` workers (0: one per core), or none for a single thread: then the run
/// stays on the caller's thread and never hands work across threads.
pub(crate) fn thread_pool(threads: usize) -> Result<Option<Arc<rayon::ThreadPool>>> {
    let threads = if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads
    };
    if threads <= 1 {
        return Ok(None);
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map(|p| Some(Arc::new(p)))
        .map_err(|e| Error::run(format!("cannot start {threads} worker threads ({e})")))
}

/// Runs `f` on the pool's threads, or right here without one.
pub(crate) fn on_threads<R: Send>(
    pool: &Option<Arc<rayon::ThreadPool>>,
    f: impl FnOnce() -> R + Send,
) -> R {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

impl Simulation {
    /// Builds the sample a scene describes and sets the run up. `threads` = 0 uses every core.
    pub fn new(
        scene: Scene,
        threads: usize,
        progress: &mut (dyn FnMut(&str) + Send),
    ) -> Result<Self> {
        let pool = thread_pool(threads)?;
        // Sample preparation may run dynamics (compaction): on the run's own threads.
        let s = on_threads(&pool, || sample::build(&scene, progress))?;
        Simulation::with_pool(scene, s, pool)
    }

    /// Sets a run up on a sample made elsewhere.
    pub fn from_sample(scene: Scene, sample: Sample, threads: usize) -> Result<Self> {
        Simulation::with_pool(scene, sample, thread_pool(threads)?)
    }

    fn with_pool(
        scene: Scene,
        sample: Sample,
        pool: Option<Arc<rayon::ThreadPool>>,
    ) -> Result<Self> {
        let Sample {
            bodies,
            walls,
            info,
        } = sample;
        let loading = Loading::from_scene(&scene, &walls)?;
        let height0 = if walls.is_box {
            walls.box_size().z
        } else {
            0.0
        };
        let mut sim = Simulation::assemble(scene, bodies, walls, loading, info, height0, pool)?;
        sim.evaluate_forces(false);
        sim.record_row();
        Ok(sim)
    }

    fn assemble(
        scene: Scene,
        bodies: Bodies,
        walls: Walls,
        loading: Loading,
        sample: SampleInfo,
        height0: f64,
        pool: Option<Arc<rayon::ThreadPool>>,
    ) -> Result<Self> {
        if bodies.is_empty() {
            return Err(scene.key_error("sample", "gives no bodies"));
        }
        let pipeline = Pipeline::build(&scene)?;
        let m = &scene.material;
        let dt_rayleigh = rayleigh_time_step(bodies.min_radius(), m.density, m.young, m.poisson);
        let dt = match scene.time.dt {
            DtSpec::Auto => scene.time.safety * dt_rayleigh,
            DtSpec::Seconds(s) => s,
        };
        let end_step = end_step(loading.end_time(), dt);
        let series = if walls.is_box {
            Series::new(&probe::BOX_COLUMNS)
        } else {
            Series::new(&probe::FREE_COLUMNS)
        };
        let forces = Forces::new(bodies.len());
        let sim = Simulation {
            scene,
            bodies,
            walls,
            forces,
            pipeline,
            integrator: VelocityVerlet::default(),
            loading,
            series,
            sample,
            time: 0.0,
            step: 0,
            dt,
            dt_rayleigh,
            end_step,
            height0,
            max_omega_dt: 0.0,
            warnings: Vec::new(),
            pool,
        };
        Ok(sim)
    }

    /// Restores a run from a checkpoint's scene and state.
    pub fn from_state(scene: Scene, state: RunState, threads: usize) -> Result<Self> {
        let mut sim = Simulation::assemble(
            scene,
            state.bodies,
            state.walls,
            state.loading,
            state.sample,
            state.height0,
            thread_pool(threads)?,
        )?;
        sim.pipeline.restore(&state.effects)?;
        sim.forces = state.forces;
        sim.series = state.series;
        sim.time = state.time;
        sim.step = state.step;
        sim.dt = state.dt;
        sim.max_omega_dt = state.max_omega_dt;
        sim.warnings = state.warnings;
        sim.end_step = end_step(sim.loading.end_time(), sim.dt);
        Ok(sim)
    }

    /// The persistent state, for a checkpoint.
    pub fn state(&self) -> RunState {
        RunState {
            bodies: self.bodies.clone(),
            walls: self.walls.clone(),
            forces: self.forces.clone(),
            loading: self.loading.clone(),
            series: self.series.clone(),
            sample: self.sample.clone(),
            time: self.time,
            step: self.step,
            dt: self.dt,
            height0: self.height0,
            max_omega_dt: self.max_omega_dt,
            warnings: self.warnings.clone(),
            effects: self.pipeline.save(),
        }
    }

    pub fn threads(&self) -> usize {
        self.pool.as_ref().map_or(1, |p| p.current_num_threads())
    }

    fn evaluate_forces(&mut self, update_history: bool) {
        let pool = self.pool.clone();
        on_threads(&pool, || {
            self.forces.clear();
            self.walls.clear_forces();
            let ctx = StepContext {
                dt: self.dt,
                update_history,
            };
            self.pipeline
                .accumulate(&ctx, &self.bodies, &mut self.walls, &mut self.forces);
        });
    }

    /// True once the loading has run its course.
    pub fn finished(&self) -> bool {
        self.step >= self.end_step
    }

    /// Takes up to `steps` steps (never past the end of the loading), recording series rows on
    /// the way. Fails when the state stops being finite.
    pub fn advance(&mut self, steps: u64) -> Result<()> {
        let target = self.step.saturating_add(steps).min(self.end_step);
        let pool = self.pool.clone();
        on_threads(&pool, || {
            while self.step < target {
                self.step_once();
                self.after_step()?;
            }
            Ok(())
        })
    }

    /// Every `output.every` steps (and at the end of the loading): check the state is finite
    /// and the time step short enough, and record a series row.
    fn after_step(&mut self) -> Result<()> {
        if self.step % self.scene.output.every == 0 || self.step == self.end_step {
            self.check_finite()?;
            self.check_stability()?;
            self.record_row();
        }
        Ok(())
    }

    fn step_once(&mut self) {
        self.step_by(self.dt);
    }

    /// One step of `dt` (the run's step, or a shorter one that lands on a requested time).
    fn step_by(&mut self, dt: f64) {
        self.loading.apply(&mut self.walls);
        self.integrator
            .kick_drift(&mut self.bodies, &self.forces, dt);
        self.walls.advance(dt);
        self.forces.clear();
        self.walls.clear_forces();
        let ctx = StepContext {
            dt,
            update_history: true,
        };
        self.pipeline
            .accumulate(&ctx, &self.bodies, &mut self.walls, &mut self.forces);
        self.integrator.kick(&mut self.bodies, &self.forces, dt);
        self.step += 1;
        self.time += dt;
    }

    /// Advances to exactly `time` (s): whole steps, then one shorter step that lands on it.
    /// The step size, not the distance to `time`, sets the accuracy. Series rows are recorded
    /// every `output.every` steps as in [`Simulation::advance`].
    pub fn advance_to(&mut self, time: f64) -> Result<()> {
        if !time.is_finite() || time < self.time {
            return Err(Error::run(format!(
                "cannot advance to t = {time:e} s from t = {:e} s",
                self.time
            )));
        }
        let pool = self.pool.clone();
        on_threads(&pool, || {
            // A remainder below this is rounding, not a step to take.
            let tiny = 1e-9 * self.dt;
            while time - self.time > tiny {
                let h = (time - self.time).min(self.dt);
                if time - self.time - h <= tiny {
                    self.step_by(time - self.time);
                    self.time = time;
                } else {
                    self.step_by(h);
                }
                self.after_step()?;
            }
            Ok(())
        })
    }

    /// Drives the top (z+) and bottom (z-) faces from outside from now on, at `top` and
    /// `bottom` m/s into the sample (compression positive); the run then has no end of its
    /// own. Needs a sample in a box.
    pub fn set_face_speeds(&mut self, top: f64, bottom: f64) -> Result<()> {
        if !self.walls.is_box {
            return Err(Error::run(
                "face speeds need a sample in a box (random, lattice or file packing)",
            ));
        }
        if !(top.is_finite() && bottom.is_finite()) {
            return Err(Error::run(format!(
                "face speeds must be finite, got top {top} and bottom {bottom} m/s"
            )));
        }
        self.loading = Loading::Faces { top, bottom };
        self.end_step = u64::MAX;
        Ok(())
    }

    /// Compressive normal force (N) on the top (z+) and bottom (z-) faces.
    pub fn face_forces(&self) -> (f64, f64) {
        if !self.walls.is_box {
            return (0.0, 0.0);
        }
        (
            self.walls.face(BoxFace::ZMax).normal_force(),
            self.walls.face(BoxFace::ZMin).normal_force(),
        )
    }

    /// Compressive normal stress (Pa) on the top (z+) and bottom (z-) faces.
    pub fn face_stresses(&self) -> (f64, f64) {
        if !self.walls.is_box {
            return (0.0, 0.0);
        }
        (
            self.walls.face_stress(BoxFace::ZMax),
            self.walls.face_stress(BoxFace::ZMin),
        )
    }

    /// Particles broken so far. The sphere model has no particle fracture, so none; the
    /// granular fracture model counts them here.
    pub fn broken_particles(&self) -> usize {
        0
    }

    /// Face area (m²) of the top and bottom faces.
    pub fn face_area(&self) -> f64 {
        let size = self.walls.box_size();
        size.x * size.y
    }

    fn check_finite(&self) -> Result<()> {
        if let Some(i) = self.bodies.first_non_finite() {
            return Err(Error::run(format!(
                "the run became unstable at step {} (t = {:e} s): body {i} has a non-finite position or velocity; lower time.safety (now {}) or time.dt",
                self.step, self.time, self.scene.time.safety
            )));
        }
        Ok(())
    }

    /// Velocity Verlet is stable while `ω dt < 2` for the highest frequency ω of the system.
    /// Hertz contacts stiffen as they overlap, so a step chosen from the Rayleigh time can
    /// become too long under heavy compaction: then the results go wrong before anything turns
    /// infinite (SHPB to 10% strain: 1% off at an estimated ω dt of 1.7, 22% at 2.04). The
    /// estimate is checked at every output step; above 2 the run stops, above 1.6 it warns.
    fn check_stability(&mut self) -> Result<()> {
        let omega_dt = self.pipeline.max_frequency(&self.bodies, &self.walls) * self.dt;
        self.max_omega_dt = self.max_omega_dt.max(omega_dt);
        if omega_dt > OMEGA_DT_LIMIT {
            return Err(Error::run(format!(
                "the time step is too long for the contacts at step {} (t = {:e} s): the stiffest body oscillates with omega dt = {omega_dt:.2}, and velocity Verlet needs less than 2; lower time.safety (now {}) or time.dt",
                self.step, self.time, self.scene.time.safety
            )));
        }
        if omega_dt > OMEGA_DT_WARN && !self.warnings.iter().any(|w| w.starts_with("omega dt")) {
            self.warnings.push(format!(
                "omega dt reached {omega_dt:.2} at step {} (t = {:e} s): contacts have stiffened enough that results lose accuracy (about 1% at 1.7); consider a lower time.safety",
                self.step, self.time
            ));
        }
        Ok(())
    }

    fn record_row(&mut self) {
        let contacts = self.pipeline.contacts();
        let row = if self.walls.is_box {
            probe::box_row(self.time, self.height0, &self.bodies, &self.walls, contacts)
        } else {
            probe::free_row(self.time, &self.bodies, contacts)
        };
        if self.series.rows.last().is_some_and(|r| r[0] == row[0]) {
            return;
        }
        self.series.rows.push(row);
    }

    /// The axial strain of the box (0 without one).
    pub fn axial_strain(&self) -> f64 {
        if self.walls.is_box {
            (self.height0 - self.walls.box_size().z) / self.height0
        } else {
            0.0
        }
    }

    /// The results of the run so far; identical for identical scenes, seeds, thread counts
    /// and builds.
    pub fn summary(&self) -> Value {
        let mut m = run::common_summary(self);
        m.insert("dt_rayleigh".into(), self.dt_rayleigh.into());
        m.insert(
            "sample".into(),
            serde_json::to_value(&self.sample).expect("sample info serialises"),
        );
        m.insert(
            "solid_fraction_initial".into(),
            self.sample.solid_fraction.into(),
        );
        m.insert("contacts_final".into(), self.pipeline.contacts().into());
        m.insert("max_omega_dt".into(), self.max_omega_dt.into());
        m.insert(
            "kinetic_energy_final".into(),
            self.bodies.kinetic_energy().into(),
        );
        self.loading.summarize(&self.series, &mut m);
        Value::Object(m)
    }

    /// Restores a run from the bytes [`Run::save_state`] wrote.
    pub fn restore(scene: Scene, state: &[u8], threads: usize) -> Result<Self> {
        let state: RunState = postcard::from_bytes(state)
            .map_err(|e| Error::run(format!("the checkpoint's granular state is damaged ({e})")))?;
        Simulation::from_state(scene, state, threads)
    }
}

impl Run for Simulation {
    fn scene(&self) -> &Scene {
        &self.scene
    }
    fn model(&self) -> &'static str {
        "granular"
    }
    fn bodies(&self) -> usize {
        self.bodies.len()
    }
    fn step(&self) -> u64 {
        self.step
    }
    fn end_step(&self) -> u64 {
        self.end_step
    }
    fn time(&self) -> f64 {
        self.time
    }
    fn dt(&self) -> f64 {
        self.dt
    }
    fn threads(&self) -> usize {
        Simulation::threads(self)
    }
    fn advance(&mut self, steps: u64) -> Result<()> {
        Simulation::advance(self, steps)
    }
    fn series(&self) -> &Series {
        &self.series
    }
    fn summary(&self) -> Value {
        Simulation::summary(self)
    }
    fn snapshot(&self) -> Vec<(&'static str, String)> {
        let mut files = vec![("particles", vtk::particles_vtu(&self.bodies, &self.forces))];
        if self.walls.is_box {
            files.push(("walls", vtk::box_walls_vtu(&self.walls)));
        }
        files
    }
    fn save_state(&self) -> Vec<u8> {
        postcard::to_stdvec(&self.state()).expect("the granular state serialises")
    }
    fn status(&self) -> String {
        format!("t = {:.4e} s, strain {:.4}", self.time, self.axial_strain())
    }
    fn warnings(&self) -> &[String] {
        &self.warnings
    }
}
