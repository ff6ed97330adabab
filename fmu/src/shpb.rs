//! The SHPB specimen model: what the FMU's variables mean and how they map onto
//! `fractum::Simulation`. The FMI layer ([`crate::fmi2`]) reaches it only through
//! [`Model`]; every call into the `fractum` library is here.
//!
//! Variables (value references in [`vr`]):
//! * inputs `v_incident` (m/s, the incident-bar face moving into the specimen, compression
//!   positive) and `v_transmitted` (m/s, the transmitted-bar face moving along the bar axis,
//!   away from the specimen): the specimen shortens at `v_incident - v_transmitted`;
//! * outputs `stress_incident`, `stress_transmitted` (Pa, specimen axial stress at each face,
//!   compression positive), `force_incident`, `force_transmitted` (N, that stress over the
//!   specimen cross-section), `bar_stress_incident`, `bar_stress_transmitted` (Pa, the force
//!   over the bar cross-section), `strain`, `broken_particles`, `kinetic_energy` (J);
//! * calculated parameter `specimen_length` (m, the DEM specimen's axial length when loading
//!   starts, which `strain` is relative to; 0 until the specimen is built);
//! * parameters `scene` (a path inside resources/), `specimen_diameter`, `bar_diameter` (m),
//!   `seed`.

use std::path::Path;

use fractum::Run;
use fractum::models::granular::{Faces, Simulation};
use fractum::run::MAX_STEPS;
use serde::{Deserialize, Serialize};

use crate::fmi2::{Failure, Model, Phase, StepError};

/// The GUID of modelDescription.xml; Instantiate refuses any other.
pub const GUID: &str = "{5f1c6f2e-3b9a-4d57-9c1e-7a2f0d8e4b61}";
pub const MODEL_IDENTIFIER: &str = "fractum_shpb";
const DEFAULT_SCENE: &str = "shpb_sand.toml";

/// Value references.
pub mod vr {
    pub const V_INCIDENT: u32 = 0;
    pub const V_TRANSMITTED: u32 = 1;
    pub const STRESS_INCIDENT: u32 = 2;
    pub const STRESS_TRANSMITTED: u32 = 3;
    pub const FORCE_INCIDENT: u32 = 4;
    pub const FORCE_TRANSMITTED: u32 = 5;
    pub const BAR_STRESS_INCIDENT: u32 = 6;
    pub const BAR_STRESS_TRANSMITTED: u32 = 7;
    pub const STRAIN: u32 = 8;
    pub const KINETIC_ENERGY: u32 = 9;
    pub const SPECIMEN_DIAMETER: u32 = 10;
    pub const BAR_DIAMETER: u32 = 11;
    /// Integer variables.
    pub const BROKEN_PARTICLES: u32 = 12;
    pub const SEED: u32 = 13;
    /// String variable.
    pub const SCENE: u32 = 14;
    /// Boolean variable.
    pub const FRACTURE: u32 = 15;
    /// A calculated parameter (Real).
    pub const SPECIMEN_LENGTH: u32 = 16;
}

/// Everything a host can set, and the time.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Variables {
    v_incident: f64,
    v_transmitted: f64,
    specimen_diameter: f64,
    bar_diameter: f64,
    seed: i32,
    scene: String,
    /// Whether the grains may break (the scene's `fracture`, `cohesion` and `weibull`
    /// effects); false builds the same specimen without them.
    fracture: bool,
    /// The communication time (s) the outputs refer to.
    time: f64,
    /// The experiment's start time (s): the specimen's own clock reads `time - start`.
    start: f64,
}

/// The start values of modelDescription.xml.
impl Default for Variables {
    fn default() -> Self {
        Variables {
            // As modelDescription.xml's start: the default experiment compacts the specimen
            // at 500/s (with 0, `fmpy simulate` drew a flat line).
            v_incident: 3.0,
            v_transmitted: 0.0,
            specimen_diameter: 19.05e-3,
            bar_diameter: 19.05e-3,
            seed: 1,
            scene: DEFAULT_SCENE.to_string(),
            fracture: true,
            time: 0.0,
            start: 0.0,
        }
    }
}

impl Variables {
    /// The parameters, as a host sets them: what a saved state's specimen was built from.
    fn configuration(&self) -> String {
        format!(
            "scene = \"{}\", seed = {}, fracture = {}, specimen_diameter = {:e} m, \
             bar_diameter = {:e} m",
            self.scene, self.seed, self.fracture, self.specimen_diameter, self.bar_diameter
        )
    }
}

/// The outputs at one instant: face stresses (Pa, compression positive), axial strain,
/// kinetic energy (J) and broken grains.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
struct Sample {
    time: f64,
    top: f64,
    bottom: f64,
    strain: f64,
    kinetic: f64,
    broken: usize,
}

impl Sample {
    fn of(sim: &Simulation) -> Sample {
        let (top, bottom) = sim.model.face_stresses();
        Sample {
            time: sim.clock.time,
            top,
            bottom,
            strain: sim.model.axial_strain(),
            kinetic: sim.model.state.bodies.kinetic_energy(),
            broken: sim.model.broken_particles(),
        }
    }

    /// The sample at `time` between `lo` and `hi` (linear; broken grains as at `lo`).
    fn between(lo: &Sample, hi: &Sample, time: f64) -> Sample {
        let w = (time - lo.time) / (hi.time - lo.time);
        let at = |a: f64, b: f64| a + w * (b - a);
        Sample {
            time,
            top: at(lo.top, hi.top),
            bottom: at(lo.bottom, hi.bottom),
            strain: at(lo.strain, hi.strain),
            kinetic: at(lo.kinetic, hi.kinetic),
            broken: lo.broken,
        }
    }
}

/// One SHPB specimen: the variables, and the simulation once initialisation has built it.
///
/// The specimen advances on its own grid of whole steps, whatever the communication steps: a
/// master that steps by 1 µs and one that steps by 10 µs drive the very same trajectory, and
/// their outputs at a common time are the same bits (a fracture run is chaotic: the landing
/// steps a communication point forced into the trajectory used to move its outputs by the
/// runs' spread, up to 0.7% of the stress after 10 µs). `sim` goes to the first whole step at
/// or after the communication point; the outputs there are interpolated in time between that
/// step (`sim`) and the one before it (`lo`). An input set at a communication point therefore
/// acts from the step after `sim`'s time: at most one internal step (about 26 ns for the
/// shipped scene) late.
#[derive(Default)]
pub struct Shpb {
    vars: Variables,
    sim: Option<Simulation>,
    /// The outputs at the whole step before `sim`'s (once a step has been taken).
    lo: Sample,
    /// The outputs at the communication point `vars.time`.
    out: Sample,
}

/// What a saved FMU state holds of the model: the variables, the simulation's own saved
/// state and the outputs.
#[derive(Serialize, Deserialize)]
pub struct Saved {
    vars: Variables,
    sim: Option<Vec<u8>>,
    lo: Sample,
    out: Sample,
}

impl Shpb {
    fn scene_path(&self, resources: &Path) -> Result<std::path::PathBuf, Failure> {
        let rel = Path::new(&self.vars.scene);
        if rel.is_absolute()
            || rel
                .components()
                .any(|c| matches!(c, std::path::Component::ParentDir))
        {
            return Err(format!(
                "parameter scene = \"{}\" must be a path inside the FMU's resources folder",
                self.vars.scene
            ));
        }
        let path = resources.join(rel);
        // A link inside resources/ may point anywhere: the file it reaches must be inside too.
        if let (Ok(real), Ok(root)) = (path.canonicalize(), resources.canonicalize())
            && !real.starts_with(&root)
        {
            return Err(format!(
                "parameter scene = \"{}\" must be a path inside the FMU's resources folder \
                 (it is a link to {}, outside it)",
                self.vars.scene,
                real.display()
            ));
        }
        Ok(path)
    }

    /// The specimen's scene: the `scene` parameter's file with `seed`, no VTK and no series
    /// rows (the host reads the outputs).
    fn scene(&self, resources: &Path, seed: i32) -> Result<fractum::Scene, Failure> {
        let mut overrides = vec![
            format!("seed={seed}"),
            "output.vtk=0".to_string(),
            "output.every=1000000000".to_string(),
        ];
        let path = self.scene_path(resources)?;
        // Another model's scene was read as a granular one and refused for keys it rightly has.
        let own = fractum::Scene::load(&path, &[]).map_err(|e| e.to_string())?;
        if own.model.kind != "granular" {
            return Err(format!(
                "parameter scene = \"{}\" is a {} scene (model.kind = \"{}\"); this FMU runs \
                 granular SHPB scenes (model.kind = \"granular\") only",
                self.vars.scene, own.model.kind, own.model.kind
            ));
        }
        if !self.vars.fracture {
            // The scene's own effects less the three of grain breakage.
            let scene = fractum::Scene::load(&path, &overrides).map_err(|e| e.to_string())?;
            use fractum::scene::EffectKind::{Cohesion, Fracture, Weibull};
            let keep: Vec<String> = scene
                .effects
                .iter()
                .filter(|e| !matches!(e, Fracture | Cohesion | Weibull))
                .map(|e| format!("\"{}\"", e.as_str()))
                .collect();
            overrides.push(format!("effects=[{}]", keep.join(", ")));
        }
        fractum::Scene::load(&path, &overrides).map_err(|e| e.to_string())
    }
}

impl Model for Shpb {
    const GUID: &'static str = GUID;
    const MODEL_IDENTIFIER: &'static str = MODEL_IDENTIFIER;
    // The Integer and String variables a host can set are all parameters.
    const SET_REAL_IN: &'static [Phase] =
        &[Phase::Instantiated, Phase::Initialization, Phase::Running];
    const SET_INTEGER_IN: &'static [Phase] = &[Phase::Instantiated, Phase::Initialization];
    const SET_STRING_IN: &'static [Phase] = &[Phase::Instantiated, Phase::Initialization];
    /// `fracture`, a parameter.
    const SET_BOOLEAN_IN: &'static [Phase] = &[Phase::Instantiated, Phase::Initialization];
    const HAS_BOOLEANS: bool = true;
    type Saved = Saved;

    fn time(&self) -> f64 {
        self.vars.time
    }

    fn set_time(&mut self, time: f64) {
        self.vars.time = time;
        self.vars.start = time;
    }

    fn build(&mut self, resources: &Path) -> Result<(), Failure> {
        for (name, d) in [
            ("specimen_diameter", self.vars.specimen_diameter),
            ("bar_diameter", self.vars.bar_diameter),
        ] {
            if !(d.is_finite() && d > 0.0) {
                return Err(format!(
                    "parameter {name} = {d} is outside the allowed range (0, inf) m"
                ));
            }
        }
        let scene = self.scene(resources, self.vars.seed)?;
        let mut sim = Simulation::new(scene, 1, &mut |_| {}).map_err(|e| e.to_string())?;
        sim.set_face_speeds(self.vars.v_incident, -self.vars.v_transmitted)
            .map_err(|e| e.to_string())?;
        self.out = Sample::of(&sim);
        self.lo = self.out;
        self.sim = Some(sim);
        Ok(())
    }

    fn built(&self) -> String {
        let n = self.sim.as_ref().map_or(0, |s| s.model.state.bodies.len());
        format!("specimen built: {n} grains")
    }

    fn real(&self, r: u32) -> Result<f64, Failure> {
        let v = &self.vars;
        let area = |d: f64| std::f64::consts::PI * d * d / 4.0;
        let (top, bottom) = (self.out.top, self.out.bottom);
        // `+ 0.0` turns a negative zero (a face without contacts) into 0: masters wrote "-0".
        Ok(0.0
            + match r {
                vr::V_INCIDENT => v.v_incident,
                vr::V_TRANSMITTED => v.v_transmitted,
                vr::SPECIMEN_DIAMETER => v.specimen_diameter,
                vr::BAR_DIAMETER => v.bar_diameter,
                vr::STRESS_INCIDENT => top,
                vr::STRESS_TRANSMITTED => bottom,
                vr::FORCE_INCIDENT => top * area(v.specimen_diameter),
                vr::FORCE_TRANSMITTED => bottom * area(v.specimen_diameter),
                vr::BAR_STRESS_INCIDENT => top * area(v.specimen_diameter) / area(v.bar_diameter),
                vr::BAR_STRESS_TRANSMITTED => {
                    bottom * area(v.specimen_diameter) / area(v.bar_diameter)
                }
                vr::STRAIN => self.out.strain,
                vr::KINETIC_ENERGY => self.out.kinetic,
                vr::SPECIMEN_LENGTH => self.sim.as_ref().map_or(0.0, |s| s.model.initial_height()),
                _ => return Err(format!("{r} is not the value reference of a Real variable")),
            })
    }

    fn set_real(&mut self, r: u32, value: f64, phase: Phase) -> Result<(), Failure> {
        if !value.is_finite() {
            return Err(format!(
                "value reference {r}: {value} is not a finite number"
            ));
        }
        let parameter_phases = [Phase::Instantiated, Phase::Initialization];
        match r {
            vr::V_INCIDENT => self.vars.v_incident = value,
            vr::V_TRANSMITTED => self.vars.v_transmitted = value,
            vr::SPECIMEN_DIAMETER | vr::BAR_DIAMETER => {
                phase.expect(&parameter_phases, "setting a parameter")?;
                if r == vr::SPECIMEN_DIAMETER {
                    self.vars.specimen_diameter = value;
                } else {
                    self.vars.bar_diameter = value;
                }
            }
            _ => {
                return Err(format!(
                    "{r} is not the value reference of a settable Real variable"
                ));
            }
        }
        if let Some(sim) = &mut self.sim {
            sim.set_face_speeds(self.vars.v_incident, -self.vars.v_transmitted)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    fn integer(&self, r: u32) -> Result<i32, Failure> {
        Ok(match r {
            vr::SEED => self.vars.seed,
            vr::BROKEN_PARTICLES => self.out.broken as i32,
            _ => {
                return Err(format!(
                    "{r} is not the value reference of an Integer variable"
                ));
            }
        })
    }

    fn set_integer(&mut self, r: u32, value: i32, _phase: Phase) -> Result<(), Failure> {
        match r {
            vr::SEED if value >= 0 => self.vars.seed = value,
            vr::SEED => {
                return Err(format!(
                    "parameter seed = {value} is outside the allowed range [0, inf)"
                ));
            }
            _ => {
                return Err(format!(
                    "{r} is not the value reference of a settable Integer variable"
                ));
            }
        }
        Ok(())
    }

    fn boolean(&self, r: u32) -> Result<bool, Failure> {
        if r != vr::FRACTURE {
            return Err(format!(
                "{r} is not the value reference of a Boolean variable"
            ));
        }
        Ok(self.vars.fracture)
    }

    fn set_boolean(&mut self, r: u32, value: bool, _phase: Phase) -> Result<(), Failure> {
        if r != vr::FRACTURE {
            return Err(format!(
                "{r} is not the value reference of a Boolean variable"
            ));
        }
        self.vars.fracture = value;
        Ok(())
    }

    fn string(&self, r: u32) -> Result<String, Failure> {
        if r != vr::SCENE {
            return Err(format!(
                "{r} is not the value reference of a String variable"
            ));
        }
        Ok(self.vars.scene.clone())
    }

    fn set_string(&mut self, r: u32, value: Option<String>, _phase: Phase) -> Result<(), Failure> {
        if r != vr::SCENE {
            return Err(format!(
                "{r} is not the value reference of a String variable"
            ));
        }
        self.vars.scene = value.ok_or("the scene string is a null pointer")?;
        Ok(())
    }

    fn step_bound() -> String {
        format!("{MAX_STEPS:.0e} solver steps")
    }

    fn do_step(&mut self, current: f64, h: f64) -> Result<(), StepError> {
        let sim = self.sim.as_mut().ok_or_else(|| {
            StepError::Refused("no specimen: initialisation did not finish".into())
        })?;
        // The specimen's own clock starts at 0 when the experiment starts. Whole steps until
        // the specimen is at or past the communication point (within rounding); the step may
        // shorten itself on the way (fracture), so one at a time.
        let target = (current + h) - self.vars.start;
        // Refused before the first step, under the CLI's bound on a run: doStep(0, 1e300)
        // planned 2.8e307 steps and never returned. The count is at the present step; one
        // that shortens on the way (fracture) stops the step, failed, at the bound.
        let needed = (target - sim.clock.time) / sim.clock.dt;
        if needed.is_nan() || needed > MAX_STEPS {
            return Err(StepError::Refused(format!(
                "communicationStepSize = {h:e} s needs {needed:.2e} solver steps of {:.3e} s, \
                 more than the limit of {}: the allowed range is (0, {:.3e}] s",
                sim.clock.dt,
                Self::step_bound(),
                MAX_STEPS * sim.clock.dt
            )));
        }
        let first = sim.clock.step;
        let failed = |e: fractum::Error| StepError::Failed(e.to_string());
        while sim.clock.time < target - 1e-9 * sim.clock.dt {
            if (sim.clock.step - first) as f64 >= MAX_STEPS {
                return Err(StepError::Failed(format!(
                    "the solver step shortened on the way: the step stopped at t = {:e} s \
                     after the limit of {}",
                    sim.clock.time,
                    Self::step_bound()
                )));
            }
            // Only the step that reaches the point needs the outputs before it. (The step
            // never grows, so a step predicted not to reach the point does not.)
            if sim.clock.time + sim.clock.dt >= target - 1e-9 * sim.clock.dt {
                self.lo = Sample::of(sim);
            }
            let step = sim.clock.step;
            sim.advance(1).map_err(failed)?;
            if sim.clock.step == step {
                return Err(StepError::Failed(format!(
                    "the specimen stopped at t = {:e} s and cannot reach the communication point",
                    sim.clock.time
                )));
            }
        }
        let hi = Sample::of(sim);
        self.out = if hi.time - target <= 1e-9 * sim.clock.dt {
            hi
        } else {
            Sample::between(&self.lo, &hi, target)
        };
        self.vars.time = current + h;
        Ok(())
    }

    fn save(&self) -> Saved {
        Saved {
            vars: self.vars.clone(),
            sim: self.sim.as_ref().map(|s| s.save_state()),
            lo: self.lo,
            out: self.out,
        }
    }

    fn restore(&mut self, saved: &Saved, resources: &Path) -> Result<(), Failure> {
        // A built specimen takes back only its own configuration's states: another seed's
        // bytes restored under this scene (or fracture's) and took its parameters. An
        // instance not built yet takes the state's configuration with it.
        if saved.sim.is_some() && self.sim.is_some() {
            let (theirs, ours) = (saved.vars.configuration(), self.vars.configuration());
            if theirs != ours {
                return Err(format!(
                    "the FMU state is of an instance configured with {theirs}; this one has \
                     {ours}"
                ));
            }
        }
        self.sim = match (&saved.sim, &self.sim) {
            (None, _) => None,
            (Some(bytes), Some(current)) => Some(
                Simulation::restore(current.scene.clone(), bytes, 1).map_err(|e| e.to_string())?,
            ),
            // Built from the state's own configuration (scene, fracture, seed), as
            // docs/embedding.md says; the instance's parameters refused another variant's state.
            (Some(bytes), None) => {
                let theirs = Shpb {
                    vars: saved.vars.clone(),
                    ..Shpb::default()
                };
                Some(
                    Simulation::restore(theirs.scene(resources, saved.vars.seed)?, bytes, 1)
                        .map_err(|e| e.to_string())?,
                )
            }
        };
        self.vars = saved.vars.clone();
        self.lo = saved.lo;
        self.out = saved.out;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The variables of modelDescription.xml: name, value reference, type, start value.
    fn described() -> Vec<(String, u32, String, Option<String>)> {
        let xml = include_str!("../modelDescription.xml");
        xml.split("<ScalarVariable ")
            .skip(1)
            .map(|v| {
                let v = format!(" {}", v.split("</ScalarVariable>").next().unwrap());
                let attr = |a: &str| {
                    let rest = v.split(&format!(" {a}=\"")).nth(1)?;
                    Some(rest.split('"').next()?.to_string())
                };
                let kind = ["Real", "Integer", "String", "Boolean"]
                    .into_iter()
                    .find(|k| v.contains(&format!("<{k}")))
                    .unwrap();
                (
                    attr("name").unwrap(),
                    attr("valueReference").unwrap().parse().unwrap(),
                    kind.to_string(),
                    attr("start"),
                )
            })
            .collect()
    }

    #[test]
    fn model_description_matches_the_value_references_and_start_values() {
        let names = [
            ("v_incident", vr::V_INCIDENT),
            ("v_transmitted", vr::V_TRANSMITTED),
            ("stress_incident", vr::STRESS_INCIDENT),
            ("stress_transmitted", vr::STRESS_TRANSMITTED),
            ("force_incident", vr::FORCE_INCIDENT),
            ("force_transmitted", vr::FORCE_TRANSMITTED),
            ("bar_stress_incident", vr::BAR_STRESS_INCIDENT),
            ("bar_stress_transmitted", vr::BAR_STRESS_TRANSMITTED),
            ("strain", vr::STRAIN),
            ("kinetic_energy", vr::KINETIC_ENERGY),
            ("specimen_diameter", vr::SPECIMEN_DIAMETER),
            ("bar_diameter", vr::BAR_DIAMETER),
            ("broken_particles", vr::BROKEN_PARTICLES),
            ("seed", vr::SEED),
            ("scene", vr::SCENE),
            ("fracture", vr::FRACTURE),
            ("specimen_length", vr::SPECIMEN_LENGTH),
        ];
        let vars = described();
        assert_eq!(vars.len(), names.len());
        let model = Shpb::default();
        for (name, r, kind, start) in vars {
            let known = names.iter().find(|(n, _)| *n == name);
            assert_eq!(known.map(|k| k.1), Some(r), "{name}");
            // Each variable reads with its own type, and a start value is the default.
            match kind.as_str() {
                "Real" => {
                    let v = model.real(r).unwrap();
                    if let Some(s) = start {
                        assert_eq!(v, s.parse::<f64>().unwrap(), "{name}");
                    }
                }
                "Integer" => {
                    let v = model.integer(r).unwrap();
                    if let Some(s) = start {
                        assert_eq!(v, s.parse::<i32>().unwrap(), "{name}");
                    }
                }
                "String" => assert_eq!(Some(model.string(r).unwrap()), start, "{name}"),
                "Boolean" => {
                    let v = model.boolean(r).unwrap();
                    if let Some(s) = start {
                        assert_eq!(v, s.parse::<bool>().unwrap(), "{name}");
                    }
                }
                other => panic!("{name}: a {other} variable the model does not have"),
            }
        }
        assert_eq!(GUID, {
            let xml = include_str!("../modelDescription.xml");
            xml.split("guid=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
        });
    }

    #[test]
    fn parameters_are_set_only_before_running_and_outputs_never() {
        let mut m = Shpb::default();
        m.set_real(vr::SPECIMEN_DIAMETER, 0.02, Phase::Initialization)
            .unwrap();
        assert_eq!(m.real(vr::SPECIMEN_DIAMETER), Ok(0.02));
        assert_eq!(
            m.set_real(vr::BAR_DIAMETER, 0.02, Phase::Running),
            Err("setting a parameter is not allowed in the Running state of the FMU".to_string())
        );
        m.set_real(vr::V_INCIDENT, 3.0, Phase::Running).unwrap();
        assert_eq!(
            m.set_real(vr::STRESS_INCIDENT, 1.0, Phase::Initialization),
            Err("2 is not the value reference of a settable Real variable".to_string())
        );
        assert_eq!(
            m.set_real(vr::V_INCIDENT, f64::NAN, Phase::Running),
            Err("value reference 0: NaN is not a finite number".to_string())
        );
        assert!(m.set_integer(vr::SEED, -1, Phase::Instantiated).is_err());
        assert!(m.set_string(vr::SCENE, None, Phase::Instantiated).is_err());
    }

    /// A resources folder of its own holding a small granular scene, `small.toml`: 60 spheres
    /// in a box, with the shipped scene's effects.
    fn resources(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("fractum-fmu-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let scene = r#"
name = "small"
seed = 1
effects = ["contact", "damping", "friction", "fracture", "cohesion"]
[material]
young = 60e9
poisson = 0.17
density = 2650.0
friction = 0.5
restitution = 0.5
[sample]
kind = "random"
count = 60
radius_mean = 0.3e-3
radius_sd = 0.05e-3
box = [3e-3, 3e-3, 3e-3]
solid_fraction = 0.45
[fracture]
mi = 20.56
sigma_c = 592e6
reference_strength = 3e9
toughness = 1.77e6
[loading]
kind = "oedometer"
strain_rate = 200.0
end_strain = 0.05
"#;
        std::fs::write(dir.join("small.toml"), scene).unwrap();
        dir
    }

    fn small(resources: &Path, fracture: bool, seed: i32) -> Shpb {
        let mut m = Shpb::default();
        m.set_string(vr::SCENE, Some("small.toml".into()), Phase::Instantiated)
            .unwrap();
        m.set_boolean(vr::FRACTURE, fracture, Phase::Instantiated)
            .unwrap();
        m.set_integer(vr::SEED, seed, Phase::Instantiated).unwrap();
        m.build(resources).unwrap();
        m
    }

    #[test]
    fn a_fresh_instance_takes_the_configuration_of_the_state_it_restores() {
        // docs/embedding.md: an instance not built yet takes the state's configuration. It
        // built the specimen from its own scene and fracture parameters (only the seed came
        // from the state), so a state of another variant was refused.
        let res = resources("fresh");
        let mut saver = small(&res, false, 2);
        saver.do_step(0.0, 1e-7).unwrap();
        let saved = saver.save();
        let mut fresh = Shpb::default();
        fresh.restore(&saved, &res).unwrap();
        assert_eq!(fresh.string(vr::SCENE).unwrap(), "small.toml");
        assert_eq!(fresh.boolean(vr::FRACTURE), Ok(false));
        assert_eq!(fresh.integer(vr::SEED), Ok(2));
        saver.do_step(1e-7, 1e-7).unwrap();
        fresh.do_step(1e-7, 1e-7).unwrap();
        for r in 2..10 {
            assert_eq!(fresh.real(r), saver.real(r), "output {r}");
        }
        // A built instance of another configuration still refuses it.
        let mut other = small(&res, true, 2);
        let e = other.restore(&saved, &res).unwrap_err();
        assert!(e.contains("fracture = false"), "{e}");
        let _ = std::fs::remove_dir_all(&res);
    }

    #[test]
    fn a_scene_outside_resources_or_of_another_model_is_refused() {
        let res = resources("outside");
        let outside = res.with_extension("outside.toml");
        std::fs::copy(res.join("small.toml"), &outside).unwrap();
        std::os::unix::fs::symlink(&outside, res.join("link.toml")).unwrap();
        let mut m = Shpb::default();
        m.set_string(vr::SCENE, Some("link.toml".into()), Phase::Instantiated)
            .unwrap();
        let e = m.build(&res).unwrap_err();
        assert!(
            e.contains("must be a path inside the FMU's resources folder") && e.contains("link"),
            "{e}"
        );
        // A DLSM scene: the FMU runs granular scenes, and says so.
        let dlsm = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/dlsm_tensile.toml");
        std::fs::copy(dlsm, res.join("dlsm.toml")).unwrap();
        m.set_string(vr::SCENE, Some("dlsm.toml".into()), Phase::Instantiated)
            .unwrap();
        let e = m.build(&res).unwrap_err();
        assert!(
            e.contains("is a dlsm scene") && e.contains("this FMU runs granular"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&res);
        let _ = std::fs::remove_file(&outside);
    }
}
