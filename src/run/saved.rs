//! A run's saved state: its format, the scene it belongs to, and the runner's part of it.

use serde::{Deserialize, Serialize};

use crate::probe::Series;
use crate::scene::Scene;

use super::Clock;

/// What a run's saved state ([`Run::save_state`]) starts with, and its format version.
pub(super) const STATE_MAGIC: &[u8; 8] = b"FRACTUMS";
/// 2: dlsm states gained the Brazilian platens, the drop's size and the ground's total force.
/// 3: the ground contact gained its surface (plane or jaw), velocity and reach, the
/// Brazilian loading its arcs' pressure.
/// 4: the state names the scene it belongs to ([`SceneIdentity`]); grain fracture keeps the
/// seed of its keyed draws instead of a sequential stream.
/// 6: fracture constants gained the size exponent, the particle-strength reading and the
/// comminution limit; granular states keep how far comminution has gone at each report strain.
/// 7: granular states keep their whole step control (cadence, target, first step, counters,
/// a collapse) where they kept the largest `ω dt` and the shortenings, and faces driven from
/// outside beside the scene's loading instead of in its place.
pub(super) const STATE_VERSION: u32 = 7;

/// Which scene a saved state belongs to: a state restored under another scene took that
/// scene's parameters with its own bodies (a dlsm state of E = 1 GPa went on under a handle of
/// 20 GPa, a granular state of 58 bodies into a handle of 101, without a word).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SceneIdentity {
    /// `model.kind`, the scene's name and seed, and its effects (the FMU's fracture switch
    /// among them): what the refusal names.
    pub model: String,
    pub name: String,
    pub seed: u64,
    pub effects: Vec<String>,
    /// FNV-1a of everything that makes the run: the model, seed, effects, time and gravity
    /// keys and the model's own tables, overrides applied (not the output keys, nor comments
    /// and layout of the file).
    pub hash: u64,
}

impl SceneIdentity {
    pub fn of(scene: &Scene) -> SceneIdentity {
        let effects: Vec<String> = scene.effects.iter().map(|e| e.as_str().into()).collect();
        let tables = toml::to_string(&scene.tables).unwrap_or_default();
        let text = format!(
            "{}\n{}\n{:?}\n{:?}\n{:?}\n{tables}",
            scene.model.kind, scene.seed, effects, scene.time, scene.gravity
        );
        SceneIdentity {
            model: scene.model.kind.clone(),
            name: scene.name.clone(),
            seed: scene.seed,
            effects,
            hash: crate::output::sealed::checksum(text.as_bytes()),
        }
    }
}

impl std::fmt::Display for SceneIdentity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "a {} run of scene \"{}\" (seed {}, effects [{}], scene hash {:016x})",
            self.model,
            self.name,
            self.seed,
            self.effects.join(", "),
            self.hash
        )
    }
}

/// The runner's part of a checkpoint; the model's own bytes ride along.
#[derive(Serialize, Deserialize)]
pub(super) struct RunnerState {
    pub(super) scene: SceneIdentity,
    pub(super) clock: Clock,
    pub(super) series: Series,
    pub(super) warnings: Vec<String>,
    pub(super) last_row: Option<u64>,
    pub(super) model: Vec<u8>,
}
