//! The dlsm model as the runner drives it.

use super::*;
use crate::run::{BodiesView, Physics, Report};

impl Model for Dlsm {
    const KIND: &'static str = "dlsm";

    type Raw = scene::RawDlsmScene;

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
}

impl Physics for Dlsm {
    type Config = DlsmScene;

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
        let start = Clock::planned(scene, model.cfg.material.young, dt, end_time)?;
        model
            .state
            .loading
            .as_loading()
            .prescribe(&mut model.state.bodies, 0.0);
        model.evaluate_forces(&start, 0.0);
        Ok(Built {
            model,
            clock: start,
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
        let built = std::mem::take(&mut model.state.pipeline);
        model.state = state;
        model.state.pipeline.keep_built(built);
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
}

impl Report for Dlsm {
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
            contact_energy: st.pipeline.ground.as_ref().map_or(0.0, |g| g.energy),
            ground_contacts: st.pipeline.ground.as_ref().map_or(0, |g| g.contacts),
        };
        st.loading.as_loading_mut().row(&inputs)
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
}

impl BodiesView for Dlsm {
    fn rigid_bodies(&self) -> Option<&Bodies> {
        Some(&self.state.bodies)
    }
}
