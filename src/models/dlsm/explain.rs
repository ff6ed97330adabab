//! `fractum explain` for a dlsm scene.

use std::fmt::Write;

use super::loading::arc_factor;
use super::scene::{DlsmScene, LoadBy, LoadingKind};
use super::{DEFAULT_PHI, JAW_RADIUS, sample};
use crate::error::Result;
use crate::scene::{EffectKind, IntegratorKind, Scene};

/// `fractum explain` for a dlsm scene: what it builds, without building the sample.
pub fn explain(scene: &Scene) -> Result<String> {
    let cfg: DlsmScene = scene.section()?;
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
    let method = p.method.map_or("noisy_grid", |x| x.as_str());
    let randomness = match method {
        "noisy_grid" => format!(", noise d = {}", p.noise.unwrap_or(sample::DEFAULT_NOISE)),
        "packing" => format!(
            ", radius dispersion {}",
            p.radius_dispersion.unwrap_or(sample::DEFAULT_DISPERSION)
        ),
        _ => String::new(),
    };
    let _ = writeln!(
        s,
        "sample: {} of about {} elements, seeds by {method}{randomness}, domain {:?}",
        p.kind.as_str(),
        p.elements.unwrap_or(0),
        sample::domain(&cfg)
    );
    let _ = writeln!(
        s,
        "effects, in evaluation order (after the cohesive contacts):"
    );
    let mut built = Vec::new();
    if scene.has_effect(EffectKind::Fracture) {
        built.push(format!(
            "fracture: a contact breaks for good when sigma_xx > {:e} Pa (Eq. 36) and becomes a frictional (mu = {}) non-cohesive polyhedron contact (GJK/EPA)",
            m.tensile_strength.unwrap_or(0.0),
            m.friction
        ));
    }
    if scene.has_effect(EffectKind::Contact) {
        built.push(format!(
            "contact: elements against the ground plane, stiffness {:e} N/m{}",
            m.contact_stiffness.unwrap_or(0.0),
            if scene.has_effect(EffectKind::Friction) {
                format!(", Coulomb friction mu = {}", m.friction)
            } else {
                ", frictionless".to_string()
            }
        ));
    }
    if scene.has_effect(EffectKind::Gravity) {
        let g = scene.gravity.acceleration;
        built.push(format!(
            "gravity: m g, g = ({}, {}, {}) m/s²",
            g[0], g[1], g[2]
        ));
    }
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
    let l = &cfg.loading;
    let loading = match l.kind {
        LoadingKind::Tension => format!(
            "tension: x- and x+ face elements pulled apart at {} 1/s to strain {}",
            l.strain_rate.unwrap_or(0.0),
            l.end_strain.unwrap_or(0.0)
        ),
        LoadingKind::FreeVibration => format!(
            "free vibration from a static {:?} field, x- clamped, for {:e} s",
            l.mode,
            l.end_time.unwrap_or(0.0)
        ),
        LoadingKind::Brazilian if l.load_by == Some(LoadBy::FlatPlatens) => format!(
            "Brazilian test between two rigid flat platens (frictional contacts), {} m/s per side to diametral strain {}, force read on the platens (Eq. 46)",
            l.speed.unwrap_or(0.0),
            l.end_strain.unwrap_or(0.0)
        ),
        LoadingKind::Brazilian if l.load_by == Some(LoadBy::CurvedJaws) => format!(
            "Brazilian test between two rigid curved jaws of radius {JAW_RADIUS} R (frictional contacts), {} m/s per side to diametral strain {}, force read on the jaws (Eq. 46, and Eq. 48 at the contact arc they make)",
            l.speed.unwrap_or(0.0),
            l.end_strain.unwrap_or(0.0)
        ),
        LoadingKind::Brazilian if l.load_by == Some(LoadBy::ArcPressure) => {
            let arc = l.arc_degrees.unwrap_or(0.0);
            format!(
                "Brazilian test, a uniform radial pressure over loading arcs of {arc} degrees (k = {:.4}, Eq. 47) set by a servo on their closure, commanded at {} m/s per side to diametral strain {}; the disc's rigid motions held",
                arc_factor(0.5 * arc.to_radians()),
                l.speed.unwrap_or(0.0),
                l.end_strain.unwrap_or(0.0)
            )
        }
        LoadingKind::Brazilian => {
            let arc = l.arc_degrees.unwrap_or(0.0);
            format!(
                "Brazilian test, the elements of a loading arc of {arc} degrees driven (k = {:.4}, Eq. 47), {} m/s per side to diametral strain {}",
                arc_factor(0.5 * arc.to_radians()),
                l.speed.unwrap_or(0.0),
                l.end_strain.unwrap_or(0.0)
            )
        }
        LoadingKind::Drop => format!(
            "drop at {:?} m/s onto a ground inclined {} degrees, for {:e} s",
            l.initial_velocity.unwrap_or([0.0; 3]),
            l.ground_angle_degrees.unwrap_or(0.0),
            l.end_time.unwrap_or(0.0)
        ),
        LoadingKind::None => format!(
            "none: nothing prescribed for {:e} s",
            l.end_time.unwrap_or(0.0)
        ),
    };
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
