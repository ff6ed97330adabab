//! The `dlsm` model's run: Voronoi elements joined by the distinct lattice spring model
//! (dlsm paper).
//!
//! ```text
//! loading.prescribe        prescribed velocity components for the step
//! kick_drift               Tchamwa–Wielgosz first stage (Eq. 37–38)
//! bonds.evaluate           cohesive forces and moments (Eq. 1–34), breaking (Eq. 36)
//! effects                  broken contacts (fracture), ground (contact, friction), gravity
//! loading.constrain        reactions out of the prescribed components
//! kick                     second stage
//! every output.every steps: check finite, a row of series.csv, stop after failure
//! ```
//!
//! Only the effects the scene lists are built: without `fracture` no contact can break and
//! no polyhedron contact is looked for; without `contact` there is no ground.

pub mod accuracy;
pub mod bench;
mod explain;
pub mod loading;
pub mod sample;
pub mod scene;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use crate::bond::dlsm::DlsmBonds;
use crate::contact::polyhedron::{BrokenContacts, GroundContact};
use crate::error::{Error, Result};
use crate::integrate::TchamwaWielgosz;
use crate::output::vtk;
use crate::run::{Built, Clock, Model, RunInfo, Runner, end_step};
use crate::sample::voronoi::Domain;
use crate::scene::{DtSpec, EffectKind, IntegratorKind, Scene};
use crate::shape::polyhedron::Polyhedron;
use crate::state::{Bodies, Forces, Vec3};
use loading::{Brazilian, DlsmLoading, RowInputs, Setting};
use sample::{DlsmSample, DlsmSampleInfo};
use scene::DlsmScene;

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
    /// `gravity`.
    pub gravity: Option<Vec3>,
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
    /// `fracture`: the contacts broken bonds leave.
    pub broken: Option<BrokenContacts>,
    /// `contact` (with `friction`): the ground.
    pub ground: Option<GroundContact>,
    pub loading: DlsmLoading,
    /// True once the loading has found the specimen failed.
    pub stopped: bool,
}

impl Dlsm {
    /// The model on a freshly built sample, at t = 0 with nothing broken, and its step.
    fn assemble(scene: &Scene, cfg: DlsmScene, s: DlsmSample) -> Result<(Self, f64, Vec<String>)> {
        let DlsmSample {
            domain,
            bodies,
            shapes,
            seeds,
            bonds,
            boundary: _,
            info,
        } = &s;
        let m = &cfg.material;
        let loading = DlsmLoading::build(&Setting {
            scene,
            cfg: &cfg,
            sample: &s,
        })?;
        let tensile_strength = if scene.has_effect(EffectKind::Fracture) {
            m.tensile_strength
        } else {
            None
        };
        let broken = tensile_strength.map(|_| BrokenContacts::new(m.friction, m.poisson));
        let ground = match (
            &loading,
            m.contact_stiffness,
            scene.has_effect(EffectKind::Contact),
        ) {
            (DlsmLoading::Drop(d), Some(k), true) => Some(GroundContact::new(
                d.ground_point,
                d.ground_normal,
                k,
                if scene.has_effect(EffectKind::Friction) {
                    m.friction
                } else {
                    0.0
                },
                bodies.len(),
            )),
            _ => None,
        };
        let gravity = scene
            .has_effect(EffectKind::Gravity)
            .then(|| Vec3::from(scene.gravity.acceleration));
        let dt_critical = bonds.critical_time_step(&bodies.mass);
        let dt_rotational = rotational_time_step(bodies, bonds);
        // Eq. 39 bounds the translational springs; the rotational ones (K S, Eq. 31) are
        // stiffer for their inertia, so their counterpart bounds the step too.
        let mut dt_limit = dt_critical.min(dt_rotational);
        let platens = match &loading {
            DlsmLoading::Brazilian(l) => l.platens.iter().collect(),
            _ => Vec::new(),
        };
        for g in ground.iter().chain(platens) {
            let lightest = bodies.mass.iter().copied().fold(f64::INFINITY, f64::min);
            dt_limit = dt_limit.min((lightest / g.stiffness).sqrt());
        }
        if let DlsmLoading::Brazilian(Brazilian {
            pressure: Some(arc),
            ..
        }) = &loading
        {
            dt_limit = dt_limit.min(arc.step_bound(bodies));
        }
        let dt = scene.time.step(dt_limit);
        let phi = match scene.time.integrator {
            IntegratorKind::TchamwaWielgosz => scene.time.phi.unwrap_or(DEFAULT_PHI),
            _ => 0.5,
        };
        let mut warnings = Vec::new();
        if !dt_critical.is_finite() {
            warnings.push("the sample has no cohesive contact".to_string());
        }
        if phi < 1.5 {
            warnings.push(format!(
                "phi = {phi}: the lattice has slowly growing (flutter) modes that phi of about 2 (time.integrator = \"tchamwa_wielgosz\") damps at a third of the critical step; runs of more than a few thousand steps may diverge"
            ));
        }
        let mut bodies = bodies.clone();
        let reference = bodies.pos.clone();
        if let DlsmLoading::FreeVibration(v) = &loading {
            for (p, seed) in bodies.pos.iter_mut().zip(seeds) {
                *p += v.initial_displacement(seed);
            }
        }
        if let DlsmLoading::Drop(_) = &loading {
            let v0 = Vec3::from(match cfg.loading {
                scene::LoadingSpec::Drop(d) => d.initial_velocity,
                _ => [0.0; 3],
            });
            bodies.vel.iter_mut().for_each(|v| *v = v0);
        }
        let model = Dlsm {
            bonds: bonds.clone(),
            shapes: shapes.clone(),
            domain: *domain,
            reference,
            sample: info.clone(),
            integrator: TchamwaWielgosz::new(phi),
            tensile_strength,
            gravity,
            dt_critical,
            dt_rotational,
            energy_fault: None,
            cfg,
            state: DlsmState {
                forces: Forces::new(bodies.len()),
                bodies,
                broken_order: Vec::new(),
                break_log: Vec::new(),
                first_break: None,
                broken,
                ground,
                loading,
                stopped: false,
            },
        };
        Ok((model, dt, warnings))
    }

    /// Refuses a step the lattice cannot survive, at build (a restored run was checked when
    /// it was built). The scheme is stable for ω dt < √(2/φ) (φ = ½: velocity Verlet's 2).
    /// Eq. 39 bounds one spring at a time with E; the lattice's own highest frequency (each
    /// element held by all its springs, stiffness from λ + 2μ and μ) lies above 1/dt_limit, by
    /// a factor that grows towards ν = 0.5 and ν = -1: computed here on the undeformed
    /// lattice, it refuses the step instead of letting the run blow up.
    fn check_step(&self, scene: &Scene, dt: f64) -> Result<()> {
        let mut undeformed = self.state.bodies.clone();
        undeformed.pos.clone_from(&self.reference);
        let (omega_max, stiffest) =
            lattice_highest_frequency(&undeformed, &self.bonds, &self.state.loading, 60);
        let phi = self.integrator.phi;
        let stable = (2.0 / phi).sqrt() / omega_max;
        if dt <= stable {
            return Ok(());
        }
        let (key, value, fix) = match scene.time.dt {
            DtSpec::Auto => (
                "time.safety",
                format!("{}", scene.time.safety),
                format!(
                    "set time.safety below {:.3}",
                    stable / dt * scene.time.safety
                ),
            ),
            DtSpec::Seconds(v) => (
                "time.dt",
                format!("{v:e} s"),
                format!("set time.dt below {stable:.3e} s"),
            ),
        };
        Err(scene.key_error(
            key,
            format!(
                "= {value} gives a step of {dt:.3e} s, above this lattice's stability limit of {stable:.3e} s (its highest vibration frequency, computed at build, is {omega_max:.4e} rad/s, at element {stiffest}; the scheme needs ω dt < √(2/φ) = {:.3} for φ = {phi}): {fix}",
                (2.0 / phi).sqrt()
            ),
        ))
    }

    /// Forces and torques at the current positions, which are those of time `at`: bonds,
    /// effects, platens, reactions. `clock` is where the run is (breaks are logged at its step).
    fn evaluate_forces(&mut self, clock: &Clock, at: f64) {
        let strength = self.tensile_strength;
        let st = &mut self.state;
        let broke = self.bonds.evaluate(&st.bodies, &mut st.forces, strength);
        if !broke.is_empty() {
            self.record_breaks(clock, &broke);
        }
        let st = &mut self.state;
        if let Some(b) = &mut st.broken {
            b.accumulate(&st.bodies, &self.shapes, &mut st.forces, clock.dt);
        }
        if let Some(g) = &mut st.ground {
            g.accumulate(&st.bodies, &self.shapes, &mut st.forces, clock.dt);
        }
        if let Some(g) = self.gravity {
            for (f, &m) in st.forces.force.iter_mut().zip(&st.bodies.mass) {
                *f += g * m;
            }
        }
        let loading = st.loading.as_loading_mut();
        loading.press(&st.bodies, &self.shapes, &mut st.forces, at, clock.dt);
        loading.constrain(&mut st.forces);
    }

    fn record_breaks(&mut self, clock: &Clock, broke: &[usize]) {
        let st = &mut self.state;
        let mid = |c: usize| {
            let [i, j] = self.bonds.pair[c];
            0.5 * (st.bodies.pos[i as usize] + st.bodies.pos[j as usize])
        };
        if st.first_break.is_none() {
            st.first_break = Some(FirstBreak {
                step: clock.step,
                contact: broke[0],
                position: mid(broke[0]),
                time: clock.time,
            });
        }
        for &c in broke {
            st.broken_order.push(c as u32);
            st.break_log.push((clock.step, mid(c)));
            if let Some(b) = &mut st.broken {
                let k = self.bonds.young * self.bonds.area[c] / self.bonds.length0[c];
                b.add(self.bonds.pair[c], k);
            }
        }
    }

    /// The model's summary keys (after those every model shares).
    fn summary_keys(&self, run: &RunInfo, m: &mut Map<String, Value>) {
        let st = &self.state;
        m.insert("elements".into(), st.bodies.len().into());
        m.insert(
            "sample".into(),
            serde_json::to_value(&self.sample).expect("sample info serialises"),
        );
        m.insert("contacts".into(), self.bonds.contacts().into());
        m.insert("broken_contacts".into(), st.broken_order.len().into());
        m.insert("dt_critical".into(), self.dt_critical.into());
        m.insert("dt_rotational".into(), self.dt_rotational.into());
        m.insert("phi".into(), self.integrator.phi.into());
        m.insert("stopped_after_failure".into(), st.stopped.into());
        m.insert(
            "kinetic_energy_final".into(),
            st.bodies.kinetic_energy().into(),
        );
        let dt_row = run.scene.output.every as f64 * run.clock.dt;
        let mut series = run.series.clone();
        if matches!(st.loading, DlsmLoading::FreeVibration(_)) {
            // The spectrum needs evenly spaced rows: drop a last row off the grid.
            let off = |r: &Vec<f64>| {
                let k = r[0] / dt_row;
                (k - k.round()).abs() > 1e-6
            };
            if series.rows.last().is_some_and(off) {
                series.rows.pop();
            }
        }
        st.loading.as_loading().summarize(&series, dt_row, m);
        if let Some(fb) = &st.first_break {
            m.insert("first_break_step".into(), fb.step.into());
            m.insert("first_break_time".into(), fb.time.into());
            m.insert(
                "first_break_position".into(),
                serde_json::json!([fb.position.x, fb.position.y, fb.position.z]),
            );
            if let Domain::Disc { diameter, .. } = self.domain {
                let offset = |p: &Vec3| p.x.hypot(p.y) / diameter;
                m.insert("crack_start_offset".into(), offset(&fb.position).into());
                // The macroscopic crack: the first contact to break once the load is within
                // 5% of its peak (isolated breaks under the loading arcs come earlier).
                if let Some(force) = run.series.column("force") {
                    let peak = force.iter().copied().fold(0.0, f64::max);
                    let row_step = |k: usize| (run.series.rows[k][0] / run.clock.dt).round() as u64;
                    if let Some(k) = force.iter().position(|&f| f >= 0.95 * peak) {
                        let from = if k > 0 { row_step(k - 1) } else { 0 };
                        if let Some((_, p)) = st.break_log.iter().find(|(s, _)| *s >= from) {
                            m.insert("main_crack_start_offset".into(), offset(p).into());
                        }
                    }
                }
                // The crack's path, once the disc has split: the share of the broken contacts
                // within a tenth of D of the loaded (y) diameter.
                if st.stopped {
                    let near = st
                        .break_log
                        .iter()
                        .filter(|(_, p)| p.x.abs() < 0.1 * diameter)
                        .count();
                    m.insert(
                        "crack_band_fraction".into(),
                        (near as f64 / st.break_log.len() as f64).into(),
                    );
                }
            }
        }
    }

    /// The elements as a polyhedral mesh for ParaView.
    pub fn elements_vtu(&self) -> String {
        vtk::polyhedra_vtu(
            &self.state.bodies,
            &self.shapes,
            &self.state.forces,
            &self.reference,
        )
    }
}

impl Model for Dlsm {
    const KIND: &'static str = "dlsm";
    type Raw = scene::RawDlsmScene;
    type Config = DlsmScene;
    const BODY: &'static str = "element";
    const EFFECTS: &'static [EffectKind] = &scene::EFFECTS;
    const INTEGRATORS: &'static [IntegratorKind] = &[
        IntegratorKind::VelocityVerlet,
        IntegratorKind::TchamwaWielgosz,
    ];
    const SHARED_KEYS: &'static [&'static str] = &["time.phi"];

    fn config(scene: &Scene, raw: &scene::RawDlsmScene) -> Result<DlsmScene> {
        scene::validate(scene, raw)
    }

    fn explain(scene: &Scene, cfg: &DlsmScene) -> Result<String> {
        explain::explain(scene, cfg)
    }

    fn build(
        scene: &Scene,
        cfg: DlsmScene,
        progress: &mut (dyn FnMut(&str) + Send),
    ) -> Result<Built<Self>> {
        let s = sample::build(scene, &cfg, progress)?;
        let (mut model, dt, warnings) = Dlsm::assemble(scene, cfg, s)?;
        model.check_step(scene, dt)?;
        let columns = model.state.loading.as_loading().columns();
        let end_time = model.state.loading.as_loading().end_time();
        crate::run::check_planned_steps(scene, model.cfg.material.young, end_time, dt)?;
        let end = end_step(end_time, dt);
        let start = Clock {
            time: 0.0,
            step: 0,
            dt,
            end_step: end,
            end_time,
        };
        model
            .state
            .loading
            .as_loading()
            .prescribe(&mut model.state.bodies, 0.0);
        model.evaluate_forces(&start, 0.0);
        Ok(Built {
            model,
            dt,
            end_step: end,
            end_time,
            columns,
            warnings,
        })
    }

    fn save(&self) -> Vec<u8> {
        postcard::to_stdvec(&self.state).expect("the dlsm state serialises")
    }

    fn restore(scene: &Scene, cfg: DlsmScene, bytes: &[u8]) -> Result<Self> {
        let state: DlsmState = postcard::from_bytes(bytes)
            .map_err(|e| Error::run(format!("the checkpoint's dlsm state is damaged ({e})")))?;
        let s = sample::build(scene, &cfg, &mut |_| {})?;
        let (mut model, _, _) = Dlsm::assemble(scene, cfg, s)?;
        if state.bodies.len() != model.state.bodies.len() {
            return Err(Error::run(
                "the checkpoint's elements do not match the sample its scene builds",
            ));
        }
        let ids: Vec<usize> = state.broken_order.iter().map(|&c| c as usize).collect();
        model.bonds.break_contacts(&ids);
        // Effects the scene does not build stay unbuilt.
        let (broken, ground) = (model.state.broken.is_some(), model.state.ground.is_some());
        model.state = state;
        if !broken {
            model.state.broken = None;
        }
        if !ground {
            model.state.ground = None;
        }
        Ok(model)
    }

    fn bodies(&self) -> usize {
        self.state.bodies.len()
    }

    fn step(&mut self, clock: &Clock, dt: f64) {
        self.state
            .loading
            .as_loading()
            .prescribe(&mut self.state.bodies, clock.time + 0.5 * dt);
        let st = &mut self.state;
        self.integrator.kick_drift(&mut st.bodies, &st.forces, dt);
        // Breaks are logged at the step being taken, at its start time.
        let during = Clock { dt, ..*clock };
        self.evaluate_forces(&during, clock.time + dt);
        let st = &mut self.state;
        self.integrator.kick(&mut st.bodies, &st.forces, dt);
    }

    fn stopped(&self) -> bool {
        self.state.stopped
    }

    fn row(&mut self, clock: &Clock) -> Vec<f64> {
        let st = &mut self.state;
        let drop = matches!(
            st.loading,
            DlsmLoading::Drop(_) | DlsmLoading::FreeVibration(_)
        );
        let inputs = RowInputs {
            time: clock.time,
            bodies: &st.bodies,
            reference: &self.reference,
            broken: st.broken_order.len(),
            strain_energy: if drop {
                self.bonds.strain_energy(&st.bodies)
            } else {
                0.0
            },
            contact_energy: st.ground.as_ref().map_or(0.0, |g| g.energy),
            ground_contacts: st.ground.as_ref().map_or(0, |g| g.contacts),
        };
        st.loading.as_loading_mut().row(&inputs)
    }

    fn after_row(&mut self, _clock: &Clock, series: &crate::probe::Series) {
        if self.state.loading.as_loading().failed(series) {
            self.state.stopped = true;
        }
        // Free vibration and the drop put no work in after the start: their total energy can
        // only fall (the scheme and the ground dissipate). The strain energy is an estimate
        // (exact for uniform strain), hence the margin; growth past it is a growing mode,
        // which ran to 1e13 J before the run noticed anything.
        if let Some(k) = series.index("total_energy")
            && let (Some(first), Some(last)) = (series.rows.first(), series.rows.last())
            && last[k] > ENERGY_GROWTH_LIMIT * first[k]
        {
            let (first, now) = (first[k], last[k]);
            let phi = self.integrator.phi;
            let cause = if phi < 1.5 {
                format!(
                    "a growing mode: at φ = {phi}, below 1.5, the flutter of the springs (which do not derive from a potential) is not damped; raise time.phi to 2"
                )
            } else {
                "a growing mode, from a step too long for the lattice; lower time.safety"
                    .to_string()
            };
            self.energy_fault = Some(format!(
                "the lattice's total energy (kinetic + strain{}) grew to {now:.4e} J, {:.3} times its initial {first:.4e} J, with no work put in: {cause}",
                if matches!(self.state.loading, DlsmLoading::Drop(_)) {
                    " + potential + ground contact"
                } else {
                    ""
                },
                now / first,
            ));
        }
    }

    fn fault(&self, _clock: &Clock) -> Option<String> {
        self.energy_fault.clone()
    }

    fn first_non_finite(&self) -> Option<usize> {
        self.state.bodies.first_non_finite()
    }

    fn instability_hint(&self, scene: &Scene, _clock: &Clock) -> String {
        format!("lower time.safety (now {}) or time.dt", scene.time.safety)
    }

    fn summary(&self, run: &RunInfo, m: &mut Map<String, Value>) {
        self.summary_keys(run, m);
    }

    fn snapshot(&self) -> Vec<(&'static str, String)> {
        vec![("elements", self.elements_vtu())]
    }

    fn status(&self, clock: &Clock) -> String {
        format!(
            "t = {:.4e} s, {} broken contacts",
            clock.time,
            self.state.broken_order.len()
        )
    }

    fn rigid_bodies(&self) -> Option<&Bodies> {
        Some(&self.state.bodies)
    }
}

/// The rotational counterpart of Eq. 39: the smallest `sqrt(I_ij / (K S))` over the contacts,
/// with `I_ij = I_i I_j / (I_i + I_j)` of the smallest principal moments (s).
fn rotational_time_step(bodies: &Bodies, bonds: &DlsmBonds) -> f64 {
    let mut dt = f64::INFINITY;
    for (c, p) in bonds.pair.iter().enumerate() {
        let (a, b) = (
            bodies.inertia[p[0] as usize].min(),
            bodies.inertia[p[1] as usize].min(),
        );
        let inertia = a * b / (a + b);
        let k = bonds.young * bonds.length0[c] * bonds.area[c];
        dt = dt.min((inertia / k).sqrt());
    }
    dt
}

/// The lattice's highest vibration frequency (rad/s) at its built configuration, computed by
/// `iterations` power iterations ([`crate::probe::modes`]) with the stiffness applied as a
/// forward difference of the springs' forces (no breaking), the loaded elements held as the
/// loading holds them; and the element that moves most in that mode. Ground contact and
/// gravity are left out (the ground's own bound is in the step limit).
pub fn lattice_highest_frequency(
    bodies: &Bodies,
    bonds: &DlsmBonds,
    loading: &DlsmLoading,
    iterations: usize,
) -> (f64, usize) {
    use crate::probe::modes::{
        MassScale, highest_eigenvalue, largest_motion, stiffness_by_difference,
    };
    let n = bodies.len();
    if n == 0 || bonds.contacts() == 0 {
        return (0.0, 0);
    }
    let length = bonds.length0.iter().copied().fold(f64::INFINITY, f64::min);
    let mut bonds = bonds.clone();
    let mut loading = loading.clone();
    let mut forces = Forces::new(n);
    let mut evaluate = |b: &Bodies| {
        bonds.evaluate(b, &mut forces, None);
        loading.as_loading_mut().constrain(&mut forces);
        forces
            .force
            .iter()
            .zip(&forces.torque)
            .map(|(f, t)| (*f, *t))
            .collect::<Vec<_>>()
    };
    let base = evaluate(bodies);
    let scale = MassScale::of(bodies);
    let mut trial = bodies.clone();
    let (lambda, mode) = highest_eigenvalue(n, iterations, |w, out| {
        stiffness_by_difference(
            bodies,
            &scale,
            length,
            &base,
            &mut trial,
            w,
            out,
            &mut evaluate,
        )
    });
    (lambda.sqrt(), largest_motion(&mode).0)
}
