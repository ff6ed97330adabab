//! `fractum explain` for a dlsm scene.

use std::fmt::Write;

use super::loading::DlsmLoading;
use super::pipeline::ElementPipeline;
use super::scene::{DlsmScene, Seeds};
use super::{DEFAULT_PHI, sample};
use crate::error::Result;
use crate::scene::{EffectKind, IntegratorKind, Scene};

/// `fractum explain` for a dlsm scene: what it builds, without building the sample.
pub fn explain(scene: &Scene, cfg: &DlsmScene) -> Result<String> {
    let mut s = String::new();
    let p = &cfg.sample;
    let m = &cfg.material;
    let _ = writeln!(
        s,
        "scene {} (\"{}\"), seed {}",
        scene.source.label, scene.name, scene.seed
    );
    let _ = writeln!(
        s,
        "model: dlsm, Voronoi polyhedra joined by the distinct lattice spring model: least-squares strain per element (Eq. 1-15), contact strain (Eq. 16-18), Hooke force (Eq. 20-25) with E = {:e} Pa, nu = {}, moments with K = E L0 per unit area (Eq. 28-34)",
        m.young, m.poisson
    );
    let method = p.seeds.method().as_str();
    let randomness = match p.seeds {
        Seeds::NoisyGrid { noise } => format!(", noise d = {noise}"),
        Seeds::Packing { radius_dispersion } => {
            format!(", radius dispersion {radius_dispersion}")
        }
        Seeds::Grid => String::new(),
    };
    let _ = writeln!(
        s,
        "sample: {} of about {} elements, seeds by {method}{randomness}, domain {:?}",
        p.kind().as_str(),
        p.elements,
        sample::domain(cfg)
    );
    let _ = writeln!(
        s,
        "effects, in evaluation order (after the cohesive contacts):"
    );
    let built = ElementPipeline::describe(scene, cfg);
    if built.is_empty() {
        let _ = writeln!(s, "  (none: the cohesive lattice alone)");
    }
    for (k, line) in built.iter().enumerate() {
        let _ = writeln!(s, "  {}. {line}", k + 1);
    }
    let left_out: Vec<&str> = [
        EffectKind::Fracture,
        EffectKind::Contact,
        EffectKind::Friction,
        EffectKind::Gravity,
    ]
    .iter()
    .filter(|e| !scene.has_effect(**e))
    .map(|e| e.as_str())
    .collect();
    if !left_out.is_empty() {
        let _ = writeln!(s, "not built (not in `effects`): {}", left_out.join(", "));
    }
    let loading = DlsmLoading::describe(&cfg.loading);
    let _ = writeln!(s, "loading: {loading}");
    let integrator = match scene.time.integrator {
        IntegratorKind::TchamwaWielgosz => format!(
            "Tchamwa-Wielgosz, phi = {}",
            scene.time.phi.unwrap_or(DEFAULT_PHI)
        ),
        _ => "velocity Verlet (phi = 0.5)".to_string(),
    };
    let dt = scene
        .time
        .describe_step("min sqrt(m_ij L0 / (E S)) over the contacts (Eq. 39)");
    crate::explain::write_integrator(&mut s, &integrator, &dt);
    crate::explain::write_outputs(&mut s, scene, Some("elements.pvd"), "summary.json");
    Ok(s)
}
