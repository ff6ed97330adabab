//! The registry: the only place that names every model. It reads a scene's `model.kind`,
//! checks the scene against that model's own section, and builds, restores and explains its
//! runs. Adding a model means a folder beside these, its `pub mod` line and one entry in
//! `MODELS`.

pub mod beam2d;
pub mod dlsm;
pub mod granular;

use std::path::Path;

use crate::error::{Error, Result};
use crate::run::{Model, Run, Runner};
use crate::scene::{COMMON_KEYS, EffectKind, IntegratorKind, Scene, describe};

/// A run built or restored by the registry.
type Built = Result<Box<dyn Run>>;
/// Where a run being built reports its long stages.
type Progress<'a> = &'a mut (dyn FnMut(&str) + Send);

/// One row of the registry: a model's `model.kind` and what the registry does with it.
struct Entry {
    kind: &'static str,
    effects: &'static [EffectKind],
    integrators: &'static [IntegratorKind],
    shared_keys: &'static [&'static str],
    check: fn(&Scene) -> Result<()>,
    knows: fn(&toml::Table) -> bool,
    knows_value: fn(&toml::Table) -> bool,
    build: fn(Scene, usize, Progress) -> Built,
    restore: fn(Scene, &[u8], usize) -> Built,
    explain: fn(&Scene) -> Result<String>,
}

const fn entry<M: Model + 'static>() -> Entry {
    Entry {
        kind: M::KIND,
        effects: M::EFFECTS,
        integrators: M::INTEGRATORS,
        shared_keys: M::SHARED_KEYS,
        check: check::<M>,
        knows: knows::<M>,
        knows_value: knows_value::<M>,
        build: |scene, threads, progress| Ok(Box::new(Runner::<M>::new(scene, threads, progress)?)),
        restore: |scene, bytes, threads| Ok(Box::new(Runner::<M>::restore(scene, bytes, threads)?)),
        explain: |scene| M::explain(scene, &M::read(scene)?),
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

/// The other models that have what `has` asks about, as `"a" and "b"`.
fn others(kind: &str, has: impl Fn(&Entry) -> bool) -> Option<String> {
    let owners: Vec<&str> = MODELS
        .iter()
        .filter(|e| e.kind != kind && has(e))
        .map(|e| e.kind)
        .collect();
    (!owners.is_empty()).then(|| format!("model.kind = \"{}\"", owners.join("\" and \"")))
}

/// The shared keys against what model `M` has: the kinds of its sample and loading, its
/// effects, its integrators and the model-specific shared keys. What belongs to another
/// model is refused naming that model.
fn check_shared<M: Model + 'static>(scene: &Scene) -> Result<()> {
    let here = format!("model.kind = \"{}\"", M::KIND);
    for key in ["sample.kind", "loading.kind"] {
        let Some(value) = lookup(&scene.tables, key) else {
            continue; // missing: the section says so
        };
        let table = single_key(&scene.tables, key);
        if knows_value::<M>(&table) {
            continue;
        }
        if let Some(owner) = others(M::KIND, |e| (e.knows_value)(&table)) {
            let allowed = serde_path_to_error::deserialize::<_, M::Raw>(toml::Value::Table(table))
                .err()
                .and_then(|e| {
                    let m = e.inner().message().to_string();
                    m.split_once("expected ")
                        .map(|(_, tail)| tail.replace('`', ""))
                })
                .map(|a| format!("; allowed values: {}", a.trim_start_matches("one of ")))
                .unwrap_or_default();
            return Err(scene.key_error(
                key,
                format!("= {value} belongs to {owner}, not to this scene's {here}{allowed}"),
            ));
        }
    }
    for e in &scene.effects {
        if !M::EFFECTS.contains(e) {
            let owner = others(M::KIND, |m| m.effects.contains(e))
                .map(|o| format!(" (an effect of {o})"))
                .unwrap_or_default();
            let allowed: Vec<&str> = M::EFFECTS.iter().map(|e| e.as_str()).collect();
            return Err(scene.key_error(
                "effects",
                format!(
                    "lists \"{}\"{owner}, which {here} does not have; its effects: {}",
                    e.as_str(),
                    allowed.join(", ")
                ),
            ));
        }
    }
    let integrator = scene.time.integrator;
    if !M::INTEGRATORS.contains(&integrator) {
        let owner = others(M::KIND, |m| m.integrators.contains(&integrator))
            .map(|o| format!(" is available to {o} only, not to {here}"))
            .unwrap_or_default();
        let allowed: Vec<&str> = M::INTEGRATORS.iter().map(|i| i.as_str()).collect();
        return Err(scene.key_error(
            "time.integrator",
            format!(
                "= \"{}\"{owner}; allowed values: {}",
                integrator.as_str(),
                allowed.join(", ")
            ),
        ));
    }
    for (key, given) in [
        ("time.phi", scene.time.phi.is_some()),
        (
            "output.report_strains",
            scene.output.report_strains.is_some(),
        ),
    ] {
        if given && !M::SHARED_KEYS.contains(&key) {
            let owner = others(M::KIND, |m| m.shared_keys.contains(&key))
                .map(|o| format!("is a key of {o}, not of this scene's {here}"))
                .unwrap_or_else(|| format!("is not a key of {here}"));
            return Err(scene.key_error(key, owner));
        }
    }
    Ok(())
}

/// Reads the scene's own tables into the model's section and checks them. A key that the
/// model does not have is refused by name, with the model that has it when another does.
fn check<M: Model + 'static>(scene: &Scene) -> Result<()> {
    check_shared::<M>(scene)?;
    let raw: M::Raw = scene.section_or_path().map_err(|(path, message)| {
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
        let table = single_key(&scene.tables, &key);
        let text = if let Some(owner) = others(M::KIND, |e| (e.knows)(&table)) {
            text.replacen(
                &format!("unknown key `{key}`"),
                &format!(
                    "`{key}` is a key of {owner}, not of this scene's model.kind = \"{}\"",
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
    M::config(scene, &raw).map(drop)
}

/// The value at `key` (a dotted path) in `tables`.
fn lookup<'a>(tables: &'a toml::Table, key: &str) -> Option<&'a toml::Value> {
    let (parents, last) = match key.rsplit_once('.') {
        Some((p, l)) => (Some(p), l),
        None => (None, key),
    };
    let mut node = tables;
    for p in parents.into_iter().flat_map(|p| p.split('.')) {
        node = node.get(p)?.as_table()?;
    }
    node.get(last)
}

/// The table holding only `key` (a dotted path) with its value from `tables`.
fn single_key(tables: &toml::Table, key: &str) -> toml::Table {
    let mut out = lookup(tables, key)
        .cloned()
        .unwrap_or(toml::Value::Boolean(false));
    for p in key.rsplit('.') {
        let mut t = toml::Table::new();
        t.insert(p.to_string(), out);
        out = toml::Value::Table(t);
    }
    match out {
        toml::Value::Table(t) => t,
        _ => toml::Table::new(),
    }
}

/// Whether `table` (one key path) names a key of model `M`: reading it into the section
/// fails for anything but an unknown key (a missing key, a wrong type) when the key exists.
fn knows<M: Model + 'static>(table: &toml::Table) -> bool {
    match serde_path_to_error::deserialize::<_, M::Raw>(toml::Value::Table(table.clone())) {
        Ok(_) => true,
        Err(e) => !e.inner().message().starts_with("unknown field"),
    }
}

/// Whether the value in `table` (one key path) is one model `M` accepts there: reading it
/// fails for anything but an unknown key or value.
fn knows_value<M: Model + 'static>(table: &toml::Table) -> bool {
    match serde_path_to_error::deserialize::<_, M::Raw>(toml::Value::Table(table.clone())) {
        Ok(_) => true,
        Err(e) => {
            let m = e.inner().message();
            !(m.starts_with("unknown field") || m.starts_with("unknown variant"))
        }
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

/// Every model's cases of `fractum bench accuracy`, model by model.
pub fn accuracy_cases() -> Vec<crate::accuracy::Case> {
    let mut cases = granular::accuracy::cases();
    cases.extend(dlsm::accuracy::cases());
    cases.extend(beam2d::accuracy::cases());
    cases
}

/// Restores a run from the state [`Run::save_state`] wrote for this scene.
pub fn restore(scene: Scene, state: &[u8], threads: usize) -> Result<Box<dyn Run>> {
    (model_of(&scene)?.restore)(scene, state, threads)
}

/// Restores the run a checkpoint file holds, with the VTK frames it had written.
pub fn resume(path: &Path, threads: usize) -> Result<(Box<dyn Run>, Vec<crate::output::Frame>)> {
    let saved = crate::output::checkpoint::load(path)?;
    // A state that passed the seal but cannot be stepped (a NaN inside, an index past the
    // bodies) is a bad checkpoint: the user's input, named by its file.
    let run = restore(saved.scene, &saved.state, threads).map_err(|e| match e {
        Error::Run(why) => Error::input(
            path.display().to_string(),
            format!("is not a usable checkpoint: {why}"),
        ),
        other => other,
    })?;
    Ok((run, saved.frames))
}

/// `fractum explain`: what a scene will build, without building the sample.
pub fn explain(scene: &Scene) -> Result<String> {
    (model_of(scene)?.explain)(scene)
}
