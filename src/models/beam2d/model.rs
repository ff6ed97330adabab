//! The beam2d model as the runner drives it.

use super::build::{critical_time_step, lattice, make_beams, polygon_pipeline};
use super::*;
use crate::run::{BodiesView, Physics, Report};

impl Model for Beam2d {
    const KIND: &'static str = "beam2d";

    type Raw = scene::RawBeam2dScene;

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
}

impl Physics for Beam2d {
    type Config = Beam2dScene;

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
        let start = loading.as_loading().restarts().then(|| StartState {
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
        let load = loading.as_loading();
        let columns = load.columns().to_vec();
        let mut clock = Clock::planned(scene, cfg.material.young, dt, load.end_time())?;
        // The moduli test runs two phases, each to the step that ends it.
        clock.end_step = load.end_step(dt);
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
            clock,
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
        st.loading.as_loading().prescribe(t, p);
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
            .as_loading()
            .quiet_steps()
            .is_some_and(|q| self.state.steps_since_break >= q)
    }

    fn output_due(&self, clock: &Clock) -> bool {
        self.phase_ends(clock)
    }

    fn after_row(&mut self, clock: &Clock, _series: &Series) {
        if self.phase_ends(clock) {
            self.start_next_phase(clock);
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
}

impl Report for Beam2d {
    fn row(&mut self, clock: &Clock) -> Vec<f64> {
        let st = &mut self.state;
        if st.loading.as_loading().conserves_momentum() && st.momentum_scale > 0.0 {
            let drift = (st.polygons.momentum() - st.momentum0).norm() / st.momentum_scale;
            st.max_momentum_drift = st.max_momentum_drift.max(drift);
        }
        self.state.loading.as_loading().row(self, clock.time)
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
        let loading = self.state.loading.as_loading();
        loading.summarize(self, run.series, m);
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
}

impl BodiesView for Beam2d {
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
