//! The granular model as the runner drives it.

use super::step::TEAM_MIN_SPHERES_PER_THREAD;
use super::*;
use crate::run::{BodiesView, Physics, Report};

impl Model for Granular {
    const KIND: &'static str = "granular";

    type Raw = scene::RawGranularScene;

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
}

impl Physics for Granular {
    type Config = GranularScene;

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

    /// Every thread: a sample's preparation runs its large samples in parts on the team, the
    /// same sample on any thread count (`sample::PREPARATION_PART_ROWS`).
    fn build_members(threads: usize) -> usize {
        threads
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
        match &st.driven {
            Some(d) => d.apply(&mut st.walls),
            None => st.loading.as_loading().apply(&mut st.walls),
        }
        self.integrator.kick_drift(&mut st.bodies, &st.forces, dt);
        st.walls.advance(dt);
        self.evaluate_forces(dt, true);
        let st = &mut self.state;
        self.integrator.kick(&mut st.bodies, &st.forces, dt);
    }

    fn after_step(&mut self, clock: &Clock, dt: f64) -> Option<f64> {
        if self.state.fracture.is_some() {
            self.after_fracture_step(clock, dt)
        } else {
            None
        }
    }

    fn check_step(
        &mut self,
        scene: &Scene,
        clock: &Clock,
        warn: &mut Vec<String>,
    ) -> Result<Option<f64>> {
        if !self.state.step_control.due(clock.step, clock.end_step) {
            return Ok(None);
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
        if let Some(why) = &self.state.step_control.collapsed {
            return Some(why.clone());
        }
        let st = &self.state;
        if !st.walls.is_box || st.loading().is_some_and(|l| l.holds()) {
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
        let fraction = solid / st.walls.volume();
        (fraction > 1.0 || size.min() <= 0.0).then(|| {
            format!(
                "the grains fill {fraction:.3} of the box (axial strain {:.3}): they overlap by more than all the pore space, beyond what contact mechanics describes; the faces were driven faster or further than the specimen can follow (lower the face speeds or loading.end_strain)",
                (st.height0 - size.z) / st.height0
            )
        })
    }

    fn first_non_finite(&self) -> Option<usize> {
        self.state.bodies.first_non_finite()
    }

    fn instability_hint(&self, scene: &Scene, _clock: &Clock) -> String {
        format!("lower time.safety (now {}) or time.dt", scene.time.safety)
    }
}

impl Report for Granular {
    fn row(&mut self, clock: &Clock) -> Vec<f64> {
        let st = &self.state;
        let contacts = self.pipeline.contacts();
        let mut row = if st.loading().is_some_and(|l| l.reads_platens()) {
            probe::platen_row(clock.time, st.height0, &st.bodies, &st.walls, contacts)
        } else if st.walls.is_box {
            let mut row = probe::box_row(clock.time, st.height0, &st.bodies, &st.walls, contacts);
            probe::sleeve_row(&st.walls, &mut row);
            row
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
        m.insert("max_omega_dt".into(), st.step_control.max_omega_dt.into());
        if st.fracture.is_some() {
            m.insert("dt_shortened".into(), st.step_control.shortened.into());
        }
        m.insert(
            "kinetic_energy_final".into(),
            st.bodies.kinetic_energy().into(),
        );
        if let Some(l) = st.loading() {
            l.summarize(run.series, m);
        }
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
}

impl BodiesView for Granular {
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

impl Runner<Granular> {
    /// A granular run on a sample made elsewhere (tests, benchmarks, exports).
    pub fn from_sample(scene: Scene, sample: Sample, threads: usize) -> Result<Self> {
        let cfg = Granular::read(&scene)?;
        let built = Granular::from_sample(&scene, cfg, sample)?;
        Runner::from_built(scene, built, threads)
    }

    /// Splits the given grains now (see [`Granular::break_grains`]).
    pub fn break_grains(&mut self, breaking: &[crate::fracture::Breaking]) -> usize {
        let (made, new_dt) = self.model.break_grains(&self.clock, breaking);
        if let Some(dt) = new_dt {
            self.clock.set_dt(dt);
        }
        made
    }
}
