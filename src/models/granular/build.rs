//! Building a granular model: the force pipeline of the effects a scene names, the
//! contact and fracture constants, and the model on a sample or a restored state.

use super::*;

/// The force pipeline of exactly the effects a granular scene names. `friction` overrides
/// the material's coefficient (sample preparation compacts with its own).
pub fn pipeline(scene: &Scene, cfg: &GranularScene) -> BodyPipeline {
    pipeline_for(scene, cfg, false)
}

/// [`pipeline`] for bodies that hold non-spherical shapes when `shaped` (a sample read from a
/// data file of the Fractum LAMMPS plugin may, whatever the scene's own keys say): their
/// contacts take the shapes' path.
pub(super) fn pipeline_for(scene: &Scene, cfg: &GranularScene, shaped: bool) -> BodyPipeline {
    let contact = scene.has_effect(EffectKind::Contact).then(|| {
        let mut params = contact_params(scene, cfg, None);
        params.shapes |= shaped;
        params
    });
    let gravity = scene
        .has_effect(EffectKind::Gravity)
        .then(|| Vec3::from(scene.gravity.acceleration));
    BodyPipeline::new(contact, gravity)
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
        sleeve_friction: cfg.walls.sleeve_friction,
        skin: cfg.neighbor.skin,
        shapes: scene.has_effect(EffectKind::Fracture) || cfg.sample.non_spherical(),
        parts: crate::effects::PairParts::PerThread,
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

/// The step control of a granular run whose first step is `dt` (s): with fracture and
/// `time.dt = "auto"` it shortens the step as pieces stiffen, checked every
/// [`STABILITY_EVERY`] steps; otherwise it checks after every step and never shortens.
pub(super) fn step_control(scene: &Scene, dt: f64) -> StepControl {
    let adapting = scene.has_effect(EffectKind::Fracture) && scene.time.dt == DtSpec::Auto;
    if adapting {
        StepControl::new(
            STABILITY_EVERY,
            Some(ADAPT_PER_SAFETY * scene.time.safety),
            dt,
        )
    } else {
        StepControl::new(1, None, dt)
    }
}

/// Puts the scene's sleeve (`walls.sleeve`) round `walls` if they lack it: the sleeve is not
/// saved with a sample (the sample cache) or a state, and a sample made elsewhere has none.
fn with_scene_sleeve(cfg: &GranularScene, walls: &mut Walls) {
    if cfg.walls.sleeve && walls.is_box && walls.sleeve.is_none() {
        walls.add_sleeve();
    }
}

impl Granular {
    /// Sets the model up on a sample (built from the scene, or made elsewhere).
    pub fn from_sample(scene: &Scene, cfg: GranularScene, sample: Sample) -> Result<Built<Self>> {
        let Sample {
            bodies,
            mut walls,
            info,
        } = sample;
        // A sample read from the cache (or made elsewhere) comes without the scene's sleeve.
        with_scene_sleeve(&cfg, &mut walls);
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
        let clock = Clock::planned(scene, m.young, dt, loading.as_loading().end_time())?;
        let mut columns: Vec<&'static str> = if loading.as_loading().reads_platens() {
            probe::PLATEN_COLUMNS.to_vec()
        } else if walls.is_box {
            probe::BOX_COLUMNS.to_vec()
        } else {
            probe::FREE_COLUMNS.to_vec()
        };
        if walls.sleeve.is_some() && !loading.as_loading().reads_platens() {
            columns.extend_from_slice(&probe::SLEEVE_COLUMNS);
        }
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
                step_control: step_control(scene, dt),
                fracture: fracture_state,
                energy: None,
                psd: Vec::new(),
                comminution: Vec::new(),
                initial: [0.0; 2],
                driven: None,
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
            clock,
            columns,
            warnings: Vec::new(),
        })
    }

    /// The model of `state` under its scene: what is built from the scene (pipeline,
    /// integrator, gravity, report strains) around the persistent state.
    pub(super) fn with_state(scene: &Scene, cfg: GranularScene, state: GranularState) -> Granular {
        let fracture = scene.has_effect(EffectKind::Fracture);
        let shaped = state.bodies.shape.iter().any(|s| !s.is_sphere());
        let mut model = Granular {
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
            solid_volume: std::cell::Cell::new(None),
            cfg,
            state,
        };
        // The sleeve is the scene's, not saved with a state: made again on a restored one.
        with_scene_sleeve(&model.cfg, &mut model.state.walls);
        model
    }
}
