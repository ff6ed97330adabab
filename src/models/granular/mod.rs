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
mod explain;
pub mod export;
pub mod loading;
pub mod sample;
pub mod scene;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use crate::effects::{ContactParams, Pipeline, StepContext};
use crate::error::{Error, Result};
use crate::fracture::{FractureParams, GrainFracture};
use crate::integrate::{
    StepVerdict, VelocityVerlet, adapted_step, rayleigh_time_step, step_verdict,
};
use crate::output::vtk;
use crate::probe::energy::{EnergyAccount, Mechanical};
use crate::probe::size_distribution;
use crate::probe::{self, Series};
pub use crate::run::Faces;
use crate::run::{Built, Clock, Model, RunInfo, Runner, end_step};
use crate::sample::{Sample, SampleInfo};
use crate::scene::{DtSpec, EffectKind, IntegratorKind, Scene};
use crate::state::{Bodies, BoxFace, Forces, Vec3, Walls};
use loading::Loading;
use scene::GranularScene;

pub use explain::explain;

/// A granular run: the generic runner over the granular model.
pub type Simulation = Runner<Granular>;

/// The granular model: its scene section, the pipeline and integrator built from it, and the
/// persistent state.
pub struct Granular {
    pub cfg: GranularScene,
    pub pipeline: Pipeline,
    pub integrator: VelocityVerlet,
    /// Gravity (m/s²) with the `gravity` effect, for the energy account.
    pub gravity: Option<Vec3>,
    /// `output.report_strains` or the default list, before the loading picks those it
    /// reaches (see [`Granular::report_strains`]).
    strains_asked: Vec<f64>,
    /// `time.dt = "auto"`: the step may be shortened for breaking grains' pieces.
    pub auto_dt: bool,
    /// The `ω dt` the step is shortened to: [`ADAPT_PER_SAFETY`] × `time.safety`.
    pub adapt_omega_dt: f64,
    /// The grains' total volume (m³) at a body count (see `fault`); not state.
    solid_volume: std::cell::Cell<Option<(usize, f64)>>,
    /// Set when a shortened step leaves more than [`crate::run::MAX_STEPS`] steps to the end:
    /// the run stops at the next check saying so (see `adapt_time_step`); not state.
    collapsed: Option<String>,
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
    /// The largest `ω dt` seen after a step (see `Granular::check_stability`).
    pub max_omega_dt: f64,
    /// Times the step was shortened for breaking grains' pieces (see `adapt_time_step`).
    pub dt_shortened: u32,
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
}

/// How far comminution has gone at one strain: bodies, pieces (held by intact springs), the
/// bodies of each generation (index: splits since the sample's grain) and the bodies below
/// the comminution limit.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Comminution {
    pub strain: f64,
    pub bodies: usize,
    pub pieces: usize,
    pub generations: Vec<usize>,
    pub at_limit: usize,
}

impl Comminution {
    /// The state of `fracture` over `bodies` at axial strain `strain`.
    pub fn of(strain: f64, bodies: &Bodies, fracture: &GrainFracture) -> Comminution {
        let n = bodies.len();
        let mut generations = Vec::new();
        for &g in &fracture.generation[..n] {
            let g = usize::from(g);
            if generations.len() <= g {
                generations.resize(g + 1, 0);
            }
            generations[g] += 1;
        }
        let at_limit = (0..n)
            .filter(|&i| fracture.params.below_comminution_limit(bodies.volume(i)))
            .count();
        Comminution {
            strain,
            bodies: n,
            pieces: fracture.pieces(n).1,
            generations,
            at_limit,
        }
    }

    fn json(&self) -> Value {
        serde_json::json!({
            "bodies": self.bodies,
            "pieces": self.pieces,
            "generations": self.generations,
            "at_comminution_limit": self.at_limit,
        })
    }
}

impl GranularState {
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

/// The value of `ys` at `x` by linear interpolation along the increasing `xs`; `None` outside.
fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> Option<f64> {
    let k = xs.iter().position(|&v| v >= x)?;
    if k == 0 {
        return (xs[0] == x).then(|| ys[0]);
    }
    let t = (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
    Some(ys[k - 1] + t * (ys[k] - ys[k - 1]))
}

/// Spheres per thread from which a granular step runs on the worker team (see
/// `Model::team_members` below).
const TEAM_MIN_SPHERES_PER_THREAD: usize = 1500;

/// Steps between the stability checks and step adaptations of a granular run that adapts its
/// step (fracture with `time.dt = "auto"`; also after every split and at the last step); other
/// runs check after every step. A fixed cadence, so that what a run computes does not depend
/// on `output.every` (at output steps only, a flat grain's contacts stiffened unseen for the
/// scene's 50 steps and its step collapsed where `output.every = 1` finished). Checking a
/// fracture run after every step cost 1.6 times its time per step (the estimate takes an
/// eigenvalue per contact record); every 10 steps a tenth of that, and the adaptation keeps
/// its ω dt at `ADAPT_PER_SAFETY` × safety (1.2 at 0.4), below the limit of 2, in between.
/// `fractum export lammps --plugin` writes it as the plugin's `fix fractum/dt` EVERY.
pub const STABILITY_EVERY: u64 = 10;
/// A fracture run with `time.dt = "auto"` keeps the estimated `ω dt` of its stiffest body at
/// most this times `time.safety` (1.2 at the main job's 0.4): the safety that sets the first step
/// from the Rayleigh step also sets how close to the stiffest contact the step stays as pieces
/// appear (docs/performance.md: the main job's ensembles at each safety).
pub const ADAPT_PER_SAFETY: f64 = 3.0;

/// The force pipeline of exactly the effects a granular scene names. `friction` overrides
/// the material's coefficient (sample preparation compacts with its own).
pub fn pipeline(scene: &Scene, cfg: &GranularScene) -> Pipeline {
    pipeline_for(scene, cfg, false)
}

/// [`pipeline`] for bodies that hold non-spherical shapes when `shaped` (a sample read from a
/// data file of the Fractum LAMMPS plugin may, whatever the scene's own keys say): their
/// contacts take the shapes' path.
fn pipeline_for(scene: &Scene, cfg: &GranularScene, shaped: bool) -> Pipeline {
    let contact = scene.has_effect(EffectKind::Contact).then(|| {
        let mut params = contact_params(scene, cfg, None);
        params.shapes |= shaped;
        params
    });
    let gravity = scene
        .has_effect(EffectKind::Gravity)
        .then(|| Vec3::from(scene.gravity.acceleration));
    Pipeline::new(contact, gravity)
}

/// The contact model a granular scene asks for.
pub fn contact_params(scene: &Scene, cfg: &GranularScene, friction: Option<f64>) -> ContactParams {
    use crate::contact::hertz_mindlin::{Hertz, Mindlin, ViscousDamping};
    let m = &cfg.material;
    let nu = m.poisson;
    ContactParams {
        hertz: Hertz::new(m.young, nu),
        damping: scene
            .has_effect(EffectKind::Damping)
            .then(|| ViscousDamping::from_restitution(m.restitution)),
        mindlin: scene
            .has_effect(EffectKind::Friction)
            .then(|| Mindlin::new(m.young, nu, friction.unwrap_or(m.friction))),
        wall_friction: cfg.walls.friction,
        skin: cfg.neighbor.skin,
        shapes: scene.has_effect(EffectKind::Fracture) || cfg.sample.non_spherical(),
    }
}

/// The fracture constants of a granular scene, resolved.
pub fn fracture_params(scene: &Scene, cfg: &GranularScene) -> FractureParams {
    FractureParams::new(
        &cfg.fracture,
        cfg.material.young,
        cfg.material.poisson,
        scene.has_effect(EffectKind::Weibull),
        scene.has_effect(EffectKind::Cohesion),
    )
}

impl Granular {
    /// Sets the model up on a sample (built from the scene, or made elsewhere).
    pub fn from_sample(scene: &Scene, cfg: GranularScene, sample: Sample) -> Result<Built<Self>> {
        let Sample {
            bodies,
            walls,
            info,
        } = sample;
        if bodies.is_empty() {
            return Err(scene.key_error("sample", "gives no bodies"));
        }
        let loading = Loading::from_scene(scene, &cfg, &walls)?;
        let height0 = if walls.is_box {
            walls.box_size().z
        } else {
            0.0
        };
        let m = &cfg.material;
        // Breaking grains end as pieces of an eighth of their mass (three splits at most,
        // Section 3.3.3) whose Rayleigh time is about half the grain's: the first step is
        // chosen for them; `adapt_time_step` shortens it further when pieces' contacts ask.
        let fracture = scene.has_effect(EffectKind::Fracture);
        let r_min = bodies.min_radius() * if fracture { 0.5 } else { 1.0 };
        let dt_rayleigh = rayleigh_time_step(r_min, m.density, m.young, m.poisson);
        let dt = scene.time.step(dt_rayleigh);
        crate::run::check_planned_steps(scene, m.young, loading.end_time(), dt)?;
        let end = end_step(loading.end_time(), dt);
        let end_time = loading.end_time();
        let mut columns: Vec<&'static str> = if matches!(loading, Loading::Platens { .. }) {
            probe::PLATEN_COLUMNS.to_vec()
        } else if walls.is_box {
            probe::BOX_COLUMNS.to_vec()
        } else {
            probe::FREE_COLUMNS.to_vec()
        };
        if fracture {
            columns.extend_from_slice(&probe::FRACTURE_COLUMNS);
        }
        let fracture_state =
            fracture.then(|| GrainFracture::new(fracture_params(scene, &cfg), scene.seed, &bodies));
        let mut model = Granular::with_state(
            scene,
            cfg,
            GranularState {
                forces: Forces::new(bodies.len()),
                bodies,
                walls,
                loading,
                sample: info,
                height0,
                dt_rayleigh,
                max_omega_dt: 0.0,
                dt_shortened: 0,
                fracture: fracture_state,
                energy: None,
                psd: Vec::new(),
                comminution: Vec::new(),
                initial: [0.0; 2],
            },
        );
        model.evaluate_forces(dt, false);
        model.state.initial = model.load_bearing();
        if model.state.fracture.is_some() {
            model.state.energy = Some(EnergyAccount::new(
                &model.state.walls,
                model.mechanical_energy(),
            ));
            model.take_size_distributions();
        }
        Ok(Built {
            model,
            dt,
            end_step: end,
            end_time,
            columns,
            warnings: Vec::new(),
        })
    }

    /// The model of `state` under its scene: what is built from the scene (pipeline,
    /// integrator, gravity, report strains) around the persistent state.
    fn with_state(scene: &Scene, cfg: GranularScene, state: GranularState) -> Granular {
        let fracture = scene.has_effect(EffectKind::Fracture);
        let shaped = state.bodies.shape.iter().any(|s| !s.is_sphere());
        Granular {
            pipeline: pipeline_for(scene, &cfg, shaped),
            integrator: VelocityVerlet {
                track_orientation: fracture || shaped,
            },
            gravity: scene
                .has_effect(EffectKind::Gravity)
                .then(|| Vec3::from(scene.gravity.acceleration)),
            strains_asked: scene
                .output
                .report_strains
                .clone()
                .unwrap_or_else(|| vec![0.05, 0.1, 0.2, 0.3, 0.4]),
            auto_dt: scene.time.dt == DtSpec::Auto,
            adapt_omega_dt: ADAPT_PER_SAFETY * scene.time.safety,
            solid_volume: std::cell::Cell::new(None),
            collapsed: None,
            cfg,
            state,
        }
    }

    fn evaluate_forces(&mut self, dt: f64, update_history: bool) {
        let st = &mut self.state;
        st.forces.clear();
        st.walls.clear_forces();
        let ctx = StepContext { dt, update_history };
        self.pipeline
            .accumulate(&ctx, &st.bodies, &mut st.walls, &mut st.forces);
        if let Some(f) = &mut st.fracture {
            f.add_spring_forces(&st.bodies, &mut st.forces);
        }
    }

    /// Fracture after a step: account the step's energy, break the grains that fail at the
    /// new state, and take the size distribution at the report strains.
    fn after_fracture_step(&mut self, clock: &mut Clock, dt: f64) {
        let dissipated = self.pipeline.records().map_or(0.0, |r| r.dissipated);
        if let Some(e) = &mut self.state.energy {
            e.add_step(&self.state.walls, dissipated, dt);
        }
        let st = &mut self.state;
        let fracture = st.fracture.as_mut().expect("called with fracture");
        let records = self.pipeline.records().expect("fracture records contacts");
        let breaking = fracture.check(&st.bodies, &st.forces, records);
        self.break_grains(clock, &breaking);
        self.take_size_distributions();
    }

    /// Splits the given grains now (each with what broke it; see
    /// [`GrainFracture::check`]), re-evaluates the forces on the new shapes and bonds the
    /// halves. Returns the number of splits made (grains whose shape forbids breaking make
    /// none). Needs the `fracture` effect.
    pub fn break_grains(
        &mut self,
        clock: &mut Clock,
        breaking: &[crate::fracture::Breaking],
    ) -> usize {
        if breaking.is_empty() || self.state.fracture.is_none() {
            return 0;
        }
        let before = self.mechanical_energy();
        let st = &mut self.state;
        let fracture = st.fracture.as_mut().expect("checked above");
        let pending = fracture.split(&mut st.bodies, &st.forces, breaking, clock.step, clock.time);
        if !pending.is_empty() {
            let reshaped: Vec<usize> = pending.iter().map(|p| p.a).collect();
            self.pipeline.reshaped(&reshaped);
            self.state.forces = Forces::new(self.state.bodies.len());
            self.evaluate_forces(clock.dt, false);
            let omega = self
                .pipeline
                .max_frequency(&self.state.bodies, &self.state.walls);
            self.adapt_time_step(clock, omega);
            let after = self.mechanical_energy();
            let st = &mut self.state;
            let fracture = st.fracture.as_mut().expect("checked above");
            fracture.split_energy += after.total() - before.total();
            fracture.bond(&st.bodies, &mut st.forces, &pending);
        }
        pending.len()
    }

    /// Kinetic, contact elastic and gravitational energy now (J); elastic from the contact
    /// records of the last evaluation.
    fn mechanical_energy(&self) -> Mechanical {
        let b = &self.state.bodies;
        let elastic = self
            .pipeline
            .records()
            .map_or(0.0, |r| r.list.iter().map(|c| c.energy).sum());
        let gravity = match self.gravity {
            Some(g) => -(0..b.len())
                .map(|i| b.mass[i] * g.dot(&b.pos[i]))
                .sum::<f64>(),
            None => 0.0,
        };
        Mechanical {
            kinetic: b.kinetic_energy(),
            elastic,
            gravity,
        }
    }

    /// The masses and equivalent diameters (of their own volume) of the pieces (grains and
    /// fragments held by intact springs), at the start and once each report strain is passed.
    fn take_size_distributions(&mut self) {
        let st = &self.state;
        let Some(f) = &st.fracture else {
            return;
        };
        let strain = self.axial_strain();
        let due = if st.psd.is_empty() {
            Some(0.0)
        } else {
            self.report_strains_iter()
                .find(|&e| strain >= e - 1e-12 && st.psd.iter().all(|(s, _)| *s != e))
        };
        let Some(at) = due else {
            return;
        };
        let n = st.bodies.len();
        let (labels, count) = f.pieces(n);
        let sum = |x: &[f64]| crate::probe::fragments::sum_by_component(&labels, count, x);
        let volumes: Vec<f64> = (0..n).map(|i| st.bodies.volume(i)).collect();
        let pieces = size_distribution::pieces(&sum(&st.bodies.mass), &sum(&volumes));
        let comminution = Comminution::of(at, &st.bodies, f);
        self.state.psd.push((at, pieces));
        self.state.comminution.push(comminution);
    }

    /// Breaking grains make pieces smaller than any grain of the sample, and contacts between
    /// them as stiff as their overlaps make them: with `fracture` and `time.dt = "auto"`, the
    /// step is shortened whenever the bound on the highest frequency (normal and tangential
    /// contact springs through their levers, `records_max_frequency`) gives `ω dt` above
    /// [`ADAPT_PER_SAFETY`] × `time.safety`; it never grows back. Checked after every step
    /// and every split. Without it the pieces' spins went unstable (ω dt estimated 1.3,
    /// the rotational modes beyond 2) and fed energy to the contacts' damping: 91%
    /// energy-balance error in a 5×5×5 hcp SHPB sample at 0.2 strain.
    /// `omega` is the current estimate of the highest frequency (rad/s).
    fn adapt_time_step(&mut self, clock: &mut Clock, omega: f64) {
        if self.state.fracture.is_none() || !self.auto_dt {
            return;
        }
        let Some(dt) = adapted_step(omega, clock.dt, self.adapt_omega_dt) else {
            return;
        };
        let before = clock.dt;
        clock.set_dt(dt);
        self.state.dt_shortened += 1;
        let remaining = clock.remaining();
        // The limit of steps the build checks holds for the steps left after a shortening
        // too: a step that collapses (stiffening contacts the step cannot follow) used to leave
        // a run that went on for ever without a word.
        let left = remaining / clock.dt;
        if self.collapsed.is_none() && (left.is_nan() || left > crate::run::MAX_STEPS) {
            self.collapsed = Some(format!(
                "the time step collapsed from {:.3e} s (the first) to {dt:.3e} s ({} shortenings, the last from {before:.3e} s): contacts stiffen faster than the step can follow (highest contact frequency {omega:.3e} rad/s), and the {remaining:.3e} s left to the end of the loading would take {left:.2e} steps, more than the limit of 1e9; the grains or pieces are crushed beyond what the contact law describes: check the sample's shapes and the loading (loading.speed, loading.end_displacement), or give time.dt in seconds",
                self.state.dt_rayleigh * self.adapt_omega_dt / ADAPT_PER_SAFETY,
                self.state.dt_shortened
            ));
        }
    }

    /// Velocity Verlet is stable while `ω dt < 2` for the highest frequency ω of the system.
    /// Hertz contacts stiffen as they overlap, so a step chosen from the Rayleigh time can
    /// become too long under heavy compaction: then the results go wrong before anything turns
    /// infinite (SHPB to 10% strain: 1% off at an estimated ω dt of 1.7, 22% at 2.04). The
    /// estimate is checked after every step; above 2 the run stops, above 1.6 it warns.
    fn check_stability(
        &mut self,
        scene: &Scene,
        clock: &mut Clock,
        warnings: &mut Vec<String>,
    ) -> Result<()> {
        let omega = self
            .pipeline
            .max_frequency(&self.state.bodies, &self.state.walls);
        self.adapt_time_step(clock, omega);
        if let Some(why) = &self.collapsed {
            return Err(Error::run(format!(
                "the run stopped at step {} (t = {:e} s): {why}",
                clock.step, clock.time
            )));
        }
        let omega_dt = omega * clock.dt;
        self.state.max_omega_dt = self.state.max_omega_dt.max(omega_dt);
        let verdict = step_verdict(omega_dt);
        if verdict == StepVerdict::Unstable {
            return Err(Error::run(format!(
                "the time step is too long for the contacts at step {} (t = {:e} s): the stiffest body oscillates with omega dt = {omega_dt:.2}, and velocity Verlet needs less than 2; lower time.safety (now {}) or time.dt",
                clock.step, clock.time, scene.time.safety
            )));
        }
        if verdict == StepVerdict::Coarse && !warnings.iter().any(|w| w.starts_with("omega dt")) {
            warnings.push(format!(
                "omega dt reached {omega_dt:.2} at step {} (t = {:e} s): contacts are resolved by few steps and results lose accuracy (two spheres meeting at 0.9 of the critical step, omega dt 1.93, rebound 48% too fast); consider a lower time.safety",
                clock.step, clock.time
            ));
        }
        Ok(())
    }

    /// The box's height (z, m) when loading began: what `axial_strain` is relative to (0
    /// without a box). A prepared sample's box is not the scene's nominal one: a jammed sample
    /// stops within its fraction's tolerance, its box scaled to match.
    pub fn initial_height(&self) -> f64 {
        if self.state.walls.is_box {
            self.state.height0
        } else {
            0.0
        }
    }

    /// The axial strain of the box (0 without one).
    pub fn axial_strain(&self) -> f64 {
        let st = &self.state;
        if st.walls.is_box {
            (st.height0 - st.walls.box_size().z) / st.height0
        } else {
            0.0
        }
    }

    /// Grains of the sample broken so far (0 without the `fracture` effect).
    pub fn broken_particles(&self) -> usize {
        self.state
            .fracture
            .as_ref()
            .map_or(0, |f| f.broken_particles())
    }

    /// The strains at which the size distribution and the stress are reported: those of an
    /// oedometer run up to its end strain.
    pub fn report_strains(&self) -> Vec<f64> {
        self.report_strains_iter().collect()
    }

    /// [`Granular::report_strains`] without collecting them (checked at every step).
    fn report_strains_iter(&self) -> impl Iterator<Item = f64> + '_ {
        let end = match self.state.loading {
            Loading::Oedometer { end_strain, .. } => end_strain,
            _ => f64::NEG_INFINITY,
        };
        self.strains_asked
            .iter()
            .copied()
            .filter(move |&e| e <= end + 1e-12)
    }

    /// The mean stress on the walls (Pa, compression positive: each wall's normal force over
    /// its box face's area, averaged over the walls) and the mean coordination number
    /// (contacts per body, a wall contact counting once) at the last force evaluation.
    fn load_bearing(&self) -> [f64; 2] {
        let st = &self.state;
        let walls = &st.walls;
        let stress = if walls.is_box {
            crate::state::BoxFace::ALL
                .iter()
                .map(|&f| walls.face_stress(f))
                .sum::<f64>()
                / 6.0
        } else {
            0.0
        };
        let wall_contacts: usize = walls.walls.iter().map(|w| w.contacts).sum();
        let n = st.bodies.len().max(1);
        let coordination = (2 * self.pipeline.contacts() + wall_contacts) as f64 / n as f64;
        [stress, coordination]
    }

    /// The `fracture` effect's results: grains broken, fragments, splits by criterion, springs,
    /// the stress at the report strains, the median size at each, and the energy account.
    fn fracture_summary(&self, f: &GrainFracture, m: &mut Map<String, Value>) {
        use serde_json::json;
        let n = self.state.bodies.len();
        m.insert("broken_particles".into(), f.broken_particles().into());
        m.insert("fragments".into(), f.fragments(n).into());
        m.insert("particles_final".into(), n.into());
        m.insert(
            "comminution".into(),
            Comminution::of(self.axial_strain(), &self.state.bodies, f).json(),
        );
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
            m.insert(
                "first_split".into(),
                json!({
                    "step": first.step,
                    "time": first.time,
                    "axis": first.axis,
                    "criterion": first.criterion,
                    "semi_plus": first.semi[0],
                    "semi_minus": first.semi[1],
                }),
            );
        }
        let strains = self.report_strains();
        if !strains.is_empty() {
            // The mass median and the modes (quarter-octave bins, 0.19 in ln d, a mode holding
            // at least 3% of the mass) of each distribution.
            let (mut d50, mut peaks) = (serde_json::Map::new(), serde_json::Map::new());
            for (e, pieces) in &self.state.psd {
                let median = size_distribution::median_diameter(pieces);
                let at = size_distribution::modes(pieces, 2f64.powf(0.25), 0.03);
                d50.insert(format!("{e}"), median.into());
                peaks.insert(format!("{e}"), at.into());
            }
            m.insert("median_diameter_at_strain".into(), Value::Object(d50));
            m.insert("size_modes_at_strain".into(), Value::Object(peaks));
            let mut at = serde_json::Map::new();
            for c in &self.state.comminution {
                at.insert(format!("{}", c.strain), c.json());
            }
            m.insert("comminution_at_strain".into(), Value::Object(at));
        }
        if let Some(e) = &self.state.energy {
            m.insert(
                "energy".into(),
                e.report(self.mechanical_energy(), f.spring_work, f.split_energy),
            );
        }
    }

    /// The stresses (Pa, compression positive) at the report strains of an oedometer run:
    /// `stress_at_strain` the axial stress (mean of the driven and the opposite face),
    /// `stress_driven_at_strain` and `stress_opposite_at_strain` each face's own (an SHPB's
    /// one-wave stress is the opposite face's, on the transmitted bar), and
    /// `stress_lateral_at_strain` the mean of the four side faces (a sleeve's radial stress).
    fn stress_summary(&self, series: &Series, m: &mut Map<String, Value>) {
        let strains = self.report_strains();
        if strains.is_empty() {
            return;
        }
        let eps = series.column("axial_strain").unwrap_or_default();
        let (x, y) = (
            series.column("stress_lateral_x").unwrap_or_default(),
            series.column("stress_lateral_y").unwrap_or_default(),
        );
        let lateral: Vec<f64> = x.iter().zip(&y).map(|(a, b)| 0.5 * (a + b)).collect();
        let columns = [
            ("stress_at_strain", axial_stress_column(series)),
            (
                "stress_driven_at_strain",
                series.column("stress_driven").unwrap_or_default(),
            ),
            (
                "stress_opposite_at_strain",
                series.column("stress_opposite").unwrap_or_default(),
            ),
            ("stress_lateral_at_strain", lateral),
        ];
        for (key, column) in columns {
            let mut at = serde_json::Map::new();
            for e in &strains {
                if let Some(v) = interpolate(&eps, &column, *e) {
                    at.insert(format!("{e}"), v.into());
                }
            }
            m.insert(key.into(), Value::Object(at));
        }
    }

    /// psd.csv: the sieve curves (mass fraction finer than each equivalent diameter) at the
    /// start and at each report strain reached.
    pub fn psd_csv(&self) -> Option<String> {
        if self.state.psd.is_empty() || self.state.fracture.is_none() {
            return None;
        }
        let curves: Vec<&Vec<(f64, f64)>> = self.state.psd.iter().map(|(_, p)| p).collect();
        let sieves =
            size_distribution::sieve_sizes(curves.iter().flat_map(|c| c.iter().map(|p| p.1)), 40);
        let passing: Vec<Vec<f64>> = curves
            .iter()
            .map(|c| size_distribution::passing(c, &sieves))
            .collect();
        let mut s = String::from("diameter");
        for (e, _) in &self.state.psd {
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
}

/// Axial stress of each series row: the mean of the top and bottom faces (Pa).
fn axial_stress_column(series: &Series) -> Vec<f64> {
    match (
        series.column("stress_driven"),
        series.column("stress_opposite"),
    ) {
        (Some(a), Some(b)) => a.iter().zip(&b).map(|(x, y)| 0.5 * (x + y)).collect(),
        _ => Vec::new(),
    }
}

impl Model for Granular {
    const KIND: &'static str = "granular";
    type Raw = scene::RawGranularScene;
    type Config = GranularScene;
    const BODY: &'static str = "body";
    const EFFECTS: &'static [EffectKind] = &scene::EFFECTS;
    const INTEGRATORS: &'static [IntegratorKind] = &[IntegratorKind::VelocityVerlet];
    const SHARED_KEYS: &'static [&'static str] = &["output.report_strains"];

    fn config(scene: &Scene, raw: &scene::RawGranularScene) -> Result<GranularScene> {
        scene::validate(scene, raw)
    }

    fn explain(scene: &Scene, cfg: &GranularScene) -> Result<String> {
        explain::explain(scene, cfg)
    }

    fn build(
        scene: &Scene,
        cfg: GranularScene,
        progress: &mut (dyn FnMut(&str) + Send),
    ) -> Result<Built<Self>> {
        let sample = sample::build(scene, &cfg, progress)?;
        Granular::from_sample(scene, cfg, sample)
    }

    fn save(&self) -> Vec<u8> {
        postcard::to_stdvec(&(&self.state, self.pipeline.save()))
            .expect("the granular state serialises")
    }

    fn restore(scene: &Scene, cfg: GranularScene, bytes: &[u8]) -> Result<Self> {
        type Saved = (GranularState, Vec<(String, Vec<u8>)>);
        let (state, effects): Saved = postcard::from_bytes(bytes)
            .map_err(|e| Error::run(format!("the checkpoint's granular state is damaged ({e})")))?;
        state.check_lengths().map_err(|why| {
            Error::run(format!("the saved granular state is inconsistent: {why}"))
        })?;
        let mut model = Granular::with_state(scene, cfg, state);
        model.pipeline.restore(&effects, model.state.bodies.len())?;
        Ok(model)
    }

    fn bodies(&self) -> usize {
        self.state.bodies.len()
    }

    /// Poly-ellipsoids (a Newton solve per pair): every thread. Spheres: one thread per
    /// `TEAM_MIN_SPHERES_PER_THREAD`, at most `threads`: a sphere pair costs tens of
    /// nanoseconds, and handing half the bodies to another core (whose cache then fetches the
    /// bodies the caller just moved) cost more than it saved (2-core CI machine, 1000 dense
    /// spheres: 0.92x of one thread on the team, 0.86x at 2000 with rayon). Before, a run
    /// with more threads than its spheres paid for took none of them (8000 spheres on a
    /// 16-core machine: 3.35e6 particle-steps/s on 1 thread, 5.49e6 on 4, 3.04e6 on 16).
    fn team_members(&self, threads: usize) -> usize {
        let b = &self.state.bodies;
        if b.shape.iter().any(|s| !s.is_sphere()) {
            threads
        } else {
            (b.len() / TEAM_MIN_SPHERES_PER_THREAD).clamp(1, threads.max(1))
        }
    }

    fn step(&mut self, _clock: &Clock, dt: f64) {
        let st = &mut self.state;
        st.loading.apply(&mut st.walls);
        self.integrator.kick_drift(&mut st.bodies, &st.forces, dt);
        st.walls.advance(dt);
        self.evaluate_forces(dt, true);
        let st = &mut self.state;
        self.integrator.kick(&mut st.bodies, &st.forces, dt);
    }

    fn after_step(&mut self, clock: &mut Clock, dt: f64) {
        if self.state.fracture.is_some() {
            self.after_fracture_step(clock, dt);
        }
    }

    fn check_step(
        &mut self,
        scene: &Scene,
        clock: &mut Clock,
        warn: &mut Vec<String>,
    ) -> Result<()> {
        let adapting = self.state.fracture.is_some() && self.auto_dt;
        if adapting && clock.step % STABILITY_EVERY != 0 && clock.step != clock.end_step {
            return Ok(());
        }
        self.check_stability(scene, clock, warn)
    }

    /// Grains packed beyond full density: in a box whose faces are driven (the SHPB faces, an
    /// oedometer) the grains' volume over the box's exceeds 1, so they overlap by more than all
    /// the pore space and Hertz contacts (a small-overlap law) describe nothing; left alone, a
    /// face driven at 1e4 m/s crossed the specimen with every grain touching every other and
    /// the neighbour search slowed to a crawl. The grains' volume changes only when
    /// one splits, so it is cached by body count.
    fn fault(&self, _clock: &Clock) -> Option<String> {
        if let Some(why) = &self.collapsed {
            return Some(why.clone());
        }
        let st = &self.state;
        if !st.walls.is_box || matches!(st.loading, Loading::None { .. }) {
            return None;
        }
        let size = st.walls.box_size();
        let n = st.bodies.len();
        let solid = match self.solid_volume.get() {
            Some((count, v)) if count == n => v,
            _ => {
                let v = st.bodies.solid_volume();
                self.solid_volume.set(Some((n, v)));
                v
            }
        };
        let fraction = solid / (size.x * size.y * size.z);
        (fraction > 1.0 || size.min() <= 0.0).then(|| {
            format!(
                "the grains fill {fraction:.3} of the box (axial strain {:.3}): they overlap by more than all the pore space, beyond what contact mechanics describes; the faces were driven faster or further than the specimen can follow (lower the face speeds or loading.end_strain)",
                (st.height0 - size.z) / st.height0
            )
        })
    }

    fn row(&mut self, clock: &Clock) -> Vec<f64> {
        let st = &self.state;
        let contacts = self.pipeline.contacts();
        let mut row = if matches!(st.loading, Loading::Platens { .. }) {
            probe::platen_row(clock.time, st.height0, &st.bodies, &st.walls, contacts)
        } else if st.walls.is_box {
            probe::box_row(clock.time, st.height0, &st.bodies, &st.walls, contacts)
        } else {
            probe::free_row(clock.time, &st.bodies, contacts)
        };
        if let (Some(f), Some(e)) = (&st.fracture, &st.energy) {
            let now = self.mechanical_energy();
            row.extend_from_slice(&[
                st.bodies.len() as f64,
                f.broken_particles() as f64,
                f.fragments(st.bodies.len()) as f64,
                f.intact_springs() as f64,
                now.elastic,
                e.boundary_work,
                e.dissipated,
                -f.spring_work,
            ]);
        }
        row
    }

    fn first_non_finite(&self) -> Option<usize> {
        self.state.bodies.first_non_finite()
    }

    fn instability_hint(&self, scene: &Scene, _clock: &Clock) -> String {
        format!("lower time.safety (now {}) or time.dt", scene.time.safety)
    }

    fn summary(&self, run: &RunInfo, m: &mut Map<String, Value>) {
        let st = &self.state;
        m.insert("dt_rayleigh".into(), st.dt_rayleigh.into());
        m.insert(
            "sample".into(),
            serde_json::to_value(&st.sample).expect("sample info serialises"),
        );
        m.insert(
            "solid_fraction_initial".into(),
            st.sample.solid_fraction.into(),
        );
        m.insert("contacts_final".into(), self.pipeline.contacts().into());
        m.insert("initial_mean_stress".into(), st.initial[0].into());
        m.insert("initial_coordination".into(), st.initial[1].into());
        m.insert("max_omega_dt".into(), st.max_omega_dt.into());
        if st.fracture.is_some() {
            m.insert("dt_shortened".into(), st.dt_shortened.into());
        }
        m.insert(
            "kinetic_energy_final".into(),
            st.bodies.kinetic_energy().into(),
        );
        st.loading.summarize(run.series, m);
        self.stress_summary(run.series, m);
        if let Some(f) = &st.fracture {
            self.fracture_summary(f, m);
        }
    }

    fn snapshot(&self) -> Vec<(&'static str, String)> {
        let st = &self.state;
        let mut files = vec![("particles", vtk::particles_vtu(&st.bodies, &st.forces))];
        if st.walls.is_box {
            files.push(("walls", vtk::box_walls_vtu(&st.walls)));
        }
        if st.fracture.is_some() || st.bodies.shape.iter().any(|s| !s.is_sphere()) {
            let origin = st.fracture.as_ref().map_or(&[][..], |f| &f.origin[..]);
            files.push(("grains", vtk::grains_vtu(&st.bodies, origin)));
        }
        files
    }

    fn extra_outputs(&self) -> Vec<(String, Vec<u8>)> {
        self.psd_csv()
            .map(|csv| vec![("psd.csv".to_string(), csv.into_bytes())])
            .unwrap_or_default()
    }

    fn status(&self, clock: &Clock) -> String {
        format!(
            "t = {:.4e} s, strain {:.4}",
            clock.time,
            self.axial_strain()
        )
    }

    fn rigid_bodies(&self) -> Option<&Bodies> {
        Some(&self.state.bodies)
    }

    fn radii(&self) -> Option<Vec<f64>> {
        Some(self.state.bodies.radius.clone())
    }

    fn grain_loads(&self) -> Option<Vec<crate::fracture::GrainLoad>> {
        let f = self.state.fracture.as_ref()?;
        let mut loads = f.loads().to_vec();
        loads.resize(self.state.bodies.len(), Default::default());
        Some(loads)
    }

    fn contacts(&self) -> Option<usize> {
        Some(self.pipeline.contacts())
    }

    fn faces_mut(&mut self) -> Option<&mut dyn Faces> {
        self.state.walls.is_box.then_some(self as &mut dyn Faces)
    }

    fn faces(&self) -> Option<&dyn Faces> {
        self.state.walls.is_box.then_some(self as &dyn Faces)
    }
}

impl Faces for Granular {
    fn set_face_speeds(&mut self, top: f64, bottom: f64) -> Result<()> {
        if !self.state.walls.is_box {
            return Err(Error::run(
                "face speeds need a sample in a box (random, lattice or file packing)",
            ));
        }
        if !(top.is_finite() && bottom.is_finite()) {
            return Err(Error::run(format!(
                "face speeds must be finite, got top {top} and bottom {bottom} m/s"
            )));
        }
        self.state.loading = Loading::Faces { top, bottom };
        Ok(())
    }

    fn face_forces(&self) -> (f64, f64) {
        let w = &self.state.walls;
        if !w.is_box {
            return (0.0, 0.0);
        }
        (
            w.face(BoxFace::ZMax).normal_force(),
            w.face(BoxFace::ZMin).normal_force(),
        )
    }

    fn face_stresses(&self) -> (f64, f64) {
        let w = &self.state.walls;
        if !w.is_box {
            return (0.0, 0.0);
        }
        (w.face_stress(BoxFace::ZMax), w.face_stress(BoxFace::ZMin))
    }

    fn face_area(&self) -> f64 {
        let size = self.state.walls.box_size();
        size.x * size.y
    }

    fn axial_strain(&self) -> f64 {
        Granular::axial_strain(self)
    }
}

impl Runner<Granular> {
    /// A granular run on a sample made elsewhere (tests, benchmarks, exports).
    pub fn from_sample(scene: Scene, sample: Sample, threads: usize) -> Result<Self> {
        let cfg = Granular::read(&scene)?;
        let built = Granular::from_sample(&scene, cfg, sample)?;
        Runner::from_built(scene, built, threads)
    }

    /// Splits the given grains now (see [`Granular::break_grains`]).
    pub fn break_grains(&mut self, breaking: &[crate::fracture::Breaking]) -> usize {
        let (model, clock) = (&mut self.model, &mut self.clock);
        model.break_grains(clock, breaking)
    }
}
