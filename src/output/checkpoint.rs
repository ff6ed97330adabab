//! Checkpoints: the whole state of a run in one binary file (postcard encoding), with the
//! scene text and overrides it was built from, so `fractum resume` continues bit for bit.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::Frame;
use crate::error::{Error, Result};
use crate::run::Run;
use crate::scene::{Scene, io_reason};

const MAGIC: &[u8; 8] = b"FRACTUM\x01";
const FORMAT_VERSION: u32 = 3;

#[derive(Serialize, Deserialize)]
struct Checkpoint {
    format_version: u32,
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
        format_version: FORMAT_VERSION,
        fractum_version: env!("CARGO_PKG_VERSION").to_string(),
        model: run.model().to_string(),
        scene_text: src.text.clone(),
        scene_label: src.label.clone(),
        scene_dir: src.dir.to_string_lossy().to_string(),
        overrides: src.overrides.clone(),
        frames: frames.to_vec(),
        state: run.save_state(),
    };
    let mut bytes = MAGIC.to_vec();
    bytes.extend(postcard::to_stdvec(&ck).expect("checkpoint serialises"));
    bytes
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
    let body = bytes
        .strip_prefix(MAGIC.as_slice())
        .ok_or_else(|| Error::input(origin, "is not a Fractum checkpoint"))?;
    let ck: Checkpoint = postcard::from_bytes(body)
        .map_err(|e| Error::input(origin, format!("is a damaged checkpoint ({e})")))?;
    if ck.format_version != FORMAT_VERSION {
        return Err(Error::input(
            origin,
            format!(
                "has checkpoint format {}, this Fractum reads format {FORMAT_VERSION}",
                ck.format_version
            ),
        ));
    }
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
    let bytes = std::fs::read(path).map_err(|e| {
        Error::input(
            &origin,
            format!("cannot read the checkpoint ({})", io_reason(&e)),
        )
    })?;
    decode(&bytes, &origin)
}
