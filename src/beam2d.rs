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

use std::fmt::Write as _;
use std::sync::Arc;

use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use crate::bond::beam2d::Beams;
use crate::contact::overlap_area_2d::characteristic_length;
use crate::effects::polygon2d::PolygonPipeline;
use crate::error::{Error, Result};
use crate::integrate::{Gear5, kick_dofs, kick_drift_dofs};
use crate::loading::beam2d::Beam2dLoading;
use crate::output::vtk_polygons::{beams_vtu, polygons_vtu};
use crate::probe::Series;
use crate::probe::fragments::{
    PowerLawFit, components, fit_power_law, mass_histogram, sum_by_component,
};
use crate::run::{self, Run};
use crate::sample::lattice2d::{self, LatticeInfo, PolygonSample};
use crate::scene::{DtSpec, EffectKind, IntegratorKind, LoadingKind, Outline, Scene};
use crate::shape::polygon::Vec2;
use crate::simulation::{on_threads, thread_pool};
use crate::state::polygons::Polygons;

/// The effects of the beam2d model, in evaluation order.
pub const BEAM2D_EFFECTS: [EffectKind; 5] = [
    EffectKind::Contact,
    EffectKind::Damping,
    EffectKind::Friction,
    EffectKind::Beams,
    EffectKind::BeamBreaking,
];

/// The integrator of a beam2d run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Integrator2d {
    VelocityVerlet,
    Gear5(Gear5),
}

/// The initial positions and velocities, kept for the moduli test's second phase.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct StartState {
    q: Vec<[f64; 3]>,
    v: Vec<[f64; 3]>,
}

/// Everything a checkpoint stores.
#[derive(Serialize, Deserialize)]
struct Beam2dState {
    polygons: Polygons,
    beams: Beams,
    forces: Vec<[f64; 3]>,
    integrator: Integrator2d,
    loading: Beam2dLoading,
    series: Series,
    info: LatticeInfo,
    mean_polygon_mass: f64,
    time: f64,
    step: u64,
    last_row: u64,
    dt: f64,
    dt_critical: f64,
    steps_since_break: u64,
    contacts: usize,
    momentum0: Vec2,
    momentum_scale: f64,
    max_momentum_drift: f64,
    initial_kinetic_energy: f64,
    warnings: Vec<String>,
    start: Option<StartState>,
}

/// A run of the beam2d model.
pub struct Beam2dRun {
    pub scene: Scene,
    pub polygons: Polygons,
    pub beams: Beams,
    /// Forces and torques `[F_x, F_y, M]` of the last evaluation.
    pub forces: Vec<[f64; 3]>,
    pub pipeline: PolygonPipeline,
    pub integrator: Integrator2d,
    pub loading: Beam2dLoading,
    pub series: Series,
    pub info: LatticeInfo,
    /// Mean polygon mass of the sample as built (kg): the unit of fragment masses.
    pub mean_polygon_mass: f64,
    pub time: f64,
    pub step: u64,
    pub dt: f64,
    /// Estimated stability limit of velocity Verlet, 2/ω of the stiffest polygon (s).
    pub dt_critical: f64,
    pub end_step: u64,
    pub steps_since_break: u64,
    /// Overlapping pairs in the last evaluation.
    pub contacts: usize,
    /// Total momentum at the start, Σ m|v| at the start, and the largest |P − P0| / Σ m|v|
    /// seen at the output steps (free loadings).
    pub momentum0: Vec2,
    pub momentum_scale: f64,
    pub max_momentum_drift: f64,
    pub initial_kinetic_energy: f64,
    pub warnings: Vec<String>,
    last_row: u64,
    start: Option<StartState>,
    pool: Option<Arc<rayon::ThreadPool>>,
}

/// The beams over the sample's shared sides (only with the `beams` effect).
fn make_beams(scene: &Scene, sample: &PolygonSample) -> Beams {
    let mut beams = Beams::default();
    if !scene.has_effect(EffectKind::Beams) {
        return beams;
    }
    let young = scene.material.beam_young.expect("validated");
    let t = sample.info.thickness;
    let p = &sample.polygons;
    for s in &sample.sides {
        let (i, j) = (s.i as usize, s.j as usize);
        beams.push([i, j], [p.centre(i), p.centre(j)], s.length, t, young);
    }
    beams
}

/// Velocity Verlet's stability limit 2/ω for the stiffest polygon, with
/// `ω² = 2 Σ k / m` over its beams (axial plus shear stiffness) and contacts across its sides
/// (`Y t S / Lc`), and likewise for rotation.
fn critical_time_step(scene: &Scene, sample: &PolygonSample, beams: &Beams) -> f64 {
    let p = &sample.polygons;
    let n = p.len();
    let (mut kt, mut kr) = (vec![0.0; n], vec![0.0; n]);
    for b in 0..beams.len() {
        let l = beams.rest_length[b];
        // β l0² = 2 (bend_own + bend_cross): the shear stiffness β.
        let beta = 2.0 * (beams.bend_own[b] + beams.bend_cross[b]) / (l * l);
        let rot = beams.bend_own[b] + beams.bend_cross[b].abs();
        for k in [beams.i[b] as usize, beams.j[b] as usize] {
            kt[k] += beams.alpha[b] + beta;
            kr[k] += rot;
        }
    }
    if scene.has_effect(EffectKind::Contact) {
        let yt = scene.material.young * sample.info.thickness;
        for s in &sample.sides {
            let (i, j) = (s.i as usize, s.j as usize);
            let k = yt * s.length
                / characteristic_length(p.equivalent_diameter[i], p.equivalent_diameter[j]);
            for m in [i, j] {
                kt[m] += k;
                kr[m] += k * s.length * s.length / 12.0;
            }
        }
    }
    let mut omega: f64 = 0.0;
    for k in 0..n {
        omega = omega
            .max((2.0 * kt[k] / p.mass[k]).sqrt())
            .max((2.0 * kr[k] / p.inertia[k]).sqrt());
    }
    if omega > 0.0 {
        2.0 / omega
    } else {
        f64::INFINITY
    }
}

impl Beam2dRun {
    /// Builds the lattice a scene describes and sets the run up. `threads` = 0 uses every core.
    pub fn new(
        scene: Scene,
        threads: usize,
        progress: &mut (dyn FnMut(&str) + Send),
    ) -> Result<Self> {
        let pool = thread_pool(threads)?;
        let mut sample = lattice2d::from_scene(&scene)?;
        progress(&format!(
            "{} polygons ({:.2} vertices on average), {} shared sides",
            sample.info.polygons, sample.info.mean_vertices, sample.info.shared_sides
        ));
        let mean_polygon_mass = sample.polygons.total_mass() / sample.polygons.len() as f64;
        let loading = Beam2dLoading::prepare(&scene, &mut sample)?;
        let beams = make_beams(&scene, &sample);
        let dt_critical = critical_time_step(&scene, &sample, &beams);
        let dt = match scene.time.dt {
            DtSpec::Auto => scene.time.safety * dt_critical,
            DtSpec::Seconds(s) => s,
        };
        if !dt.is_finite() {
            return Err(scene.key_error(
                "time.dt",
                "= \"auto\" needs contacts or beams to estimate a step from; give a time step in seconds",
            ));
        }
        let PolygonSample { polygons, info, .. } = sample;
        let integrator = match scene.time.integrator {
            IntegratorKind::VelocityVerlet => Integrator2d::VelocityVerlet,
            IntegratorKind::Gear5 => Integrator2d::Gear5(Gear5::new(
                3 * polygons.len(),
                scene.has_effect(EffectKind::Damping) || scene.has_effect(EffectKind::Friction),
            )),
            IntegratorKind::TchamwaWielgosz => {
                unreachable!("validated: tchamwa_wielgosz is dlsm's")
            }
        };
        let start = matches!(loading, Beam2dLoading::ElasticModuli(_)).then(|| StartState {
            q: polygons.q.clone(),
            v: polygons.v.clone(),
        });
        let mut run = Beam2dRun::assemble(scene, polygons, beams, loading, info, dt, pool);
        run.integrator = integrator;
        run.mean_polygon_mass = mean_polygon_mass;
        run.dt_critical = dt_critical;
        run.start = start;
        if dt > dt_critical {
            run.warnings.push(format!(
                "time.dt = {dt:e} s exceeds the estimated stability limit {dt_critical:e} s of the stiffest polygon; the run may blow up"
            ));
        }
        run.momentum0 = run.polygons.momentum();
        run.momentum_scale = run.polygons.momentum_scale();
        run.initial_kinetic_energy = run.polygons.kinetic_energy();
        run.restart_dynamics();
        run.record_row();
        Ok(run)
    }

    fn assemble(
        scene: Scene,
        polygons: Polygons,
        beams: Beams,
        loading: Beam2dLoading,
        info: LatticeInfo,
        dt: f64,
        pool: Option<Arc<rayon::ThreadPool>>,
    ) -> Beam2dRun {
        let skin = scene.neighbor.skin.unwrap_or(0.3 * info.spacing);
        let pipeline = PolygonPipeline::build(&scene, &polygons, &beams, skin);
        let series = Series::new(loading.columns());
        let end_step = loading.end_step(dt);
        let n = polygons.len();
        Beam2dRun {
            scene,
            polygons,
            beams,
            forces: vec![[0.0; 3]; n],
            pipeline,
            integrator: Integrator2d::VelocityVerlet,
            loading,
            series,
            info,
            mean_polygon_mass: 0.0,
            time: 0.0,
            step: 0,
            dt,
            dt_critical: f64::INFINITY,
            end_step,
            steps_since_break: 0,
            contacts: 0,
            momentum0: Vec2::zeros(),
            momentum_scale: 0.0,
            max_momentum_drift: 0.0,
            initial_kinetic_energy: 0.0,
            warnings: Vec::new(),
            last_row: u64::MAX,
            start: None,
            pool,
        }
    }

    /// Forces at the current state, and Gear's derivatives started from them.
    fn restart_dynamics(&mut self) {
        self.loading.prescribe(self.time, &mut self.polygons);
        let pool = self.pool.clone();
        on_threads(&pool, || {
            let counts = self.pipeline.evaluate(
                &self.polygons,
                &mut self.beams,
                self.time,
                &mut self.forces,
            );
            self.contacts = counts.contacts;
        });
        if let Integrator2d::Gear5(g) = &mut self.integrator {
            g.start(
                self.forces.as_flattened(),
                self.polygons.inv_m.as_flattened(),
                self.dt,
            );
        }
    }

    /// Restores a run from the bytes [`Run::save_state`] wrote.
    pub fn restore(scene: Scene, bytes: &[u8], threads: usize) -> Result<Self> {
        let s: Beam2dState = postcard::from_bytes(bytes)
            .map_err(|e| Error::run(format!("the checkpoint's beam2d state is damaged ({e})")))?;
        let mut run = Beam2dRun::assemble(
            scene,
            s.polygons,
            s.beams,
            s.loading,
            s.info,
            s.dt,
            thread_pool(threads)?,
        );
        run.forces = s.forces;
        run.integrator = s.integrator;
        run.series = s.series;
        run.mean_polygon_mass = s.mean_polygon_mass;
        run.time = s.time;
        run.step = s.step;
        run.last_row = s.last_row;
        run.dt_critical = s.dt_critical;
        run.steps_since_break = s.steps_since_break;
        run.contacts = s.contacts;
        run.momentum0 = s.momentum0;
        run.momentum_scale = s.momentum_scale;
        run.max_momentum_drift = s.max_momentum_drift;
        run.initial_kinetic_energy = s.initial_kinetic_energy;
        run.warnings = s.warnings;
        run.start = s.start;
        Ok(run)
    }

    fn state(&self) -> Beam2dState {
        Beam2dState {
            polygons: self.polygons.clone(),
            beams: self.beams.clone(),
            forces: self.forces.clone(),
            integrator: self.integrator.clone(),
            loading: self.loading.clone(),
            series: self.series.clone(),
            info: self.info.clone(),
            mean_polygon_mass: self.mean_polygon_mass,
            time: self.time,
            step: self.step,
            last_row: self.last_row,
            dt: self.dt,
            dt_critical: self.dt_critical,
            steps_since_break: self.steps_since_break,
            contacts: self.contacts,
            momentum0: self.momentum0,
            momentum_scale: self.momentum_scale,
            max_momentum_drift: self.max_momentum_drift,
            initial_kinetic_energy: self.initial_kinetic_energy,
            warnings: self.warnings.clone(),
            start: self.start.clone(),
        }
    }

    pub fn threads(&self) -> usize {
        self.pool.as_ref().map_or(1, |p| p.current_num_threads())
    }

    /// True at the end step, or once `quiet_steps` steps passed without a break.
    pub fn finished(&self) -> bool {
        self.step >= self.end_step
            || self
                .loading
                .quiet_steps()
                .is_some_and(|q| self.steps_since_break >= q)
    }

    /// Takes up to `steps` steps (never past the end), recording series rows on the way.
    pub fn advance(&mut self, steps: u64) -> Result<()> {
        let target = self.step.saturating_add(steps).min(self.end_step);
        let pool = self.pool.clone();
        on_threads(&pool, || {
            while self.step < target && !self.finished() {
                self.step_once();
                self.after_step()?;
            }
            Ok(())
        })
    }

    fn step_once(&mut self) {
        let dt = self.dt;
        let p = &mut self.polygons;
        match &mut self.integrator {
            Integrator2d::VelocityVerlet => kick_drift_dofs(
                p.q.as_flattened_mut(),
                p.v.as_flattened_mut(),
                self.forces.as_flattened(),
                p.inv_m.as_flattened(),
                dt,
            ),
            Integrator2d::Gear5(g) => g.predict(p.q.as_flattened_mut(), p.v.as_flattened_mut(), dt),
        }
        let t = self.time + dt;
        self.loading.prescribe(t, p);
        let counts = self
            .pipeline
            .evaluate(p, &mut self.beams, t, &mut self.forces);
        match &mut self.integrator {
            Integrator2d::VelocityVerlet => kick_dofs(
                p.v.as_flattened_mut(),
                self.forces.as_flattened(),
                p.inv_m.as_flattened(),
                dt,
            ),
            Integrator2d::Gear5(g) => g.correct(
                p.q.as_flattened_mut(),
                p.v.as_flattened_mut(),
                self.forces.as_flattened(),
                p.inv_m.as_flattened(),
                dt,
            ),
        }
        self.step += 1;
        self.time = t;
        self.contacts = counts.contacts;
        self.steps_since_break = if counts.broken > 0 {
            0
        } else {
            self.steps_since_break + 1
        };
    }

    fn after_step(&mut self) -> Result<()> {
        let phase_end = match &self.loading {
            Beam2dLoading::ElasticModuli(d) if d.phase == 0 => self.end_step / 2,
            _ => u64::MAX,
        };
        if self.step % self.scene.output.every == 0 || self.finished() || self.step == phase_end {
            self.check_finite()?;
            self.record_row();
        }
        if self.step == phase_end {
            self.start_compression_phase();
        }
        Ok(())
    }

    /// The moduli test's second phase: back to the initial state, then compress.
    fn start_compression_phase(&mut self) {
        let start = self.start.as_ref().expect("kept for the moduli test");
        self.polygons.q.clone_from(&start.q);
        self.polygons.v.clone_from(&start.v);
        if let Beam2dLoading::ElasticModuli(d) = &mut self.loading {
            d.phase = 1;
            d.phase_start = self.time;
            d.sign = -1.0;
        }
        self.restart_dynamics();
    }

    fn check_finite(&self) -> Result<()> {
        if let Some(i) = self.polygons.first_non_finite() {
            return Err(Error::run(format!(
                "the run became unstable at step {} (t = {:e} s): polygon {i} has a non-finite position or velocity; lower time.dt (now {:e} s, estimated limit {:e} s)",
                self.step, self.time, self.dt, self.dt_critical
            )));
        }
        Ok(())
    }

    /// Elastic energy (J) stored in the intact beams.
    pub fn beam_energy(&self) -> f64 {
        let (b, p) = (&self.beams, &self.polygons);
        (0..b.len())
            .filter(|&k| b.intact[k])
            .map(|k| {
                let (i, j) = (b.i[k] as usize, b.j[k] as usize);
                let r = b.response(k, p.centre(i), p.q[i][2], p.centre(j), p.q[j][2]);
                b.energy(k, &r)
            })
            .sum()
    }

    /// Fragment labels over the intact beams, and their number.
    pub fn fragments(&self) -> (Vec<u32>, usize) {
        let b = &self.beams;
        components(
            self.polygons.len(),
            (0..b.len())
                .filter(|&k| b.intact[k])
                .map(|k| (b.i[k] as usize, b.j[k] as usize)),
        )
    }

    fn record_row(&mut self) {
        if self.last_row == self.step {
            return;
        }
        self.last_row = self.step;
        let p = &self.polygons;
        let ke = p.kinetic_energy();
        let broken = self.beams.broken() as f64;
        let row = match self.loading.driven() {
            Some(d) => {
                let (strain, stress, lateral) = d.measure(p, &self.forces);
                vec![
                    self.time,
                    strain,
                    stress,
                    lateral,
                    ke,
                    self.contacts as f64,
                    broken,
                ]
            }
            None => {
                let momentum = p.momentum();
                if self.momentum_scale > 0.0 {
                    let drift = (momentum - self.momentum0).norm() / self.momentum_scale;
                    self.max_momentum_drift = self.max_momentum_drift.max(drift);
                }
                let (_, count) = self.fragments();
                vec![
                    self.time,
                    ke,
                    self.contacts as f64,
                    broken,
                    count as f64,
                    momentum.x,
                    momentum.y,
                ]
            }
        };
        self.series.rows.push(row);
    }

    /// Fragment masses (kg) and polygon counts, in label order.
    fn fragment_masses(&self) -> (Vec<u32>, Vec<f64>, Vec<usize>) {
        let (labels, count) = self.fragments();
        let masses = sum_by_component(&labels, count, &self.polygons.mass);
        let mut sizes = vec![0usize; count];
        for &l in &labels {
            sizes[l as usize] += 1;
        }
        (labels, masses, sizes)
    }

    /// The power-law fit of the mass histogram of fragments of two or more polygons (single
    /// polygons are left out, as in the paper's Fig. 11).
    pub fn power_law(&self) -> Option<PowerLawFit> {
        let (_, masses, sizes) = self.fragment_masses();
        let multi: Vec<f64> = masses
            .iter()
            .zip(&sizes)
            .filter(|(_, s)| **s >= 2)
            .map(|(m, _)| *m)
            .collect();
        let f = &self.scene.fragments;
        let unit = self.mean_polygon_mass;
        let bins = mass_histogram(&multi, unit, f.bins_per_decade, 1);
        fit_power_law(&bins, f.fit_range[0] * unit, f.fit_range[1] * unit)
    }

    /// Masses (kg) of the fragments of two or more polygons: what the histogram is made of.
    pub fn multi_polygon_fragment_masses(&self) -> Vec<f64> {
        let (_, masses, sizes) = self.fragment_masses();
        masses
            .iter()
            .zip(&sizes)
            .filter(|(_, s)| **s >= 2)
            .map(|(m, _)| *m)
            .collect()
    }

    /// Fraction of the broken beams (up to `until`, s) that lay within 30° of the x axis at
    /// rest: perpendicular to the load of the compression tests.
    pub fn broken_lateral_fraction(&self, until: f64) -> Option<f64> {
        let b = &self.beams;
        let broken: Vec<usize> = (0..b.len())
            .filter(|&k| !b.intact[k] && b.broken_time[k] <= until)
            .collect();
        if broken.is_empty() {
            return None;
        }
        let lateral = broken
            .iter()
            .filter(|&&k| b.rest_direction[k].y.abs() <= 0.5)
            .count();
        Some(lateral as f64 / broken.len() as f64)
    }

    /// The results of the run so far.
    pub fn summary(&self) -> Value {
        let mut m = run::common_summary(self);
        m.insert(
            "integrator".into(),
            self.scene.time.integrator.as_str().into(),
        );
        m.insert("dt_critical".into(), self.dt_critical.into());
        m.insert(
            "sample".into(),
            serde_json::to_value(&self.info).expect("info serialises"),
        );
        m.insert("polygons".into(), self.polygons.len().into());
        m.insert("mean_polygon_mass".into(), self.mean_polygon_mass.into());
        m.insert("beams".into(), self.beams.len().into());
        m.insert("broken_beams".into(), self.beams.broken().into());
        m.insert("contacts_final".into(), self.contacts.into());
        m.insert(
            "kinetic_energy_initial".into(),
            self.initial_kinetic_energy.into(),
        );
        m.insert(
            "kinetic_energy_final".into(),
            self.polygons.kinetic_energy().into(),
        );
        self.loading.summarize(&self.series, &mut m);
        match &self.loading {
            Beam2dLoading::ConfinedCompression(_) => {
                let all = &self.beams.rest_direction;
                let baseline = all.iter().filter(|d| d.y.abs() <= 0.5).count() as f64
                    / all.len().max(1) as f64;
                m.insert("beams_lateral_fraction".into(), baseline.into());
                m.insert(
                    "broken_beams_lateral_fraction".into(),
                    json!(self.broken_lateral_fraction(f64::INFINITY)),
                );
                if let Some(t) = m.get("peak_time").and_then(Value::as_f64) {
                    m.insert(
                        "broken_beams_lateral_fraction_at_peak".into(),
                        json!(self.broken_lateral_fraction(t)),
                    );
                }
            }
            Beam2dLoading::Explosion { .. } | Beam2dLoading::Projectile { .. } => {
                self.fragment_summary(&mut m);
            }
            Beam2dLoading::ElasticModuli(_) => {}
        }
        Value::Object(m)
    }

    fn fragment_summary(&self, m: &mut serde_json::Map<String, Value>) {
        let (_, masses, _) = self.fragment_masses();
        let total: f64 = masses.iter().sum();
        let largest = masses.iter().copied().fold(0.0, f64::max);
        m.insert("fragments".into(), masses.len().into());
        let fit = self.power_law();
        m.insert("beta".into(), json!(fit.map(|f| f.exponent)));
        let f = &self.scene.fragments;
        let unit = self.mean_polygon_mass;
        m.insert(
            "beta_fit_range".into(),
            json!([f.fit_range[0] * unit, f.fit_range[1] * unit]),
        );
        m.insert("beta_fit_range_polygon_masses".into(), json!(f.fit_range));
        m.insert("beta_fit_bins".into(), json!(fit.map(|f| f.bins)));
        m.insert("beta_r_squared".into(), json!(fit.map(|f| f.r_squared)));
        m.insert("largest_fragment_fraction".into(), (largest / total).into());
        m.insert(
            "momentum_drift_relative".into(),
            self.max_momentum_drift.into(),
        );
        let quiet = self.loading.quiet_steps().unwrap_or(u64::MAX);
        m.insert(
            "stopped_by".into(),
            if self.steps_since_break >= quiet {
                format!("{quiet} steps without a break")
            } else {
                "loading.end_time".to_string()
            }
            .into(),
        );
        if let Beam2dLoading::Explosion {
            explosive_mass,
            kicked,
            ..
        } = &self.loading
        {
            m.insert("explosive_mass".into(), (*explosive_mass).into());
            m.insert("kicked_polygons".into(), (*kicked).into());
        }
    }

    /// fragments.csv: one line per fragment (components over intact beams).
    pub fn fragments_csv(&self) -> String {
        let (labels, masses, sizes) = self.fragment_masses();
        let n = masses.len();
        let (mut centre, mut momentum) = (vec![Vec2::zeros(); n], vec![Vec2::zeros(); n]);
        for (i, &l) in labels.iter().enumerate() {
            let m = self.polygons.mass[i];
            centre[l as usize] += self.polygons.centre(i) * m;
            momentum[l as usize] += self.polygons.velocity(i) * m;
        }
        let mut s = String::from("fragment,polygons,mass,x,y,vx,vy\n");
        for k in 0..n {
            let (c, v) = (centre[k] / masses[k], momentum[k] / masses[k]);
            let _ = writeln!(
                s,
                "{k},{},{:e},{:e},{:e},{:e},{:e}",
                sizes[k], masses[k], c.x, c.y, v.x, v.y
            );
        }
        s
    }

    /// fragment_histogram.csv: the log-binned histogram of fragments of two or more polygons.
    pub fn histogram_csv(&self) -> String {
        let f = &self.scene.fragments;
        let bins = mass_histogram(
            &self.multi_polygon_fragment_masses(),
            self.mean_polygon_mass,
            f.bins_per_decade,
            1,
        );
        let mut s = String::from("mass_lo,mass_hi,mass_centre,count,density\n");
        for b in &bins {
            let _ = writeln!(
                s,
                "{:e},{:e},{:e},{},{:e}",
                b.lo,
                b.hi,
                b.centre(),
                b.count,
                b.density
            );
        }
        s
    }
}

/// The power law fitted to the fragment mass histogram averaged over several runs of one
/// scene (different seeds): the fragments of two or more polygons of all runs, binned in units
/// of the runs' mean polygon mass, per run; fitted over the scene's `fragments.fit_range`.
pub fn averaged_power_law(runs: &[&Beam2dRun]) -> Option<PowerLawFit> {
    let first = runs.first()?;
    let unit = runs.iter().map(|r| r.mean_polygon_mass).sum::<f64>() / runs.len() as f64;
    let masses: Vec<f64> = runs
        .iter()
        .flat_map(|r| r.multi_polygon_fragment_masses())
        .collect();
    let f = &first.scene.fragments;
    let bins = mass_histogram(&masses, unit, f.bins_per_decade, runs.len());
    fit_power_law(&bins, f.fit_range[0] * unit, f.fit_range[1] * unit)
}

impl Run for Beam2dRun {
    fn scene(&self) -> &Scene {
        &self.scene
    }
    fn model(&self) -> &'static str {
        "beam2d"
    }
    fn bodies(&self) -> usize {
        self.polygons.len()
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
        Beam2dRun::threads(self)
    }
    fn finished(&self) -> bool {
        Beam2dRun::finished(self)
    }
    fn advance(&mut self, steps: u64) -> Result<()> {
        Beam2dRun::advance(self, steps)
    }
    fn series(&self) -> &Series {
        &self.series
    }
    fn summary(&self) -> Value {
        Beam2dRun::summary(self)
    }
    fn snapshot(&self) -> Vec<(&'static str, String)> {
        let (labels, _) = self.fragments();
        let mut files = vec![("polygons", polygons_vtu(&self.polygons, &labels))];
        if !self.beams.is_empty() {
            files.push(("beams", beams_vtu(&self.polygons, &self.beams, false)));
            files.push(("broken_beams", beams_vtu(&self.polygons, &self.beams, true)));
        }
        files
    }
    fn extra_outputs(&self) -> Vec<(String, Vec<u8>)> {
        vec![
            ("fragments.csv".into(), self.fragments_csv().into_bytes()),
            (
                "fragment_histogram.csv".into(),
                self.histogram_csv().into_bytes(),
            ),
        ]
    }
    fn save_state(&self) -> Vec<u8> {
        postcard::to_stdvec(&self.state()).expect("the beam2d state serialises")
    }
    fn status(&self) -> String {
        format!(
            "t = {:.4e} s, {} beams broken",
            self.time,
            self.beams.broken()
        )
    }
    fn warnings(&self) -> &[String] {
        &self.warnings
    }
}

/// `fractum explain` for a beam2d scene: what it builds, without building the lattice.
pub fn explain(scene: &Scene) -> Result<String> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "scene {} (\"{}\"), seed {}",
        scene.source.label, scene.name, scene.seed
    );
    let _ = writeln!(
        s,
        "model: beam2d, rigid Voronoi polygons with overlap repulsion and breakable beams (2D, plane stress)"
    );
    let p = &scene.sample;
    let spacing = p.spacing.unwrap_or_default();
    let outline = match p.outline {
        Some(Outline::Rectangle) => {
            let c = p.cells.unwrap_or_default();
            format!(
                "a {} x {} m rectangle ({} x {} squares)",
                c[0] as f64 * spacing,
                c[1] as f64 * spacing,
                c[0],
                c[1]
            )
        }
        Some(Outline::Disc) => format!(
            "a disc of diameter {} m (about {:.0} polygons)",
            p.diameter.unwrap_or_default(),
            std::f64::consts::PI / 4.0 * (p.diameter.unwrap_or_default() / spacing).powi(2)
        ),
        None => String::new(),
    };
    let _ = writeln!(
        s,
        "sample: vectorizable random lattice, spacing {spacing:e} m, disorder {:e} m, cut to {outline}, thickness {:e} m",
        p.disorder.unwrap_or_default(),
        p.thickness.unwrap_or(1.0)
    );
    let pipeline = PolygonPipeline::build(scene, &Polygons::default(), &Beams::default(), 0.0);
    crate::explain::write_pipeline(
        &mut s,
        scene,
        &pipeline.describe(),
        &BEAM2D_EFFECTS,
        "polygons move freely",
    );
    let l = &scene.loading;
    let loading = match l.kind {
        LoadingKind::ElasticModuli => format!(
            "elastic moduli: top and bottom layers pulled apart at strain rate {} 1/s (ramp {} s) to strain {}, then compressed from the start to -{}",
            l.strain_rate.unwrap_or_default(),
            l.ramp_time.unwrap_or(0.0),
            l.end_strain.unwrap_or_default(),
            l.end_strain.unwrap_or_default()
        ),
        LoadingKind::ConfinedCompression => format!(
            "confined compression at strain rate {} 1/s (ramp {} s) to strain -{}; layers' x and rotation fixed",
            l.strain_rate.unwrap_or_default(),
            l.ramp_time.unwrap_or(0.0),
            l.end_strain.unwrap_or_default()
        ),
        LoadingKind::Explosion => format!(
            "explosion of the centre polygon, energy {:e} J; stops after {} steps without a break or at {:e} s",
            l.energy.unwrap_or_default(),
            l.quiet_steps.unwrap_or(300),
            l.end_time.unwrap_or_default()
        ),
        LoadingKind::Projectile => format!(
            "projectile: the polygon at the lower middle starts at {} m/s upwards; stops after {} steps without a break or at {:e} s",
            l.speed.unwrap_or_default(),
            l.quiet_steps.unwrap_or(300),
            l.end_time.unwrap_or_default()
        ),
        LoadingKind::None
        | LoadingKind::Oedometer
        | LoadingKind::Platens
        | LoadingKind::Tension
        | LoadingKind::FreeVibration
        | LoadingKind::Brazilian
        | LoadingKind::Drop => String::new(),
    };
    let _ = writeln!(s, "loading: {loading}");
    let dt = match scene.time.dt {
        DtSpec::Auto => format!(
            "auto = {} x the estimated stability limit 2/omega of the stiffest polygon",
            scene.time.safety
        ),
        DtSpec::Seconds(v) => format!("{v:e} s"),
    };
    let integrator = match scene.time.integrator {
        IntegratorKind::Gear5 => "Gear fifth-order predictor-corrector",
        IntegratorKind::VelocityVerlet | IntegratorKind::TchamwaWielgosz => "velocity Verlet",
    };
    let _ = writeln!(s, "integrator: {integrator}, dt {dt}");
    let vtk = if scene.output.vtk > 0 {
        format!(
            "VTK snapshot (polygons, beams, broken_beams) every {} steps",
            scene.output.vtk
        )
    } else {
        "no VTK".to_string()
    };
    let _ = writeln!(
        s,
        "outputs: series.csv row every {} steps, {vtk}, summary.json, fragments.csv and fragment_histogram.csv at the end",
        scene.output.every
    );
    Ok(s)
}
