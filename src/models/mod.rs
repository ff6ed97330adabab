//! The registry: the only place that names every model. It reads a scene's `model.kind`,
//! checks the scene against that model's own section, and builds, restores and explains its
//! runs. Adding a model means a folder beside these and one line in each table below.

pub mod beam2d;
pub mod dlsm;
pub mod granular;

use std::path::Path;

use serde::de::DeserializeOwned;

use crate::error::{Error, Result};
use crate::run::{Model, Run, Runner};
use crate::scene::{COMMON_KEYS, Scene, describe};

/// What the registry needs of a model besides [`Model`]: its typed scene section, the check
/// of its keys' values, and its explanation.
pub trait Registered: Model + 'static {
    /// The model's own tables of a scene.
    type Section: DeserializeOwned;
    /// Range checks and what goes with what, once the section has been read.
    fn validate(scene: &Scene, section: &Self::Section) -> Result<()>;
    /// `fractum explain`: what the scene builds, without building it.
    fn explain(scene: &Scene) -> Result<String>;
}

/// One row of the registry: a model's `model.kind` and what the registry does with it.
struct Entry {
    kind: &'static str,
    check: fn(&Scene) -> Result<()>,
    knows: fn(&toml::Table) -> bool,
    build: fn(Scene, usize, &mut (dyn FnMut(&str) + Send)) -> Result<Box<dyn Run>>,
    restore: fn(Scene, &[u8], usize) -> Result<Box<dyn Run>>,
    explain: fn(&Scene) -> Result<String>,
}

const fn entry<M: Registered>() -> Entry {
    Entry {
        kind: M::KIND,
        check: check::<M>,
        knows: knows::<M>,
        build: |scene, threads, progress| Ok(Box::new(Runner::<M>::new(scene, threads, progress)?)),
        restore: |scene, bytes, threads| Ok(Box::new(Runner::<M>::restore(scene, bytes, threads)?)),
        explain: M::explain,
    }
}

/// Every model, by `model.kind`.
const MODELS: [Entry; 3] = [
    entry::<granular::Granular>(),
    entry::<dlsm::Dlsm>(),
    entry::<beam2d::Beam2d>(),
];

fn model_of(scene: &Scene) -> Result<&'static Entry> {
    MODELS
        .iter()
        .find(|e| e.kind == scene.model.kind)
        .ok_or_else(|| {
            let kinds: Vec<&str> = MODELS.iter().map(|e| e.kind).collect();
            scene.key_error(
                "model.kind",
                format!(
                    "= \"{}\" is not a model; allowed values: {}",
                    scene.model.kind,
                    kinds.join(", ")
                ),
            )
        })
}

/// Reads the scene's own tables into the model's section and checks them. A key that the
/// model does not have is refused by name, with the model that has it when another does.
fn check<M: Registered>(scene: &Scene) -> Result<()> {
    let section: M::Section = scene.section_or_path().map_err(|(path, message)| {
        let text = describe(&path, &message, &scene.source.overridden);
        let Some(field) = message
            .strip_prefix("unknown field `")
            .and_then(|r| r.split('`').next())
        else {
            return Error::input(&scene.source.label, text);
        };
        let key = if path.ends_with(field) {
            path.clone()
        } else if path.is_empty() || path == "." {
            field.to_string()
        } else {
            format!("{path}.{field}")
        };
        let owners: Vec<&str> = MODELS
            .iter()
            .filter(|e| e.kind != M::KIND && (e.knows)(&single_key(&scene.tables, &key)))
            .map(|e| e.kind)
            .collect();
        let text = if !owners.is_empty() {
            text.replacen(
                &format!("unknown key `{key}`"),
                &format!(
                    "`{key}` is a key of model.kind = \"{}\", not of this scene's model.kind = \"{}\"",
                    owners.join("\" and \""),
                    M::KIND
                ),
                1,
            )
        } else if !key.contains('.') {
            format!("{text}, and the shared keys {}", COMMON_KEYS.join(", "))
        } else {
            text
        };
        Error::input(&scene.source.label, text)
    })?;
    M::validate(scene, &section)
}

/// The table holding only `key` (a dotted path) with its value from `tables`.
fn single_key(tables: &toml::Table, key: &str) -> toml::Table {
    let parts: Vec<&str> = key.split('.').collect();
    let mut value = None;
    let mut node = Some(tables);
    for (k, p) in parts.iter().enumerate() {
        let v = node.and_then(|t| t.get(*p));
        if k + 1 == parts.len() {
            value = v.cloned();
        }
        node = v.and_then(|v| v.as_table());
    }
    let mut out = value.unwrap_or(toml::Value::Boolean(false));
    for p in parts.iter().rev() {
        let mut t = toml::Table::new();
        t.insert((*p).to_string(), out);
        out = toml::Value::Table(t);
    }
    match out {
        toml::Value::Table(t) => t,
        _ => toml::Table::new(),
    }
}

/// Whether `table` (one key path) names a key of model `M`: reading it into the section
/// fails for anything but an unknown key (a missing key, a wrong type) when the key exists.
fn knows<M: Registered>(table: &toml::Table) -> bool {
    match serde_path_to_error::deserialize::<_, M::Section>(toml::Value::Table(table.clone())) {
        Ok(_) => true,
        Err(e) => !e.inner().message().starts_with("unknown field"),
    }
}

impl Scene {
    /// Reads, overrides and checks a scene file: the shared keys, then the model's own
    /// section. `overrides` are `KEY=VALUE` strings as given to `--set`.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Scene> {
        let scene = Scene::read(path, overrides)?;
        (model_of(&scene)?.check)(&scene)?;
        Ok(scene)
    }

    /// [`Scene::load`] on scene text. `label` names it in messages; relative paths resolve
    /// against `dir`.
    pub fn from_toml(text: &str, label: &str, dir: &Path, overrides: &[String]) -> Result<Scene> {
        let scene = Scene::read_toml(text, label, dir, overrides)?;
        (model_of(&scene)?.check)(&scene)?;
        Ok(scene)
    }
}

/// Builds the run a scene describes. `threads` = 0 uses every core.
pub fn build(
    scene: Scene,
    threads: usize,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<Box<dyn Run>> {
    (model_of(&scene)?.build)(scene, threads, progress)
}

/// Restores a run from the state [`Run::save_state`] wrote for this scene.
pub fn restore(scene: Scene, state: &[u8], threads: usize) -> Result<Box<dyn Run>> {
    (model_of(&scene)?.restore)(scene, state, threads)
}

/// Restores the run a checkpoint file holds, with the VTK frames it had written.
pub fn resume(path: &Path, threads: usize) -> Result<(Box<dyn Run>, Vec<crate::output::Frame>)> {
    let saved = crate::output::checkpoint::load(path)?;
    Ok((restore(saved.scene, &saved.state, threads)?, saved.frames))
}

/// `fractum explain`: what a scene will build, without building the sample.
pub fn explain(scene: &Scene) -> Result<String> {
    (model_of(scene)?.explain)(scene)
}
