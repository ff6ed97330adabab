//! Checkpoints: the whole state of a run in one binary file (postcard encoding), with the
//! scene text and overrides it was built from, so `fractum resume` continues bit for bit. The
//! file is sealed ([`super::sealed`]: magic, format version, length, checksum), so a damaged
//! or foreign file is refused with a sentence before anything in it is decoded.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::Frame;
use super::sealed::{self, Refused};
use crate::error::{Error, Result};
use crate::run::Run;
use crate::scene::{Scene, read_regular};

const MAGIC: &[u8; 8] = b"FRACTUM\x02";
/// The magic of format 3 and before (unsealed).
const OLD_MAGIC: &[u8; 8] = b"FRACTUM\x01";
/// 5: dlsm states gained the Brazilian platens, the drop's size and the ground's total force.
/// 6: the ground contact gained its surface (plane or jaw), velocity and reach, the
/// Brazilian loading its arcs' pressure.
/// 7: fracture constants gained `weibull_sigma_c`; the size distributions hold each piece's
/// equivalent diameter of its own volume beside its mass.
/// 8: the run's state names the scene it belongs to, and is refused under another; grain
/// fracture keeps the seed of its keyed draws instead of a sequential stream.
/// 9: fracture constants gained the size exponent, the particle-strength reading and the
/// comminution limit; granular states keep how far comminution has gone at each report strain.
const FORMAT_VERSION: u32 = 9;

/// The most bytes a checkpoint file may hold (64 GiB: a million poly-ellipsoids with their
/// springs and histories take about 1 GiB).
const CHECKPOINT_LIMIT: u64 = 64 << 30;

#[derive(Serialize, Deserialize)]
struct Checkpoint {
    fractum_version: String,
    model: String,
    scene_text: String,
    scene_label: String,
    scene_dir: String,
    overrides: Vec<String>,
    frames: Vec<Frame>,
    /// The model's own state ([`Run::save_state`]).
    state: Vec<u8>,
}

/// The checkpoint bytes of a run.
pub fn encode(run: &dyn Run, frames: &[Frame]) -> Vec<u8> {
    let src = &run.scene().source;
    let ck = Checkpoint {
        fractum_version: env!("CARGO_PKG_VERSION").to_string(),
        model: run.model().to_string(),
        scene_text: src.text.clone(),
        scene_label: src.label.clone(),
        scene_dir: src.dir.to_string_lossy().to_string(),
        overrides: src.overrides.clone(),
        frames: frames.to_vec(),
        state: run.save_state(),
    };
    sealed::seal(
        MAGIC,
        FORMAT_VERSION,
        &postcard::to_stdvec(&ck).expect("checkpoint serialises"),
    )
}

/// What a checkpoint holds: the scene it was built from, the model's name, the run's state
/// (for the registry's `restore`) and the VTK frames written so far.
pub struct Saved {
    pub scene: Scene,
    pub model: String,
    pub state: Vec<u8>,
    pub frames: Vec<Frame>,
}

/// Reads checkpoint bytes (`origin` names them in messages).
pub fn decode(bytes: &[u8], origin: &str) -> Result<Saved> {
    let body = sealed::open(bytes, MAGIC, FORMAT_VERSION).map_err(|why| match why {
        Refused::Foreign if bytes.starts_with(OLD_MAGIC) => Error::input(
            origin,
            format!(
                "is a checkpoint of format 3 or before, this Fractum reads format \
                 {FORMAT_VERSION}: resume it with the Fractum that wrote it"
            ),
        ),
        Refused::Foreign => Error::input(origin, "is not a Fractum checkpoint"),
        why => Error::input(origin, format!("is not a usable checkpoint: it {why}")),
    })?;
    let ck: Checkpoint = postcard::from_bytes(body)
        .map_err(|e| Error::input(origin, format!("is a damaged checkpoint ({e})")))?;
    let scene = Scene::from_toml(
        &ck.scene_text,
        &ck.scene_label,
        Path::new(&ck.scene_dir),
        &ck.overrides,
    )?;
    if scene.model.kind != ck.model {
        return Err(Error::input(
            origin,
            format!(
                "holds a {} run but its scene builds a {} one",
                ck.model, scene.model.kind
            ),
        ));
    }
    Ok(Saved {
        scene,
        model: ck.model,
        state: ck.state,
        frames: ck.frames,
    })
}

/// Reads a checkpoint file.
pub fn load(path: &Path) -> Result<Saved> {
    let origin = path.display().to_string();
    let bytes = read_regular(path, "checkpoint", CHECKPOINT_LIMIT)
        .map_err(|why| Error::input(&origin, why))?;
    decode(&bytes, &origin)
}
