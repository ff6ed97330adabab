//! The scene file: what to simulate, in TOML, SI units throughout.
//!
//! `docs/scenes.md` documents every key with its unit and allowed range. Loading goes
//! text -> TOML table -> `--set` overrides -> the keys every model shares, typed here
//! ([`Scene`]: name, seed, model, effects, time, output, gravity) -> the model's own tables
//! (material, sample, loading, ...), which the model reads into its own typed section
//! ([`Scene::section`]) and checks. `Scene::load` (in `crate::models`, the registry) does
//! all of it. Every failure is one sentence naming the file and the key.

mod overrides;
mod parse;
pub mod validate;

use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

pub use overrides::apply_override;
pub use parse::describe;

/// The keys every model shares; every other top-level key is the model's own.
pub const COMMON_KEYS: [&str; 7] = [
    "name", "seed", "model", "effects", "time", "output", "gravity",
];

/// A scene: the keys every model shares, typed, and the model's own tables as given.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Name of the run, echoed in outputs.
    pub name: String,
    /// Seed of every random choice (sample generation, fracture statistics).
    pub seed: u64,
    pub model: ModelSpec,
    /// The effects that build the force pipeline; nothing else is constructed.
    pub effects: Vec<EffectKind>,
    pub time: TimeSpec,
    pub output: OutputSpec,
    pub gravity: GravitySpec,
    /// Where the scene came from (for messages and relative paths); not a key.
    pub source: SceneSource,
    /// The model's own tables (material, sample, loading, ...), overrides applied: the model
    /// reads them with [`Scene::section`].
    pub tables: toml::Table,
}

/// The shared keys, as read from the file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Common {
    pub name: String,
    #[serde(default = "default_seed")]
    pub seed: u64,
    #[serde(default)]
    pub model: ModelSpec,
    #[serde(default)]
    pub effects: Vec<EffectKind>,
    #[serde(default)]
    pub time: TimeSpec,
    #[serde(default)]
    pub output: OutputSpec,
    #[serde(default)]
    pub gravity: GravitySpec,
}

fn default_seed() -> u64 {
    1
}

/// Where a scene came from: the file label used in messages and the folder that relative
/// paths in the scene (such as `sample.file`) are resolved against.
#[derive(Debug, Clone, Default)]
pub struct SceneSource {
    pub label: String,
    pub dir: PathBuf,
    /// The keys given with `--set`, to say so in messages.
    pub overridden: Vec<String>,
    /// The scene text and the `--set` overrides as given: a checkpoint stores them to rebuild
    /// the very same scene.
    pub text: String,
    pub overrides: Vec<String>,
}

/// `[model]`: which model runs the scene.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// `granular` (the default), `dlsm` or `beam2d`; the registry (`crate::models`) knows them.
    #[serde(default = "default_model")]
    pub kind: String,
}

fn default_model() -> String {
    "granular".to_string()
}

impl Default for ModelSpec {
    fn default() -> Self {
        ModelSpec {
            kind: default_model(),
        }
    }
}

/// One entry of the scene's `effects` list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EffectKind {
    /// Hertz normal contact force between grains and with walls.
    Contact,
    /// Viscous normal (and tangential) damping mapped from `material.restitution`.
    Damping,
    /// Mindlin tangential force with contact history and the Coulomb limit.
    Friction,
    /// Body force m·g.
    Gravity,
    /// granular: particle fracture by the Hoek–Brown and contact tensile criteria, subdivision
    /// into two sub-poly-ellipsoids. dlsm: cohesive contacts break for good when σxx > σf
    /// (Eq. 36) and turn into frictional, non-cohesive polyhedron contacts.
    Fracture,
    /// Cohesive springs between the sub-particles of a split (Eq. 35–43).
    Cohesion,
    /// Weibull statistics and size effect of the grains' strength (Eq. 18).
    Weibull,
    /// beam2d: elastic beams between neighbouring polygons (Eq. 7-12).
    Beams,
    /// beam2d: beams break by Eq. 13 and never return.
    BeamBreaking,
}

impl EffectKind {
    pub fn as_str(self) -> &'static str {
        match self {
            EffectKind::Contact => "contact",
            EffectKind::Damping => "damping",
            EffectKind::Friction => "friction",
            EffectKind::Gravity => "gravity",
            EffectKind::Fracture => "fracture",
            EffectKind::Cohesion => "cohesion",
            EffectKind::Weibull => "weibull",
            EffectKind::Beams => "beams",
            EffectKind::BeamBreaking => "beam_breaking",
        }
    }
}

/// The time step: a number of seconds, or "auto" for the Rayleigh critical step × safety.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum DtSpec {
    #[default]
    Auto,
    Seconds(f64),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorKind {
    #[default]
    VelocityVerlet,
    /// beam2d: Gear's fifth-order predictor–corrector.
    Gear5,
    /// dlsm: Tchamwa–Wielgosz with `time.phi` (Eq. 37–38).
    TchamwaWielgosz,
}

impl IntegratorKind {
    pub fn as_str(self) -> &'static str {
        match self {
            IntegratorKind::VelocityVerlet => "velocity_verlet",
            IntegratorKind::Gear5 => "gear5",
            IntegratorKind::TchamwaWielgosz => "tchamwa_wielgosz",
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    #[serde(default)]
    pub dt: DtSpec,
    /// Fraction of the Rayleigh critical time step used when `dt = "auto"`, in (0, 1].
    #[serde(default = "default_safety")]
    pub safety: f64,
    #[serde(default)]
    pub integrator: IntegratorKind,
    // dlsm
    /// φ of the Tchamwa–Wielgosz scheme, ≥ 0.5 (0.5 is velocity Verlet).
    pub phi: Option<f64>,
}

fn default_safety() -> f64 {
    0.2
}

impl TimeSpec {
    /// The run's time step (s) from the model's own bound `bound` (s: the Rayleigh step, the
    /// lattice's Eq. 39, the polygons' 2/ω): `safety` × `bound` under `dt = "auto"`, the
    /// seconds given otherwise. Every model chooses its step here.
    pub fn step(&self, bound: f64) -> f64 {
        match self.dt {
            DtSpec::Auto => self.safety * bound,
            DtSpec::Seconds(s) => s,
        }
    }

    /// The key that sets the step: `time.safety` under `dt = "auto"`, `time.dt` otherwise
    /// (what a refusal of the step names).
    pub fn step_key(&self) -> &'static str {
        match self.dt {
            DtSpec::Auto => "time.safety",
            DtSpec::Seconds(_) => "time.dt",
        }
    }

    /// The step as `explain` states it: `auto = <safety> x <bound>` (the model's words for its
    /// bound) or the seconds given.
    pub fn describe_step(&self, bound: &str) -> String {
        match self.dt {
            DtSpec::Auto => format!("auto = {} x {bound}", self.safety),
            DtSpec::Seconds(v) => format!("{v:e} s"),
        }
    }
}

impl Default for TimeSpec {
    fn default() -> Self {
        TimeSpec {
            dt: DtSpec::Auto,
            safety: default_safety(),
            integrator: IntegratorKind::VelocityVerlet,
            phi: None,
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Steps between rows of series.csv, ≥ 1.
    #[serde(default = "default_every")]
    pub every: u64,
    /// Steps between VTK snapshots; 0 writes none.
    #[serde(default)]
    pub vtk: u64,
    // granular particle fracture
    /// Axial strains at which summary.json reports the stress (`stress_at_strain`) and
    /// psd.csv the size distribution (oedometer runs with `fracture`); default 0.05, 0.1,
    /// 0.2, 0.3, 0.4 (those up to `loading.end_strain`).
    pub report_strains: Option<Vec<f64>>,
}

fn default_every() -> u64 {
    100
}

impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            every: default_every(),
            vtk: 0,
            report_strains: None,
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GravitySpec {
    /// Gravitational acceleration (m/s²), used by the `gravity` effect.
    #[serde(default = "default_g")]
    pub acceleration: [f64; 3],
}

fn default_g() -> [f64; 3] {
    [0.0, 0.0, -9.81]
}

impl Default for GravitySpec {
    fn default() -> Self {
        GravitySpec {
            acceleration: default_g(),
        }
    }
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NeighborSpec {
    /// Verlet skin (m) of the neighbour list; default 0.4 × the smallest radius.
    pub skin: Option<f64>,
}

impl Scene {
    /// Reads a scene file: the shared keys, typed, and the model's tables as given. The
    /// model's own keys are checked by `Scene::load` (the registry, `crate::models`).
    pub fn read(path: &Path, overrides: &[String]) -> Result<Scene> {
        let label = path.display().to_string();
        let bytes = read_regular(path, "scene file", SCENE_FILE_LIMIT)
            .map_err(|why| Error::input(&label, why))?;
        let text = String::from_utf8(bytes)
            .map_err(|_| Error::input(&label, "is not text: a scene file is UTF-8 TOML"))?;
        let dir = path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from("."));
        Scene::read_toml(&text, &label, &dir, overrides)
    }

    /// Reads scene text (see [`Scene::read`]). `label` names it in messages; relative paths
    /// resolve against `dir`.
    pub fn read_toml(text: &str, label: &str, dir: &Path, overrides: &[String]) -> Result<Scene> {
        let source = SceneSource {
            label: label.to_string(),
            dir: dir.to_path_buf(),
            overridden: overrides
                .iter()
                .filter_map(|o| o.split_once('=').map(|(k, _)| k.trim().to_string()))
                .collect(),
            text: text.to_string(),
            overrides: overrides.to_vec(),
        };
        let (common, tables) = parse::parse(text, label, overrides)?;
        let scene = Scene {
            name: common.name,
            seed: common.seed,
            model: common.model,
            effects: common.effects,
            time: common.time,
            output: common.output,
            gravity: common.gravity,
            source,
            tables,
        };
        validate::validate_common(&scene)?;
        Ok(scene)
    }

    /// The model's own tables read into its typed section `T` (unknown keys refused, the
    /// allowed ones listed). The registry checks every scene this way when it is loaded.
    pub fn section<T: DeserializeOwned>(&self) -> Result<T> {
        self.section_or_path().map_err(|(path, message)| {
            Error::input(
                &self.source.label,
                describe(&path, &message, &self.source.overridden),
            )
        })
    }

    /// [`Scene::section`], with the failing key path and serde's message apart.
    pub fn section_or_path<T: DeserializeOwned>(&self) -> std::result::Result<T, (String, String)> {
        serde_path_to_error::deserialize(toml::Value::Table(self.tables.clone()))
            .map_err(|e| (e.path().to_string(), e.inner().message().to_string()))
    }

    /// An input error about `key` of this scene, one sentence.
    pub fn key_error(&self, key: &str, message: impl AsRef<str>) -> Error {
        let via = if self.source.overridden.iter().any(|k| k == key) {
            " (set with --set)"
        } else {
            ""
        };
        Error::input(
            &self.source.label,
            format!("{key}{via} {}", message.as_ref()),
        )
    }

    /// Resolves a path given in the scene relative to the scene file's folder.
    pub fn resolve(&self, path: &str) -> PathBuf {
        let p = Path::new(path);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.source.dir.join(p)
        }
    }

    pub fn has_effect(&self, effect: EffectKind) -> bool {
        self.effects.contains(&effect)
    }

    /// Refuses `effect` without the `contact` effect it acts on.
    pub fn requires_contact(&self, effect: EffectKind) -> Result<()> {
        if self.has_effect(effect) && !self.has_effect(EffectKind::Contact) {
            return Err(self.key_error(
                "effects",
                format!(
                    "lists \"{}\" without \"contact\"; it acts on contacts, so add \"contact\"",
                    effect.as_str()
                ),
            ));
        }
        Ok(())
    }
}

/// The bytes of the regular file at `path`, at most `limit` of them; `what` names the file
/// in the reason ("scene file"). A FIFO given as a scene or checkpoint blocked for ever and
/// `/dev/zero` was read until memory ran out: anything but a regular file is refused before
/// it is opened, and a file that holds or grows past `limit` bytes is refused.
pub(crate) fn read_regular(
    path: &Path,
    what: &str,
    limit: u64,
) -> std::result::Result<Vec<u8>, String> {
    use std::io::Read;
    let cannot = |e: std::io::Error| format!("cannot read the {what} ({})", io_reason(&e));
    let meta = std::fs::metadata(path).map_err(cannot)?;
    if !meta.is_file() {
        let kind = if meta.is_dir() {
            "a folder"
        } else {
            "not a regular file (a FIFO, socket or device)"
        };
        return Err(format!("is {kind}: a {what} must be a regular file"));
    }
    let too_big = |size: String| {
        format!(
            "holds {size} bytes, more than the {limit} bytes a {what} may hold: is this the file meant?"
        )
    };
    if meta.len() > limit {
        return Err(too_big(meta.len().to_string()));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)
        .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
        .map_err(cannot)?;
    if bytes.len() as u64 > limit {
        return Err(too_big(format!("more than {limit}")));
    }
    Ok(bytes)
}

/// The most bytes a scene file may hold (64 MiB: the largest shipped scene is a few kB).
pub const SCENE_FILE_LIMIT: u64 = 64 << 20;

/// The short reason of an I/O error, without the "(os error 2)" noise.
pub(crate) fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
        _ => e.to_string(),
    }
}

impl Serialize for DtSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            DtSpec::Auto => s.serialize_str("auto"),
            DtSpec::Seconds(v) => s.serialize_f64(*v),
        }
    }
}

impl<'de> Deserialize<'de> for DtSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = DtSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"auto\" or a time step in seconds")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<DtSpec, E> {
                if v == "auto" {
                    Ok(DtSpec::Auto)
                } else {
                    Err(E::invalid_value(serde::de::Unexpected::Str(v), &self))
                }
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<DtSpec, E> {
                Ok(DtSpec::Seconds(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<DtSpec, E> {
                Ok(DtSpec::Seconds(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<DtSpec, E> {
                Ok(DtSpec::Seconds(v as f64))
            }
        }
        d.deserialize_any(V)
    }
}
