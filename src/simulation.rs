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
use crate::fracture::GrainFracture;
use crate::integrate::{VelocityVerlet, rayleigh_time_step};
use crate::loading::Loading;
use crate::output::vtk;
use crate::probe::energy::{EnergyAccount, Mechanical};
use crate::probe::size_distribution;
use crate::probe::{self, Series};
use crate::run::{self, Run};
use crate::sample::{self, Sample, SampleInfo};
use crate::scene::{DtSpec, EffectKind, LoadingKind, Scene};
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
    /// Times the step was shortened for breaking grains' pieces (see `adapt_time_step`).
    pub dt_shortened: u32,
    /// Warnings for the user, in the order they arose.
    pub warnings: Vec<String>,
    /// Particle fracture and cohesion (the `fracture` effect), its energy account and the
    /// pieces' masses at the report strains.
    pub fracture: Option<GrainFracture>,
    pub energy: Option<EnergyAccount>,
    pub psd: Vec<(f64, Vec<f64>)>,
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
    pub end_step: u64,
    pub max_omega_dt: f64,
    pub dt_shortened: u32,
    pub warnings: Vec<String>,
    pub effects: Vec<(String, Vec<u8>)>,
    pub fracture: Option<GrainFracture>,
    pub energy: Option<EnergyAccount>,
    pub psd: Vec<(f64, Vec<f64>)>,
}

/// The step at which a loading of `end_time` seconds ends (unbounded for an endless one).
pub(crate) fn end_step(end_time: f64, dt: f64) -> u64 {
    if end_time.is_finite() {
        (end_time / dt - 1e-9).ceil().max(1.0) as u64
    } else {
        u64::MAX
    }
}

/// The value of `ys` at `x` by linear interpolation along the increasing `xs`; `None` outside.
fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> Option<f64> {
    let k = xs.iter().position(|&v| v >= x)?;
    if k == 0 {
        return (xs[0] == x).then(|| ys[0]);
    }
    let t = (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
    Some(ys[k - 1] + t * (ys[k] - ys[k - 1]))
}

/// Above this estimated `ω dt` a run stops, above the second it warns.
const OMEGA_DT_LIMIT: f64 = 2.0;
const OMEGA_DT_WARN: f64 = 1.6;
/// The estimated `ω dt` above which a fracture run shortens its step.
pub const ADAPT_OMEGA_DT: f64 = 0.6;

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
        if sim.scene.has_effect(EffectKind::Fracture) {
            sim.fracture = Some(GrainFracture::new(&sim.scene, &sim.bodies));
        }
        sim.evaluate_forces(false);
        if sim.fracture.is_some() {
            sim.energy = Some(EnergyAccount::new(&sim.walls, sim.mechanical_energy()));
            sim.take_size_distributions();
        }
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
        // Breaking grains end as pieces of an eighth of their mass (three splits at most,
        // Section 3.3.3) whose Rayleigh time is about half the grain's: the first step is
        // chosen for them; `adapt_time_step` shortens it further when pieces' contacts ask.
        let fracture = scene.has_effect(EffectKind::Fracture);
        let r_min = bodies.min_radius() * if fracture { 0.5 } else { 1.0 };
        let dt_rayleigh = rayleigh_time_step(r_min, m.density, m.young, m.poisson);
        let dt = match scene.time.dt {
            DtSpec::Auto => scene.time.safety * dt_rayleigh,
            DtSpec::Seconds(s) => s,
        };
        let end_step = end_step(loading.end_time(), dt);
        let mut columns: Vec<&str> = if scene.loading.kind == LoadingKind::Platens {
            probe::PLATEN_COLUMNS.to_vec()
        } else if walls.is_box {
            probe::BOX_COLUMNS.to_vec()
        } else {
            probe::FREE_COLUMNS.to_vec()
        };
        if fracture {
            columns.extend_from_slice(&probe::FRACTURE_COLUMNS);
        }
        let series = Series::new(&columns);
        let track_orientation = fracture || bodies.shape.iter().any(|s| !s.is_sphere());
        let forces = Forces::new(bodies.len());
        let sim = Simulation {
            scene,
            bodies,
            walls,
            forces,
            pipeline,
            integrator: VelocityVerlet { track_orientation },
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
            dt_shortened: 0,
            warnings: Vec::new(),
            fracture: None,
            energy: None,
            psd: Vec::new(),
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
        sim.dt_shortened = state.dt_shortened;
        sim.warnings = state.warnings;
        sim.fracture = state.fracture;
        sim.energy = state.energy;
        sim.psd = state.psd;
        sim.end_step = state.end_step;
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
            end_step: self.end_step,
            max_omega_dt: self.max_omega_dt,
            dt_shortened: self.dt_shortened,
            warnings: self.warnings.clone(),
            effects: self.pipeline.save(),
            fracture: self.fracture.clone(),
            energy: self.energy.clone(),
            psd: self.psd.clone(),
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
            if let Some(f) = &mut self.fracture {
                f.add_spring_forces(&self.bodies, &mut self.forces);
            }
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
        if let Some(f) = &mut self.fracture {
            f.add_spring_forces(&self.bodies, &mut self.forces);
        }
        self.integrator.kick(&mut self.bodies, &self.forces, dt);
        self.step += 1;
        self.time += dt;
        if self.fracture.is_some() {
            self.after_fracture_step(dt);
        }
    }

    /// Fracture after a step: account the step's energy, break the grains that fail at the
    /// new state, and take the size distribution at the report strains.
    fn after_fracture_step(&mut self, dt: f64) {
        let dissipated = self.pipeline.records().map_or(0.0, |r| r.dissipated);
        if let Some(e) = &mut self.energy {
            e.add_step(&self.walls, dissipated, dt);
        }
        let fracture = self.fracture.as_ref().expect("called with fracture");
        let records = self.pipeline.records().expect("fracture records contacts");
        let breaking = fracture.check(&self.bodies, &self.forces, records);
        self.break_grains(&breaking);
        self.take_size_distributions();
    }

    /// Splits the given grains now (each with what broke it; see
    /// [`GrainFracture::check`]), re-evaluates the forces on the new shapes and bonds the
    /// halves. Returns the number of splits made (grains whose shape forbids breaking make
    /// none). Needs the `fracture` effect.
    pub fn break_grains(&mut self, breaking: &[crate::fracture::Breaking]) -> usize {
        if breaking.is_empty() || self.fracture.is_none() {
            return 0;
        }
        let before = self.mechanical_energy();
        let fracture = self.fracture.as_mut().expect("checked above");
        let pending = fracture.split(
            &mut self.bodies,
            &self.forces,
            breaking,
            self.step,
            self.time,
        );
        if !pending.is_empty() {
            let reshaped: Vec<usize> = pending.iter().map(|p| p.a).collect();
            self.pipeline.reshaped(&reshaped);
            self.forces = Forces::new(self.bodies.len());
            self.evaluate_forces(false);
            self.adapt_time_step(self.pipeline.max_frequency(&self.bodies, &self.walls));
            let after = self.mechanical_energy();
            let fracture = self.fracture.as_mut().expect("checked above");
            fracture.split_energy += after.total() - before.total();
            fracture.bond(&self.bodies, &mut self.forces, &pending);
        }
        pending.len()
    }

    /// Kinetic, contact elastic and gravitational energy now (J); elastic from the contact
    /// records of the last evaluation.
    fn mechanical_energy(&self) -> Mechanical {
        let elastic = self
            .pipeline
            .records()
            .map_or(0.0, |r| r.list.iter().map(|c| c.energy).sum());
        let gravity = if self.scene.has_effect(EffectKind::Gravity) {
            let g = crate::state::Vec3::from(self.scene.gravity.acceleration);
            -(0..self.bodies.len())
                .map(|i| self.bodies.mass[i] * g.dot(&self.bodies.pos[i]))
                .sum::<f64>()
        } else {
            0.0
        };
        Mechanical {
            kinetic: self.bodies.kinetic_energy(),
            elastic,
            gravity,
        }
    }

    /// The strains at which the size distribution and the stress are reported.
    pub fn report_strains(&self) -> Vec<f64> {
        let end = match self.loading {
            Loading::Oedometer { end_strain, .. } => end_strain,
            _ => return Vec::new(),
        };
        let strains = self
            .scene
            .output
            .report_strains
            .clone()
            .unwrap_or_else(|| vec![0.05, 0.1, 0.2, 0.3, 0.4]);
        strains.into_iter().filter(|&e| e <= end + 1e-12).collect()
    }

    /// The masses of the pieces (grains and fragments held by intact springs), at the start
    /// and once each report strain is passed.
    fn take_size_distributions(&mut self) {
        let Some(f) = &self.fracture else {
            return;
        };
        let strain = self.axial_strain();
        let due = if self.psd.is_empty() {
            Some(0.0)
        } else {
            self.report_strains()
                .into_iter()
                .find(|&e| strain >= e - 1e-12 && self.psd.iter().all(|(s, _)| *s != e))
        };
        let Some(at) = due else {
            return;
        };
        let (labels, count) = f.pieces(self.bodies.len());
        let masses = crate::probe::fragments::sum_by_component(&labels, count, &self.bodies.mass);
        self.psd.push((at, masses));
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

    /// Grains of the sample broken so far (0 without the `fracture` effect).
    pub fn broken_particles(&self) -> usize {
        self.fracture.as_ref().map_or(0, |f| f.broken_particles())
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

    /// Breaking grains make pieces smaller than any grain of the sample, and contacts between
    /// them as stiff as their overlaps make them: with `fracture` and `time.dt = "auto"`, the
    /// step is shortened whenever the estimated highest frequency (normal and tangential
    /// contact springs through their levers) gives `ω dt` above [`ADAPT_OMEGA_DT`]; it never
    /// grows back. Checked at every output step and after every split. Without it the pieces'
    /// spins went unstable (ω dt estimated 1.3, the rotational modes beyond 2) and fed energy to
    /// the contacts' damping: 91% energy-balance error in a 5×5×5 hcp SHPB sample at 0.2 strain.
    /// `omega` is the current estimate of the highest frequency (rad/s).
    fn adapt_time_step(&mut self, omega: f64) {
        if self.fracture.is_none() || self.scene.time.dt != DtSpec::Auto {
            return;
        }
        let omega_dt = omega * self.dt;
        if omega_dt <= ADAPT_OMEGA_DT {
            return;
        }
        self.dt *= ADAPT_OMEGA_DT / omega_dt;
        self.dt_shortened += 1;
        let end_time = self.loading.end_time();
        self.end_step = self
            .step
            .saturating_add(end_step((end_time - self.time).max(0.0), self.dt));
    }

    /// Velocity Verlet is stable while `ω dt < 2` for the highest frequency ω of the system.
    /// Hertz contacts stiffen as they overlap, so a step chosen from the Rayleigh time can
    /// become too long under heavy compaction: then the results go wrong before anything turns
    /// infinite (SHPB to 10% strain: 1% off at an estimated ω dt of 1.7, 22% at 2.04). The
    /// estimate is checked at every output step; above 2 the run stops, above 1.6 it warns.
    fn check_stability(&mut self) -> Result<()> {
        let omega = self.pipeline.max_frequency(&self.bodies, &self.walls);
        self.adapt_time_step(omega);
        let omega_dt = omega * self.dt;
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
        let mut row = if matches!(self.loading, Loading::Platens { .. }) {
            probe::platen_row(self.time, self.height0, &self.bodies, &self.walls, contacts)
        } else if self.walls.is_box {
            probe::box_row(self.time, self.height0, &self.bodies, &self.walls, contacts)
        } else {
            probe::free_row(self.time, &self.bodies, contacts)
        };
        if let (Some(f), Some(e)) = (&self.fracture, &self.energy) {
            let now = self.mechanical_energy();
            row.extend_from_slice(&[
                self.bodies.len() as f64,
                f.broken_particles() as f64,
                f.fragments(self.bodies.len()) as f64,
                f.intact_springs() as f64,
                now.elastic,
                e.boundary_work,
                e.dissipated,
                -f.spring_work,
            ]);
        }
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
        if self.fracture.is_some() {
            m.insert("dt_shortened".into(), self.dt_shortened.into());
        }
        m.insert(
            "kinetic_energy_final".into(),
            self.bodies.kinetic_energy().into(),
        );
        self.loading.summarize(&self.series, &mut m);
        self.stress_summary(&mut m);
        if let Some(f) = &self.fracture {
            self.fracture_summary(f, &mut m);
        }
        Value::Object(m)
    }

    /// The `fracture` effect's results: grains broken, fragments, splits by criterion, springs,
    /// the stress at the report strains, the median size at each, and the energy account.
    fn fracture_summary(&self, f: &GrainFracture, m: &mut serde_json::Map<String, Value>) {
        use serde_json::json;
        let n = self.bodies.len();
        m.insert("broken_particles".into(), f.broken_particles().into());
        m.insert("fragments".into(), f.fragments(n).into());
        m.insert("particles_final".into(), n.into());
        let by =
            |c: crate::fracture::Criterion| f.events.iter().filter(|e| e.criterion == c).count();
        m.insert(
            "splits".into(),
            json!({
                "total": f.events.len(),
                "hoek_brown": by(crate::fracture::Criterion::HoekBrown),
                "contacts": by(crate::fracture::Criterion::Contacts),
            }),
        );
        m.insert(
            "springs".into(),
            json!({"made": f.springs.len(), "intact": f.intact_springs()}),
        );
        if let Some(first) = f.events.first() {
            m.insert("first_split_time".into(), first.time.into());
        }
        let strains = self.report_strains();
        if !strains.is_empty() {
            let rho = self.scene.material.density;
            let mut d50 = serde_json::Map::new();
            for (e, masses) in &self.psd {
                let pieces = size_distribution::pieces(masses, rho);
                d50.insert(
                    format!("{e}"),
                    size_distribution::median_diameter(&pieces).into(),
                );
            }
            m.insert("median_diameter_at_strain".into(), Value::Object(d50));
        }
        if let Some(e) = &self.energy {
            m.insert(
                "energy".into(),
                e.report(self.mechanical_energy(), f.spring_work, f.split_energy),
            );
        }
    }

    /// `stress_at_strain`: the axial stress (Pa) at the report strains of an oedometer run.
    fn stress_summary(&self, m: &mut serde_json::Map<String, Value>) {
        let strains = self.report_strains();
        if !strains.is_empty() {
            let (eps, axial) = (
                self.series.column("axial_strain").unwrap_or_default(),
                self.axial_stress_column(),
            );
            let mut at = serde_json::Map::new();
            for e in &strains {
                if let Some(v) = interpolate(&eps, &axial, *e) {
                    at.insert(format!("{e}"), v.into());
                }
            }
            m.insert("stress_at_strain".into(), Value::Object(at));
        }
    }

    /// Axial stress of each series row: the mean of the top and bottom faces (Pa).
    fn axial_stress_column(&self) -> Vec<f64> {
        match (
            self.series.column("stress_driven"),
            self.series.column("stress_opposite"),
        ) {
            (Some(a), Some(b)) => a.iter().zip(&b).map(|(x, y)| 0.5 * (x + y)).collect(),
            _ => Vec::new(),
        }
    }

    /// psd.csv: the sieve curves (mass fraction finer than each equivalent diameter) at the
    /// start and at each report strain reached.
    pub fn psd_csv(&self) -> Option<String> {
        if self.psd.is_empty() || self.fracture.is_none() {
            return None;
        }
        let rho = self.scene.material.density;
        let curves: Vec<Vec<(f64, f64)>> = self
            .psd
            .iter()
            .map(|(_, masses)| size_distribution::pieces(masses, rho))
            .collect();
        let sieves = size_distribution::sieve_sizes(curves.iter().flatten().map(|p| p.1), 40);
        let passing: Vec<Vec<f64>> = curves
            .iter()
            .map(|c| size_distribution::passing(c, &sieves))
            .collect();
        let mut s = String::from("diameter");
        for (e, _) in &self.psd {
            s.push_str(&format!(",passing_at_strain_{e}"));
        }
        s.push('\n');
        for (k, d) in sieves.iter().enumerate() {
            s.push_str(&format!("{d:e}"));
            for p in &passing {
                s.push_str(&format!(",{:e}", p[k] + 0.0)); // no "-0"
            }
            s.push('\n');
        }
        Some(s)
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
        if self.fracture.is_some() || self.bodies.shape.iter().any(|s| !s.is_sphere()) {
            let origin = self.fracture.as_ref().map_or(&[][..], |f| &f.origin[..]);
            files.push(("grains", vtk::grains_vtu(&self.bodies, origin)));
        }
        files
    }
    fn extra_outputs(&self) -> Vec<(String, Vec<u8>)> {
        self.psd_csv()
            .map(|csv| vec![("psd.csv".to_string(), csv.into_bytes())])
            .unwrap_or_default()
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
