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

/// The integrator line: the scheme's name and the step (`TimeSpec::describe_step`).
pub fn write_integrator(s: &mut String, integrator: &str, dt: &str) {
    let _ = writeln!(s, "integrator: {integrator}, dt {dt}");
}

/// The outputs line: a series row every `output.every` steps, the VTK snapshots (`vtk_files`
/// names what each holds, when the model writes several) every `output.vtk` steps or none, and
/// the files written at the end (`at_end`).
pub fn write_outputs(s: &mut String, scene: &Scene, vtk_files: Option<&str>, at_end: &str) {
    let vtk = match (scene.output.vtk, vtk_files) {
        (0, _) => "no VTK".to_string(),
        (every, Some(files)) => format!("VTK snapshot ({files}) every {every} steps"),
        (every, None) => format!("VTK snapshot every {every} steps"),
    };
    let _ = writeln!(
        s,
        "outputs: series.csv row every {} steps, {vtk}, {at_end} at the end",
        scene.output.every
    );
}
