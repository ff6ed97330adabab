//! `fractum explain`: what a scene will build, without building the sample.

use std::fmt::Write;

use crate::effects::Pipeline;
use crate::error::Result;
use crate::scene::{DtSpec, EffectKind, LoadingKind, ModelKind, SampleKind, Scene};

const ALL_EFFECTS: [EffectKind; 7] = [
    EffectKind::Contact,
    EffectKind::Damping,
    EffectKind::Friction,
    EffectKind::Gravity,
    EffectKind::Fracture,
    EffectKind::Cohesion,
    EffectKind::Weibull,
];

/// A human-readable account of the scene: sample, force pipeline (and what is left out),
/// loading, time step and outputs.
pub fn explain(scene: &Scene) -> Result<String> {
    if scene.model.kind == ModelKind::Beam2d {
        return crate::beam2d::explain(scene);
    }
    if scene.model.kind == ModelKind::Dlsm {
        return crate::dlsm::explain(scene);
    }
    let pipeline = Pipeline::build(scene)?;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "scene {} (\"{}\"), seed {}",
        scene.source.label, scene.name, scene.seed
    );
    let _ = writeln!(s, "model: granular, spheres with Hertz–Mindlin contacts");
    let _ = writeln!(s, "sample: {}", describe_sample(scene));
    write_pipeline(
        &mut s,
        scene,
        &pipeline.describe(),
        &ALL_EFFECTS,
        "bodies move freely",
    );
    let l = &scene.loading;
    let loading = match l.kind {
        LoadingKind::None => format!(
            "none: walls fixed for {:e} s",
            l.end_time.unwrap_or_default()
        ),
        LoadingKind::Oedometer => format!(
            "oedometer: top wall (z+) driven down at {} 1/s to axial strain {}; the other five walls fixed",
            l.strain_rate.unwrap_or_default(),
            l.end_strain.unwrap_or_default()
        ),
        LoadingKind::Platens => format!(
            "platens: top wall (z+) driven down at {} m/s for {:e} m; the bottom fixed",
            l.speed.unwrap_or_default(),
            l.end_displacement.unwrap_or_default()
        ),
        // Validation keeps beam2d loadings out of granular scenes; beam2d explains itself.
        LoadingKind::ElasticModuli
        | LoadingKind::ConfinedCompression
        | LoadingKind::Explosion
        | LoadingKind::Projectile => format!("{} (model.kind = \"beam2d\")", l.kind.as_str()),
        LoadingKind::Tension
        | LoadingKind::FreeVibration
        | LoadingKind::Brazilian
        | LoadingKind::Drop => "a dlsm loading (needs model.kind = \"dlsm\")".to_string(),
    };
    let _ = writeln!(s, "loading: {loading}");
    let dt = match scene.time.dt {
        DtSpec::Auto => format!(
            "auto = {} x the Rayleigh critical step of the smallest sphere",
            scene.time.safety
        ),
        DtSpec::Seconds(v) => format!("{v:e} s"),
    };
    let _ = writeln!(s, "integrator: velocity Verlet, dt {dt}");
    let vtk = if scene.output.vtk > 0 {
        format!("VTK snapshot every {} steps", scene.output.vtk)
    } else {
        "no VTK".to_string()
    };
    let _ = writeln!(
        s,
        "outputs: series.csv row every {} steps, {vtk}, summary.json at the end",
        scene.output.every
    );
    Ok(s)
}

/// The force pipeline's lines in evaluation order, then those of the model's effects `all`
/// that the scene leaves out.
pub(crate) fn write_pipeline(
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

fn describe_sample(scene: &Scene) -> String {
    let p = &scene.sample;
    match p.kind {
        SampleKind::Random => {
            let (mean, sd, min, max) = crate::sample::radius_bounds(scene);
            let count = match (p.count, p.solid_fraction) {
                (Some(n), _) => format!("{n} spheres"),
                (None, Some(phi)) => format!("spheres filling solid fraction {phi}"),
                _ => String::new(),
            };
            let mut s = format!(
                "random packing of {count}, radii truncated normal (mean {mean:e} m, sd {sd:e} m, in [{min:e}, {max:e}] m), box {:?} m",
                p.box_size.unwrap_or_default()
            );
            if let Some(pr) = p.pressure {
                let _ = write!(
                    s,
                    ", then servo-compacted to {pr:e} Pa (friction {})",
                    p.compaction_friction.unwrap_or(scene.material.friction)
                );
            }
            s
        }
        SampleKind::SimpleCubic | SampleKind::Hcp => format!(
            "{} lattice of {:?} spheres of radius {:e} m",
            p.kind.as_str(),
            p.layers.unwrap_or_default(),
            p.radius_mean.unwrap_or_default()
        ),
        SampleKind::Text | SampleKind::LammpsData | SampleKind::YadeText => format!(
            "{} file {}",
            p.kind.as_str(),
            p.file.as_deref().unwrap_or("")
        ),
        SampleKind::Single => format!(
            "one poly-ellipsoid grain, semi-axes [a+, a-, b+, b-, c+, c-] = {:?} m, on the bottom of a box of base {:?} m",
            p.semi_axes.unwrap_or_default(),
            p.box_size.map(|b| [b[0], b[1]]).unwrap_or_default()
        ),
        SampleKind::VectorizableRandomLattice => {
            "vectorizable random lattice (model.kind = \"beam2d\")".to_string()
        }
        SampleKind::VoronoiBox
        | SampleKind::VoronoiCylinder
        | SampleKind::VoronoiDisc
        | SampleKind::VoronoiBall => format!("{} (needs model.kind = \"dlsm\")", p.kind.as_str()),
    }
}
