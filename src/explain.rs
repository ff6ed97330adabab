//! `fractum explain`: what a scene will build, without building the sample. Each model
//! explains its own scenes; the lines they share are written here.

use std::fmt::Write;

use crate::scene::{EffectKind, Scene};

/// The force pipeline's lines in evaluation order, then those of the model's effects `all`
/// that the scene leaves out.
pub fn write_pipeline(
    s: &mut String,
    scene: &Scene,
    lines: &[String],
    all: &[EffectKind],
    empty: &str,
) {
    let _ = writeln!(s, "force pipeline, in evaluation order:");
    if lines.is_empty() {
        let _ = writeln!(s, "  (empty: {empty})");
    }
    for (k, line) in lines.iter().enumerate() {
        let _ = writeln!(s, "  {}. {line}", k + 1);
    }
    let left_out: Vec<&str> = all
        .iter()
        .filter(|e| !scene.has_effect(**e))
        .map(|e| e.as_str())
        .collect();
    if !left_out.is_empty() {
        let _ = writeln!(s, "not built (not in `effects`): {}", left_out.join(", "));
    }
}
