//! The `dlsm` model's run: Voronoi elements joined by the distinct lattice spring model
//! (dlsm-voronoi-brittle-elastic.txt).
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

pub mod bench;
pub mod sample;

use std::fmt::Write;
use std::sync::Arc;

use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::bond::dlsm::DlsmBonds;
use crate::contact::polyhedron::{BrokenContacts, GroundContact};
use crate::error::{Error, Result};
use crate::integrate::TchamwaWielgosz;
use crate::loading::dlsm::{
    Brazilian, DlsmLoading, Drop, FreeVibration, RowInputs, Tension, arc_factor,
};
use crate::output::vtk;
use crate::probe::Series;
use crate::run::{self, Run};
use crate::sample::voronoi::{BOX_FACES, Boundary, Domain};
use crate::scene::{DtSpec, EffectKind, IntegratorKind, LoadingKind, Scene, VibrationMode};
use crate::shape::polyhedron::Polyhedron;
use crate::simulation::{on_threads, thread_pool};
use crate::state::{Bodies, Forces, Vec3};
use sample::{DlsmSample, DlsmSampleInfo};

/// φ of the Tchamwa–Wielgosz scheme when the scene does not give one. The paper uses
/// 1 ≤ φ ≤ 1.3; the lattice's flutter modes need about 2 at a third of the critical step
/// (docs/validation.md).
pub const DEFAULT_PHI: f64 = 2.0;
/// Default ramp of prescribed speeds, as a fraction of the loading time.
const DEFAULT_RAMP: f64 = 0.1;
/// Default `stop_fraction` with fracture.
const DEFAULT_STOP: f64 = 0.2;

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

pub struct DlsmRun {
    pub scene: Scene,
    pub bodies: Bodies,
    /// Forces and torques of the last evaluation.
    pub forces: Forces,
    pub bonds: DlsmBonds,
    pub shapes: Vec<Polyhedron>,
    pub domain: Domain,
    /// Undeformed centroids.
    pub reference: Vec<Vec3>,
    pub sample: DlsmSampleInfo,
    pub integrator: TchamwaWielgosz,
    /// `fracture`: the strength and the contacts broken bonds leave.
    pub tensile_strength: Option<f64>,
    pub broken: Option<BrokenContacts>,
    /// Broken contacts in the order they broke, with the step and the midpoint of the two
    /// seeds at breaking.
    pub broken_order: Vec<u32>,
    pub break_log: Vec<(u64, Vec3)>,
    pub first_break: Option<FirstBreak>,
    /// `contact` (with `friction`): the ground.
    pub ground: Option<GroundContact>,
    /// `gravity`.
    pub gravity: Option<Vec3>,
    pub loading: DlsmLoading,
    pub series: Series,
    pub time: f64,
    pub step: u64,
    pub dt: f64,
    /// Eq. 39 without its factor (s), and the rotational counterpart.
    pub dt_critical: f64,
    pub dt_rotational: f64,
    pub end_step: u64,
    /// True once the loading has found the specimen failed.
    pub stopped: bool,
    pub warnings: Vec<String>,
    pool: Option<Arc<rayon::ThreadPool>>,
}

/// The persistent state, as a checkpoint stores it; the sample is rebuilt from the scene.
#[derive(Serialize, Deserialize)]
struct DlsmState {
    bodies: Bodies,
    forces: Forces,
    broken_order: Vec<u32>,
    break_log: Vec<(u64, Vec3)>,
    first_break: Option<FirstBreak>,
    broken: Option<BrokenContacts>,
    ground: Option<GroundContact>,
    loading: DlsmLoading,
    series: Series,
    time: f64,
    step: u64,
    dt: f64,
    stopped: bool,
    warnings: Vec<String>,
}

impl DlsmRun {
    /// Builds the scene's sample and sets the run up. `threads` = 0 uses every core.
    pub fn new(
        scene: Scene,
        threads: usize,
        progress: &mut (dyn FnMut(&str) + Send),
    ) -> Result<Self> {
        let pool = thread_pool(threads)?;
        let s = sample::build(&scene, progress)?;
        let mut run = DlsmRun::assemble(scene, s, pool)?;
        run.start();
        run.evaluate_forces();
        run.record_row();
        Ok(run)
    }

    /// Restores a run from the bytes [`Run::save_state`] wrote.
    pub fn restore(scene: Scene, bytes: &[u8], threads: usize) -> Result<Self> {
        let state: DlsmState = postcard::from_bytes(bytes)
            .map_err(|e| Error::run(format!("the checkpoint's dlsm state is damaged ({e})")))?;
        let s = sample::build(&scene, &mut |_| {})?;
        let mut run = DlsmRun::assemble(scene, s, thread_pool(threads)?)?;
        if state.bodies.len() != run.bodies.len() {
            return Err(Error::run(
                "the checkpoint's elements do not match the sample its scene builds",
            ));
        }
        let ids: Vec<usize> = state.broken_order.iter().map(|&c| c as usize).collect();
        run.bonds.break_contacts(&ids);
        run.bodies = state.bodies;
        run.forces = state.forces;
        run.broken_order = state.broken_order;
        run.break_log = state.break_log;
        run.first_break = state.first_break;
        if run.broken.is_some() {
            run.broken = state.broken;
        }
        if run.ground.is_some() {
            run.ground = state.ground;
        }
        run.loading = state.loading;
        run.series = state.series;
        run.time = state.time;
        run.step = state.step;
        run.dt = state.dt;
        run.stopped = state.stopped;
        run.warnings = state.warnings;
        run.end_step = end_step(run.loading.end_time(), run.dt);
        Ok(run)
    }

    fn assemble(scene: Scene, s: DlsmSample, pool: Option<Arc<rayon::ThreadPool>>) -> Result<Self> {
        let DlsmSample {
            domain,
            bodies,
            shapes,
            seeds,
            bonds,
            boundary: _,
            info,
        } = &s;
        let m = &scene.material;
        let loading = build_loading(&scene, &s)?;
        let tensile_strength = if scene.has_effect(EffectKind::Fracture) {
            m.tensile_strength
        } else {
            None
        };
        let broken = tensile_strength.map(|_| BrokenContacts::new(m.friction, m.poisson));
        let ground = match (&loading, scene.has_effect(EffectKind::Contact)) {
            (DlsmLoading::Drop(d), true) => Some(GroundContact::new(
                d.ground_point,
                d.ground_normal,
                m.contact_stiffness.expect("validated"),
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
        if let Some(g) = &ground {
            let lightest = bodies.mass.iter().copied().fold(f64::INFINITY, f64::min);
            dt_limit = dt_limit.min((lightest / g.stiffness).sqrt());
        }
        let dt = match scene.time.dt {
            DtSpec::Auto => scene.time.safety * dt_limit,
            DtSpec::Seconds(v) => v,
        };
        let phi = match scene.time.integrator {
            IntegratorKind::VelocityVerlet => 0.5,
            IntegratorKind::TchamwaWielgosz => scene.time.phi.unwrap_or(DEFAULT_PHI),
            IntegratorKind::Gear5 => unreachable!("validated: gear5 is beam2d's"),
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
        let series = Series::new(&loading.columns());
        let end_step = end_step(loading.end_time(), dt);
        let mut bodies = bodies.clone();
        let reference = bodies.pos.clone();
        if let DlsmLoading::FreeVibration(v) = &loading {
            for (p, seed) in bodies.pos.iter_mut().zip(seeds) {
                *p += initial_displacement(v, seed);
            }
        }
        if let DlsmLoading::Drop(_) = &loading {
            let v0 = Vec3::from(scene.loading.initial_velocity.unwrap_or([0.0; 3]));
            bodies.vel.iter_mut().for_each(|v| *v = v0);
        }
        Ok(DlsmRun {
            forces: Forces::new(bodies.len()),
            bodies,
            bonds: bonds.clone(),
            shapes: shapes.clone(),
            domain: *domain,
            reference,
            sample: info.clone(),
            integrator: TchamwaWielgosz::new(phi),
            tensile_strength,
            broken,
            broken_order: Vec::new(),
            break_log: Vec::new(),
            first_break: None,
            ground,
            gravity,
            loading,
            series,
            time: 0.0,
            step: 0,
            dt,
            dt_critical,
            dt_rotational,
            end_step,
            stopped: false,
            warnings,
            pool,
            scene,
        })
    }

    /// Prescribed velocities at t = 0.
    fn start(&mut self) {
        self.loading.prescribe(&mut self.bodies, 0.0);
    }

    pub fn threads(&self) -> usize {
        self.pool.as_ref().map_or(1, |p| p.current_num_threads())
    }

    /// Forces and torques at the current positions: bonds, effects, reactions.
    fn evaluate_forces(&mut self) {
        let pool = self.pool.clone();
        let strength = self.tensile_strength;
        let broke = on_threads(&pool, || {
            self.bonds
                .evaluate(&self.bodies, &mut self.forces, strength)
        });
        if !broke.is_empty() {
            self.record_breaks(&broke);
        }
        if let Some(b) = &mut self.broken {
            b.accumulate(&self.bodies, &self.shapes, &mut self.forces, self.dt);
        }
        if let Some(g) = &mut self.ground {
            g.accumulate(&self.bodies, &self.shapes, &mut self.forces, self.dt);
        }
        if let Some(g) = self.gravity {
            for (f, &m) in self.forces.force.iter_mut().zip(&self.bodies.mass) {
                *f += g * m;
            }
        }
        self.loading.constrain(&mut self.forces);
    }

    fn record_breaks(&mut self, broke: &[usize]) {
        if self.first_break.is_none() {
            let c = broke[0];
            let [i, j] = self.bonds.pair[c];
            let position = 0.5 * (self.bodies.pos[i as usize] + self.bodies.pos[j as usize]);
            self.first_break = Some(FirstBreak {
                step: self.step,
                contact: c,
                position,
                time: self.time,
            });
        }
        for &c in broke {
            self.broken_order.push(c as u32);
            let [i, j] = self.bonds.pair[c];
            self.break_log.push((
                self.step,
                0.5 * (self.bodies.pos[i as usize] + self.bodies.pos[j as usize]),
            ));
            if let Some(b) = &mut self.broken {
                let k = self.bonds.young * self.bonds.area[c] / self.bonds.length0[c];
                b.add(self.bonds.pair[c], k);
            }
        }
    }

    fn step_once(&mut self) {
        let dt = self.dt;
        self.loading
            .prescribe(&mut self.bodies, self.time + 0.5 * dt);
        let pool = self.pool.clone();
        on_threads(&pool, || {
            self.integrator
                .kick_drift(&mut self.bodies, &self.forces, dt)
        });
        self.evaluate_forces();
        on_threads(&pool, || {
            self.integrator.kick(&mut self.bodies, &self.forces, dt)
        });
        self.step += 1;
        self.time += dt;
    }

    pub fn finished(&self) -> bool {
        self.stopped || self.step >= self.end_step
    }

    /// Takes up to `steps` steps (never past the end), recording series rows on the way.
    pub fn advance(&mut self, steps: u64) -> Result<()> {
        let target = self.step.saturating_add(steps).min(self.end_step);
        while self.step < target && !self.stopped {
            self.step_once();
            if self.step % self.scene.output.every == 0 || self.step == self.end_step {
                self.check_finite()?;
                self.record_row();
                if self.loading.failed(&self.series) {
                    self.stopped = true;
                }
            }
        }
        Ok(())
    }

    fn check_finite(&self) -> Result<()> {
        if let Some(i) = self.bodies.first_non_finite() {
            return Err(Error::run(format!(
                "the run became unstable at step {} (t = {:e} s): element {i} has a non-finite position or velocity; lower time.safety (now {}) or time.dt",
                self.step, self.time, self.scene.time.safety
            )));
        }
        Ok(())
    }

    fn record_row(&mut self) {
        let drop = matches!(self.loading, DlsmLoading::Drop(_));
        let inputs = RowInputs {
            time: self.time,
            bodies: &self.bodies,
            reference: &self.reference,
            broken: self.broken_order.len(),
            strain_energy: if drop {
                self.bonds.strain_energy(&self.bodies)
            } else {
                0.0
            },
            contact_energy: self.ground.as_ref().map_or(0.0, |g| g.energy),
            ground_contacts: self.ground.as_ref().map_or(0, |g| g.contacts),
        };
        let row = self.loading.row(&inputs);
        if self.series.rows.last().is_some_and(|r| r[0] == row[0]) {
            return;
        }
        self.series.rows.push(row);
    }

    pub fn summary(&self) -> Value {
        let mut m = run::common_summary(self);
        m.insert("elements".into(), self.bodies.len().into());
        m.insert(
            "sample".into(),
            serde_json::to_value(&self.sample).expect("sample info serialises"),
        );
        m.insert("contacts".into(), self.bonds.contacts().into());
        m.insert("broken_contacts".into(), self.broken_order.len().into());
        m.insert("dt_critical".into(), self.dt_critical.into());
        m.insert("dt_rotational".into(), self.dt_rotational.into());
        m.insert("phi".into(), self.integrator.phi.into());
        m.insert("stopped_after_failure".into(), self.stopped.into());
        m.insert(
            "kinetic_energy_final".into(),
            self.bodies.kinetic_energy().into(),
        );
        let dt_row = self.scene.output.every as f64 * self.dt;
        let mut series = self.series.clone();
        if matches!(self.loading, DlsmLoading::FreeVibration(_)) {
            // The spectrum needs evenly spaced rows: drop a last row off the grid.
            let off = |r: &Vec<f64>| {
                let k = r[0] / dt_row;
                (k - k.round()).abs() > 1e-6
            };
            if series.rows.last().is_some_and(off) {
                series.rows.pop();
            }
        }
        self.loading.summarize(&series, dt_row, &mut m);
        if let Some(fb) = &self.first_break {
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
                if let Some(force) = self.series.column("force") {
                    let peak = force.iter().copied().fold(0.0, f64::max);
                    let row_step = |k: usize| (self.series.rows[k][0] / self.dt).round() as u64;
                    if let Some(k) = force.iter().position(|&f| f >= 0.95 * peak) {
                        let from = if k > 0 { row_step(k - 1) } else { 0 };
                        if let Some((_, p)) = self.break_log.iter().find(|(s, _)| *s >= from) {
                            m.insert("main_crack_start_offset".into(), offset(p).into());
                        }
                    }
                }
            }
        }
        Value::Object(m)
    }

    /// The elements as a polyhedral mesh for ParaView.
    pub fn elements_vtu(&self) -> String {
        vtk::polyhedra_vtu(&self.bodies, &self.shapes, &self.forces, &self.reference)
    }
}

/// The step at which a loading of `end_time` seconds ends.
fn end_step(end_time: f64, dt: f64) -> u64 {
    if end_time.is_finite() {
        (end_time / dt - 1e-9).ceil().max(1.0) as u64
    } else {
        u64::MAX
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

/// The static field a free vibration starts from, at `x` (Section 8.2.2).
fn initial_displacement(v: &FreeVibration, x: &Vec3) -> Vec3 {
    match v.mode {
        VibrationMode::Tension => Vec3::new(v.amplitude * x.x, 0.0, 0.0),
        VibrationMode::Torsion => {
            let (s, c) = (v.amplitude * x.x).sin_cos();
            Vec3::new(0.0, x.y * c - x.z * s - x.y, x.y * s + x.z * c - x.z)
        }
    }
}

/// The loading of a dlsm scene on its sample.
fn build_loading(scene: &Scene, s: &DlsmSample) -> Result<DlsmLoading> {
    let l = &scene.loading;
    let m = &scene.material;
    let strength = if scene.has_effect(EffectKind::Fracture) {
        m.tensile_strength
    } else {
        None
    };
    let stop = l.stop_fraction.unwrap_or(DEFAULT_STOP);
    let mean = |set: &[u32], axis: usize| {
        set.iter()
            .map(|&i| s.bodies.pos[i as usize][axis])
            .sum::<f64>()
            / set.len().max(1) as f64
    };
    let nonempty = |set: &Vec<u32>, what: &str| -> Result<()> {
        if set.is_empty() {
            Err(scene.key_error(
                "sample.elements",
                format!("gives no element on {what}; ask for more elements"),
            ))
        } else {
            Ok(())
        }
    };
    Ok(match l.kind {
        LoadingKind::Tension => {
            let Domain::Box { lo, hi } = s.domain else {
                unreachable!("validated: tension needs a box")
            };
            let size = hi - lo;
            let faces = BOX_FACES.map(|b| s.elements_on(b));
            for (set, name) in faces.iter().zip(["x-", "x+", "y-", "y+", "z-", "z+"]) {
                nonempty(set, name)?;
            }
            let gauge = [0, 1, 2].map(|a| mean(&faces[2 * a + 1], a) - mean(&faces[2 * a], a));
            let rate = l.strain_rate.expect("validated");
            let end = l.end_strain.expect("validated");
            let middle = (0..s.bodies.len() as u32)
                .filter(|&i| {
                    let x = (s.bodies.pos[i as usize].x - lo.x) / size.x;
                    (0.2..=0.8).contains(&x)
                })
                .collect();
            let centre = lo.x + 0.5 * size.x;
            let lever = [0, 1].map(|k: usize| {
                faces[k]
                    .iter()
                    .map(|&i| s.bodies.pos[i as usize].x - centre)
                    .collect()
            });
            DlsmLoading::Tension(Tension {
                lever,
                strain_rate: rate,
                end_strain: end,
                ramp_time: l.ramp_time.unwrap_or(DEFAULT_RAMP * end / rate),
                length: size.x,
                section: size.y * size.z,
                faces,
                gauge,
                middle,
                reaction: [0.0; 2],
                stop_fraction: stop,
                tensile_strength: strength,
            })
        }
        LoadingKind::FreeVibration => {
            // The bar's length: the sample was made longer by the clamp's grip.
            let length = scene.sample.length.expect("validated");
            let mode = l.mode.expect("validated");
            let clamped = s.elements_on(Boundary::XMin);
            let free = s.elements_on(Boundary::XMax);
            nonempty(&clamped, "x-")?;
            nonempty(&free, "x+")?;
            let shear = m.young / (2.0 * (1.0 + m.poisson));
            let (amplitude, modulus) = match mode {
                VibrationMode::Tension => (l.initial_strain.unwrap_or(1e-5), m.young),
                VibrationMode::Torsion => (l.twist.unwrap_or(1e-4), shear),
            };
            DlsmLoading::FreeVibration(FreeVibration {
                mode,
                amplitude,
                end_time: l.end_time.expect("validated"),
                length,
                clamped,
                free,
                // Eq. 44 / 45.
                frequency_theory: (modulus / m.density).sqrt() / (4.0 * length),
            })
        }
        LoadingKind::Brazilian => {
            let Domain::Disc {
                diameter,
                thickness,
            } = s.domain
            else {
                unreachable!("validated: brazilian needs a disc")
            };
            let radius = 0.5 * diameter;
            let half_angle = 0.5 * l.arc_degrees.unwrap_or(0.0).to_radians();
            // Flat loading still needs elements to push: those within half an element of
            // the top (bottom) of the disc.
            let reach = half_angle.max(0.5 * s.info.element_size / radius);
            let mut top = Vec::new();
            let mut bottom = Vec::new();
            for f in &s.boundary {
                if f.boundary != Boundary::Curved {
                    continue;
                }
                let from_vertical = f.centroid.x.atan2(f.centroid.y.abs()).abs();
                if from_vertical <= reach {
                    if f.centroid.y > 0.0 {
                        top.push(f.element);
                    } else {
                        bottom.push(f.element);
                    }
                }
            }
            top.sort_unstable();
            top.dedup();
            bottom.sort_unstable();
            bottom.dedup();
            nonempty(&top, "the top loading arc")?;
            nonempty(&bottom, "the bottom loading arc")?;
            let speed = l.speed.expect("validated");
            let end = l.end_strain.expect("validated");
            let gap = mean(&top, 1) - mean(&bottom, 1);
            DlsmLoading::Brazilian(Brazilian {
                speed,
                end_strain: end,
                ramp_time: l
                    .ramp_time
                    .unwrap_or(DEFAULT_RAMP * end * diameter / (2.0 * speed)),
                half_angle,
                diameter,
                thickness,
                top,
                bottom,
                gap,
                reaction: [0.0; 2],
                stop_fraction: stop,
                tensile_strength: strength,
            })
        }
        LoadingKind::Drop => {
            let angle = l.ground_angle_degrees.unwrap_or(0.0).to_radians();
            let normal = Vec3::new(angle.sin(), 0.0, angle.cos());
            let downslope = Vec3::new(angle.cos(), 0.0, -angle.sin());
            let mut lowest = f64::INFINITY;
            for (i, shape) in s.shapes.iter().enumerate() {
                let r = s.bodies.orientation[i];
                for v in &shape.vertices {
                    lowest = lowest.min(normal.dot(&(s.bodies.pos[i] + r * v)));
                }
            }
            let ground_point = normal * (lowest - l.drop_height.unwrap_or(0.0));
            let total: f64 = s.bodies.mass.iter().sum();
            let centre = s
                .bodies
                .pos
                .iter()
                .zip(&s.bodies.mass)
                .map(|(p, m)| p * *m)
                .sum::<Vec3>()
                / total;
            let gravity = if scene.has_effect(EffectKind::Gravity) {
                Vec3::from(scene.gravity.acceleration)
            } else {
                Vec3::zeros()
            };
            DlsmLoading::Drop(Drop {
                end_time: l.end_time.expect("validated"),
                ground_point,
                ground_normal: normal,
                downslope,
                roll_axis: normal.cross(&downslope),
                gravity,
                turns: 0.0,
                last_spin: 0.0,
                last_time: 0.0,
                centre0: centre,
            })
        }
        LoadingKind::None => DlsmLoading::Free {
            end_time: l.end_time.expect("validated"),
        },
        LoadingKind::Oedometer
        | LoadingKind::Platens
        | LoadingKind::ElasticModuli
        | LoadingKind::ConfinedCompression
        | LoadingKind::Explosion
        | LoadingKind::Projectile => {
            unreachable!("validated: not a dlsm loading")
        }
    })
}

impl Run for DlsmRun {
    fn scene(&self) -> &Scene {
        &self.scene
    }
    fn model(&self) -> &'static str {
        "dlsm"
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
        DlsmRun::threads(self)
    }
    fn finished(&self) -> bool {
        DlsmRun::finished(self)
    }
    fn advance(&mut self, steps: u64) -> Result<()> {
        DlsmRun::advance(self, steps)
    }
    fn series(&self) -> &Series {
        &self.series
    }
    fn summary(&self) -> Value {
        DlsmRun::summary(self)
    }
    fn snapshot(&self) -> Vec<(&'static str, String)> {
        vec![("elements", self.elements_vtu())]
    }
    fn save_state(&self) -> Vec<u8> {
        let state = DlsmState {
            bodies: self.bodies.clone(),
            forces: self.forces.clone(),
            broken_order: self.broken_order.clone(),
            break_log: self.break_log.clone(),
            first_break: self.first_break,
            broken: self.broken.clone(),
            ground: self.ground.clone(),
            loading: self.loading.clone(),
            series: self.series.clone(),
            time: self.time,
            step: self.step,
            dt: self.dt,
            stopped: self.stopped,
            warnings: self.warnings.clone(),
        };
        postcard::to_stdvec(&state).expect("the dlsm state serialises")
    }
    fn status(&self) -> String {
        format!(
            "t = {:.4e} s, {} broken contacts",
            self.time,
            self.broken_order.len()
        )
    }
    fn warnings(&self) -> &[String] {
        &self.warnings
    }
}

/// `fractum explain` for a dlsm scene: what it builds, without building the sample.
pub fn explain(scene: &Scene) -> Result<String> {
    let mut s = String::new();
    let p = &scene.sample;
    let m = &scene.material;
    let _ = writeln!(
        s,
        "scene {} (\"{}\"), seed {}",
        scene.source.label, scene.name, scene.seed
    );
    let _ = writeln!(
        s,
        "model: dlsm, Voronoi polyhedra joined by the distinct lattice spring model: least-squares strain per element (Eq. 1-15), contact strain (Eq. 16-18), Hooke force (Eq. 20-25) with E = {:e} Pa, nu = {}, moments with K = E L0 per unit area (Eq. 28-34)",
        m.young, m.poisson
    );
    let method = p.method.map_or("noisy_grid", |x| x.as_str());
    let randomness = match method {
        "noisy_grid" => format!(", noise d = {}", p.noise.unwrap_or(sample::DEFAULT_NOISE)),
        "packing" => format!(
            ", radius dispersion {}",
            p.radius_dispersion.unwrap_or(sample::DEFAULT_DISPERSION)
        ),
        _ => String::new(),
    };
    let _ = writeln!(
        s,
        "sample: {} of about {} elements, seeds by {method}{randomness}, domain {:?}",
        p.kind.as_str(),
        p.elements.unwrap_or(0),
        sample::domain(scene)
    );
    let _ = writeln!(
        s,
        "effects, in evaluation order (after the cohesive contacts):"
    );
    let mut built = Vec::new();
    if scene.has_effect(EffectKind::Fracture) {
        built.push(format!(
            "fracture: a contact breaks for good when sigma_xx > {:e} Pa (Eq. 36) and becomes a frictional (mu = {}) non-cohesive polyhedron contact (GJK/EPA)",
            m.tensile_strength.unwrap_or(0.0),
            m.friction
        ));
    }
    if scene.has_effect(EffectKind::Contact) {
        built.push(format!(
            "contact: elements against the ground plane, stiffness {:e} N/m{}",
            m.contact_stiffness.unwrap_or(0.0),
            if scene.has_effect(EffectKind::Friction) {
                format!(", Coulomb friction mu = {}", m.friction)
            } else {
                ", frictionless".to_string()
            }
        ));
    }
    if scene.has_effect(EffectKind::Gravity) {
        let g = scene.gravity.acceleration;
        built.push(format!(
            "gravity: m g, g = ({}, {}, {}) m/s²",
            g[0], g[1], g[2]
        ));
    }
    if built.is_empty() {
        let _ = writeln!(s, "  (none: the cohesive lattice alone)");
    }
    for (k, line) in built.iter().enumerate() {
        let _ = writeln!(s, "  {}. {line}", k + 1);
    }
    let left_out: Vec<&str> = [
        EffectKind::Fracture,
        EffectKind::Contact,
        EffectKind::Friction,
        EffectKind::Gravity,
    ]
    .iter()
    .filter(|e| !scene.has_effect(**e))
    .map(|e| e.as_str())
    .collect();
    if !left_out.is_empty() {
        let _ = writeln!(s, "not built (not in `effects`): {}", left_out.join(", "));
    }
    let l = &scene.loading;
    let loading = match l.kind {
        LoadingKind::Tension => format!(
            "tension: x- and x+ face elements pulled apart at {} 1/s to strain {}",
            l.strain_rate.unwrap_or(0.0),
            l.end_strain.unwrap_or(0.0)
        ),
        LoadingKind::FreeVibration => format!(
            "free vibration from a static {:?} field, x- clamped, for {:e} s",
            l.mode,
            l.end_time.unwrap_or(0.0)
        ),
        LoadingKind::Brazilian => {
            let arc = l.arc_degrees.unwrap_or(0.0);
            format!(
                "Brazilian test, loading arc {arc} degrees (k = {:.4}, Eq. 47), {} m/s per side to diametral strain {}",
                arc_factor(0.5 * arc.to_radians()),
                l.speed.unwrap_or(0.0),
                l.end_strain.unwrap_or(0.0)
            )
        }
        LoadingKind::Drop => format!(
            "drop at {:?} m/s onto a ground inclined {} degrees, for {:e} s",
            l.initial_velocity.unwrap_or([0.0; 3]),
            l.ground_angle_degrees.unwrap_or(0.0),
            l.end_time.unwrap_or(0.0)
        ),
        _ => format!(
            "none: nothing prescribed for {:e} s",
            l.end_time.unwrap_or(0.0)
        ),
    };
    let _ = writeln!(s, "loading: {loading}");
    let integrator = match scene.time.integrator {
        IntegratorKind::VelocityVerlet | IntegratorKind::Gear5 => {
            "velocity Verlet (phi = 0.5)".to_string()
        }
        IntegratorKind::TchamwaWielgosz => format!(
            "Tchamwa-Wielgosz, phi = {}",
            scene.time.phi.unwrap_or(DEFAULT_PHI)
        ),
    };
    let dt = match scene.time.dt {
        DtSpec::Auto => format!(
            "{} x min sqrt(m_ij L0 / (E S)) over the contacts (Eq. 39)",
            scene.time.safety
        ),
        DtSpec::Seconds(v) => format!("{v:e} s"),
    };
    let _ = writeln!(s, "integrator: {integrator}, dt {dt}");
    let vtk = if scene.output.vtk > 0 {
        format!(
            "VTK snapshot (elements.pvd) every {} steps",
            scene.output.vtk
        )
    } else {
        "no VTK".to_string()
    };
    let _ = writeln!(
        s,
        "outputs: series.csv row every {} steps, {vtk}, summary.json at the end",
        scene.output.every
    );
    Ok(s)
}
