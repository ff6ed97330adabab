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
mod explain;
pub mod loading;
pub mod pipeline;
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

/// Fragment labels over the intact beams, and their number.
fn fragments(polygons: &Polygons, b: &Beams) -> (Vec<u32>, usize) {
    components(
        polygons.len(),
        (0..b.len())
            .filter(|&k| b.intact[k])
            .map(|k| (b.i[k] as usize, b.j[k] as usize)),
    )
}

/// The lattice a beam2d scene describes.
fn lattice(scene: &Scene, cfg: &Beam2dScene) -> Result<PolygonSample> {
    let p = &cfg.sample;
    let spec = LatticeSpec {
        spacing: p.spacing,
        disorder: p.disorder,
        shape: p.shape,
        thickness: p.thickness,
        density: cfg.material.density,
    };
    let mut rng = crate::sample::stream(scene.seed, STREAM_LATTICE);
    vectorizable_random_lattice(&spec, &mut rng).map_err(|m| scene.key_error("sample", m))
}

/// The force pipeline of a beam2d scene on its polygons and beams.
fn polygon_pipeline(scene: &Scene, cfg: &Beam2dScene, st: &Beam2dState) -> PolygonPipeline {
    let skin = cfg.neighbor.skin.unwrap_or(0.3 * st.info.spacing);
    PolygonPipeline::build(scene, cfg, &st.polygons, &st.beams, skin)
}

/// The beams over the sample's shared sides (only with the `beams` effect); none to a free
/// projectile.
fn make_beams(cfg: &Beam2dScene, sample: &PolygonSample, loading: &Beam2dLoading) -> Beams {
    let mut beams = Beams::default();
    // Present exactly with the `beams` effect.
    let Some(material) = cfg.material.beams else {
        return beams;
    };
    let young = material.young;
    let t = sample.info.thickness;
    let p = &sample.polygons;
    let loose = match loading {
        Beam2dLoading::Projectile {
            polygon,
            free: true,
            ..
        } => Some(*polygon),
        _ => None,
    };
    for s in &sample.sides {
        let (i, j) = (s.i as usize, s.j as usize);
        if loose.is_some_and(|k| k == i || k == j) {
            continue;
        }
        beams.push([i, j], [p.centre(i), p.centre(j)], s.length, t, young);
    }
    beams
}

/// Velocity Verlet's stability limit 2/ω for the stiffest polygon, with
/// `ω² = 2 Σ k / m` over its beams (axial plus shear stiffness) and contacts across its sides
/// (`Y t S / Lc`), and likewise for rotation.
fn critical_time_step(
    scene: &Scene,
    cfg: &Beam2dScene,
    sample: &PolygonSample,
    beams: &Beams,
) -> f64 {
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
        let yt = cfg.material.young * sample.info.thickness;
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

impl Beam2d {
    /// Forces at the current state (time `time`, step `dt`), and Gear's derivatives started
    /// from them.
    fn restart_dynamics(&mut self, time: f64, dt: f64) {
        let st = &mut self.state;
        st.loading.prescribe(time, &mut st.polygons);
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

    /// The step at which the moduli test's first phase ends (none for other loadings).
    fn phase_end(&self, clock: &Clock) -> u64 {
        match &self.state.loading {
            Beam2dLoading::ElasticModuli(d) if d.phase == 0 => clock.end_step / 2,
            _ => u64::MAX,
        }
    }

    /// The moduli test's second phase: back to the initial state, then compress.
    fn start_compression_phase(&mut self, clock: &Clock) {
        let st = &mut self.state;
        let start = st.start.as_ref().expect("kept for the moduli test");
        st.polygons.q.clone_from(&start.q);
        st.polygons.v.clone_from(&start.v);
        if let Beam2dLoading::ElasticModuli(d) = &mut st.loading {
            d.phase = 1;
            d.phase_start = clock.time;
            d.sign = -1.0;
        }
        self.restart_dynamics(clock.time, clock.dt);
    }

    /// Elastic energy (J) stored in the intact beams.
    pub fn beam_energy(&self) -> f64 {
        let (b, p) = (&self.state.beams, &self.state.polygons);
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
        fragments(&self.state.polygons, &self.state.beams)
    }

    /// Fragment masses (kg) and polygon counts, in label order.
    fn fragment_masses(&self) -> (Vec<u32>, Vec<f64>, Vec<usize>) {
        let (labels, count) = self.fragments();
        let masses = sum_by_component(&labels, count, &self.state.polygons.mass);
        let mut sizes = vec![0usize; count];
        for &l in &labels {
            sizes[l as usize] += 1;
        }
        (labels, masses, sizes)
    }

    /// The power-law fit of the mass histogram of fragments of two or more polygons (single
    /// polygons are left out, as in the paper's Fig. 11).
    pub fn power_law(&self) -> Option<PowerLawFit> {
        let masses = self.multi_polygon_fragment_masses();
        self.cfg
            .fragments
            .fit(&masses, self.state.mean_polygon_mass, 1)
    }

    /// Masses (kg) of the fragments of two or more polygons: what the histogram is made of.
    pub fn multi_polygon_fragment_masses(&self) -> Vec<f64> {
        self.fragment_masses_from(2)
    }

    /// Masses (kg) of the fragments of at least `polygons` polygons (1: every fragment).
    pub fn fragment_masses_from(&self, polygons: usize) -> Vec<f64> {
        let (_, masses, sizes) = self.fragment_masses();
        masses
            .iter()
            .zip(&sizes)
            .filter(|(_, s)| **s >= polygons)
            .map(|(m, _)| *m)
            .collect()
    }

    /// Fraction of the broken beams (up to `until`, s) that lay within 30° of the x axis at
    /// rest: perpendicular to the load of the compression tests.
    pub fn broken_lateral_fraction(&self, until: f64) -> Option<f64> {
        let b = &self.state.beams;
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

    fn fragment_summary(&self, m: &mut Map<String, Value>) {
        let (_, masses, _) = self.fragment_masses();
        let total: f64 = masses.iter().sum();
        let largest = masses.iter().copied().fold(0.0, f64::max);
        m.insert("fragments".into(), masses.len().into());
        let fit = self.power_law();
        m.insert("beta".into(), json!(fit.map(|f| f.exponent)));
        m.insert("beta_fit_range".into(), json!(fit.map(|f| f.range)));
        m.insert(
            "beta_fit_range_polygon_masses".into(),
            json!(fit.map(|f| f.range.map(|x| x / self.state.mean_polygon_mass))),
        );
        m.insert("beta_fit_bins".into(), json!(fit.map(|f| f.bins)));
        m.insert("beta_r_squared".into(), json!(fit.map(|f| f.r_squared)));
        m.insert("largest_fragment_fraction".into(), (largest / total).into());
        m.insert(
            "momentum_drift_relative".into(),
            self.state.max_momentum_drift.into(),
        );
        let quiet = self.state.loading.quiet_steps().unwrap_or(u64::MAX);
        m.insert(
            "stopped_by".into(),
            if self.state.steps_since_break >= quiet {
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
        } = &self.state.loading
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
            let m = self.state.polygons.mass[i];
            centre[l as usize] += self.state.polygons.centre(i) * m;
            momentum[l as usize] += self.state.polygons.velocity(i) * m;
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
        let f = &self.cfg.fragments;
        let bins = mass_histogram(
            &self.multi_polygon_fragment_masses(),
            self.state.mean_polygon_mass,
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
/// of the runs' mean polygon mass, per run; fitted by the first run's `fragments` rule.
pub fn averaged_power_law(runs: &[&Beam2dRun]) -> Option<PowerLawFit> {
    let first = runs.first()?;
    averaged_power_law_by(runs, &first.model.cfg.fragments, 2)
}

/// [`averaged_power_law`] by another fit rule `spec`, over the fragments of at least
/// `polygons` polygons (the beam2d ablation's fragment definition and fit window).
pub fn averaged_power_law_by(
    runs: &[&Beam2dRun],
    spec: &scene::FragmentSpec,
    polygons: usize,
) -> Option<PowerLawFit> {
    if runs.is_empty() {
        return None;
    }
    let unit = runs
        .iter()
        .map(|r| r.model.state.mean_polygon_mass)
        .sum::<f64>()
        / runs.len() as f64;
    let masses: Vec<f64> = runs
        .iter()
        .flat_map(|r| r.model.fragment_masses_from(polygons))
        .collect();
    spec.fit(&masses, unit, runs.len())
}

/// β's 95% interval over the seeds of [`averaged_power_law`]: 2000 bootstrap resamples of the
/// runs, each fitted by the same rule (docs/validation.md, "How β is fitted").
pub fn averaged_power_law_interval(runs: &[&Beam2dRun]) -> Option<[f64; 2]> {
    bootstrap_interval(runs, 2000, 20, |draw| {
        averaged_power_law(&draw.iter().map(|r| **r).collect::<Vec<_>>()).map(|f| f.exponent)
    })
}

impl Model for Beam2d {
    const KIND: &'static str = "beam2d";
    type Raw = scene::RawBeam2dScene;
    type Config = Beam2dScene;
    const BODY: &'static str = "polygon";
    const EFFECTS: &'static [EffectKind] = &scene::EFFECTS;
    const INTEGRATORS: &'static [IntegratorKind] =
        &[IntegratorKind::VelocityVerlet, IntegratorKind::Gear5];
    const SHARED_KEYS: &'static [&'static str] = &[];

    fn config(scene: &Scene, raw: &scene::RawBeam2dScene) -> Result<Beam2dScene> {
        scene::validate(scene, raw)
    }

    fn explain(scene: &Scene, cfg: &Beam2dScene) -> Result<String> {
        explain::explain(scene, cfg)
    }

    fn build(
        scene: &Scene,
        cfg: Beam2dScene,
        progress: &mut (dyn FnMut(&str) + Send),
    ) -> Result<Built<Self>> {
        let mut sample = lattice(scene, &cfg)?;
        progress(&format!(
            "{} polygons ({:.2} vertices on average), {} shared sides",
            sample.info.polygons, sample.info.mean_vertices, sample.info.shared_sides
        ));
        let mean_polygon_mass = sample.polygons.total_mass() / sample.polygons.len() as f64;
        let loading = Beam2dLoading::prepare(scene, &cfg, &mut sample)?;
        let beams = make_beams(&cfg, &sample, &loading);
        let dt_critical = critical_time_step(scene, &cfg, &sample, &beams);
        let dt = scene.time.step(dt_critical);
        if !dt.is_finite() {
            return Err(scene.key_error(
                "time.dt",
                "= \"auto\" needs contacts or beams to estimate a step from; give a time step in seconds",
            ));
        }
        let PolygonSample { polygons, info, .. } = sample;
        let integrator = match scene.time.integrator {
            IntegratorKind::Gear5 => Integrator2d::Gear5(Gear5::new(
                3 * polygons.len(),
                scene.has_effect(EffectKind::Damping) || scene.has_effect(EffectKind::Friction),
            )),
            _ => Integrator2d::VelocityVerlet,
        };
        let start = matches!(loading, Beam2dLoading::ElasticModuli(_)).then(|| StartState {
            q: polygons.q.clone(),
            v: polygons.v.clone(),
        });
        if !dt_critical.is_normal() {
            // A density of 1e-300 kg/m³ (or a modulus near the largest double) gave a limit of
            // 0 s and the advice "set time.dt to at most 0.000e0 s".
            return Err(scene.key_error(
                "material.density",
                format!(
                    "= {:e} kg/m³ with material.young = {:e} Pa (and the beams' modulus) gives a \
                     stability limit of the step of {dt_critical:e} s, zero or denormal, which \
                     no step can run under; allowed: a density and moduli of a solid (the limit \
                     is 2/ω with ω² = 2 Σk/m)",
                    cfg.material.density, cfg.material.young
                ),
            ));
        }
        // The limit is a bound (Gershgorin: ω² ≤ 2 Σk/m), so every step up to it is stable;
        // above it stability is not assured and was seen to fail (explosion_disc at 1.9x:
        // kinetic energy 10x its initial value). Refused rather than warned.
        if dt > dt_critical {
            return Err(scene.key_error(
                scene.time.step_key(),
                format!(
                    "gives a step of {dt:e} s, above the stability limit {dt_critical:.4e} s of the stiffest polygon (2/ω with ω² = 2 Σk/m over its beams and side contacts, a bound): set time.dt to at most {dt_critical:.3e} s"
                ),
            ));
        }
        let warnings = Vec::new();
        let columns = loading.columns().to_vec();
        crate::run::check_planned_steps(scene, cfg.material.young, loading.end_time(), dt)?;
        let end_step = loading.end_step(dt);
        let end_time = loading.end_time();
        let state = Beam2dState {
            forces: vec![[0.0; 3]; polygons.len()],
            momentum0: polygons.momentum(),
            momentum_scale: polygons.momentum_scale(),
            initial_kinetic_energy: polygons.kinetic_energy(),
            polygons,
            beams,
            integrator,
            loading,
            info,
            mean_polygon_mass,
            dt_critical,
            steps_since_break: 0,
            contacts: 0,
            max_momentum_drift: 0.0,
            start,
        };
        let mut model = Beam2d {
            pipeline: polygon_pipeline(scene, &cfg, &state),
            cfg,
            state,
        };
        model.restart_dynamics(0.0, dt);
        Ok(Built {
            model,
            dt,
            end_step,
            end_time,
            columns,
            warnings,
        })
    }

    fn save(&self) -> Vec<u8> {
        postcard::to_stdvec(&self.state).expect("the beam2d state serialises")
    }

    fn restore(scene: &Scene, cfg: Beam2dScene, bytes: &[u8]) -> Result<Self> {
        let state: Beam2dState = postcard::from_bytes(bytes)
            .map_err(|e| Error::run(format!("the checkpoint's beam2d state is damaged ({e})")))?;
        Ok(Beam2d {
            pipeline: polygon_pipeline(scene, &cfg, &state),
            cfg,
            state,
        })
    }

    fn bodies(&self) -> usize {
        self.state.polygons.len()
    }

    fn step(&mut self, clock: &Clock, dt: f64) {
        let st = &mut self.state;
        let p = &mut st.polygons;
        match &mut st.integrator {
            Integrator2d::VelocityVerlet => kick_drift_dofs(
                p.q.as_flattened_mut(),
                p.v.as_flattened_mut(),
                st.forces.as_flattened(),
                p.inv_m.as_flattened(),
                dt,
            ),
            Integrator2d::Gear5(g) => g.predict(p.q.as_flattened_mut(), p.v.as_flattened_mut(), dt),
        }
        let t = clock.time + dt;
        st.loading.prescribe(t, p);
        let counts = self.pipeline.evaluate(p, &mut st.beams, t, &mut st.forces);
        match &mut st.integrator {
            Integrator2d::VelocityVerlet => kick_dofs(
                p.v.as_flattened_mut(),
                st.forces.as_flattened(),
                p.inv_m.as_flattened(),
                dt,
            ),
            Integrator2d::Gear5(g) => g.correct(
                p.q.as_flattened_mut(),
                p.v.as_flattened_mut(),
                st.forces.as_flattened(),
                p.inv_m.as_flattened(),
                dt,
            ),
        }
        st.contacts = counts.contacts;
        st.steps_since_break = if counts.broken > 0 {
            0
        } else {
            st.steps_since_break + 1
        };
    }

    /// Once `quiet_steps` steps passed without a break.
    fn stopped(&self) -> bool {
        self.state
            .loading
            .quiet_steps()
            .is_some_and(|q| self.state.steps_since_break >= q)
    }

    fn output_due(&self, clock: &Clock) -> bool {
        clock.step == self.phase_end(clock)
    }

    fn row(&mut self, clock: &Clock) -> Vec<f64> {
        let st = &mut self.state;
        let p = &st.polygons;
        let ke = p.kinetic_energy();
        let broken = st.beams.broken() as f64;
        match st.loading.driven() {
            Some(d) => {
                let (strain, stress, lateral) = d.measure(p, &st.forces);
                vec![
                    clock.time,
                    strain,
                    stress,
                    lateral,
                    ke,
                    st.contacts as f64,
                    broken,
                ]
            }
            None => {
                let momentum = p.momentum();
                if st.momentum_scale > 0.0 {
                    let drift = (momentum - st.momentum0).norm() / st.momentum_scale;
                    st.max_momentum_drift = st.max_momentum_drift.max(drift);
                }
                let (_, count) = fragments(p, &st.beams);
                vec![
                    clock.time,
                    ke,
                    st.contacts as f64,
                    broken,
                    count as f64,
                    momentum.x,
                    momentum.y,
                ]
            }
        }
    }

    fn after_row(&mut self, clock: &Clock, _series: &Series) {
        if clock.step == self.phase_end(clock) {
            self.start_compression_phase(clock);
        }
    }

    fn first_non_finite(&self) -> Option<usize> {
        self.state.polygons.first_non_finite()
    }

    fn instability_hint(&self, _scene: &Scene, clock: &Clock) -> String {
        format!(
            "lower time.dt (now {:e} s, estimated limit {:e} s)",
            clock.dt, self.state.dt_critical
        )
    }

    /// Gear's scaled derivatives hold the step: it cannot be shortened.
    fn variable_step(&self) -> bool {
        matches!(self.state.integrator, Integrator2d::VelocityVerlet)
    }

    fn summary(&self, run: &RunInfo, m: &mut Map<String, Value>) {
        m.insert(
            "integrator".into(),
            run.scene.time.integrator.as_str().into(),
        );
        m.insert("dt_critical".into(), self.state.dt_critical.into());
        m.insert(
            "sample".into(),
            serde_json::to_value(&self.state.info).expect("info serialises"),
        );
        m.insert("polygons".into(), self.state.polygons.len().into());
        m.insert(
            "mean_polygon_mass".into(),
            self.state.mean_polygon_mass.into(),
        );
        m.insert("beams".into(), self.state.beams.len().into());
        m.insert("broken_beams".into(), self.state.beams.broken().into());
        m.insert("contacts_final".into(), self.state.contacts.into());
        m.insert(
            "kinetic_energy_initial".into(),
            self.state.initial_kinetic_energy.into(),
        );
        m.insert(
            "kinetic_energy_final".into(),
            self.state.polygons.kinetic_energy().into(),
        );
        self.state.loading.summarize(run.series, m);
        match &self.state.loading {
            Beam2dLoading::ConfinedCompression(_) => {
                let all = &self.state.beams.rest_direction;
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
                self.fragment_summary(m);
            }
            Beam2dLoading::ElasticModuli(_) => {}
        }
    }

    fn snapshot(&self) -> Vec<(&'static str, String)> {
        let (labels, _) = self.fragments();
        let mut files = vec![("polygons", polygons_vtu(&self.state.polygons, &labels))];
        if !self.state.beams.is_empty() {
            files.push((
                "beams",
                beams_vtu(&self.state.polygons, &self.state.beams, false),
            ));
            files.push((
                "broken_beams",
                beams_vtu(&self.state.polygons, &self.state.beams, true),
            ));
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

    fn status(&self, clock: &Clock) -> String {
        format!(
            "t = {:.4e} s, {} beams broken",
            clock.time,
            self.state.beams.broken()
        )
    }

    fn contacts(&self) -> Option<usize> {
        Some(self.state.contacts)
    }

    fn kinetic_energy(&self) -> f64 {
        self.state.polygons.kinetic_energy()
    }

    fn positions(&self) -> Vec<Vec3> {
        let p = &self.state.polygons;
        (0..p.len())
            .map(|i| Vec3::new(p.q[i][0], p.q[i][1], 0.0))
            .collect()
    }

    fn velocities(&self) -> Vec<Vec3> {
        let p = &self.state.polygons;
        (0..p.len())
            .map(|i| Vec3::new(p.v[i][0], p.v[i][1], 0.0))
            .collect()
    }

    /// Rotations about z by each polygon's angle.
    fn orientations(&self) -> Vec<[f64; 4]> {
        self.state
            .polygons
            .q
            .iter()
            .map(|q| {
                let (s, c) = (0.5 * q[2]).sin_cos();
                [c, 0.0, 0.0, s]
            })
            .collect()
    }
}
