//! Range checks of the `dlsm` model's keys, and which samples, loadings, effects and
//! integrators go with which model.

use super::validate::{Range, check, require};
use super::{EffectKind, IntegratorKind, LoadingKind, ModelKind, SampleKind, Scene, VibrationMode};
use crate::error::Result;

fn is_voronoi(kind: SampleKind) -> bool {
    matches!(
        kind,
        SampleKind::VoronoiBox
            | SampleKind::VoronoiCylinder
            | SampleKind::VoronoiDisc
            | SampleKind::VoronoiBall
    )
}

fn is_dlsm_loading(kind: LoadingKind) -> bool {
    matches!(
        kind,
        LoadingKind::Tension
            | LoadingKind::FreeVibration
            | LoadingKind::Brazilian
            | LoadingKind::Drop
    )
}

fn loading_name(kind: LoadingKind) -> &'static str {
    kind.as_str()
}

/// The keys of a Voronoi sample.
pub(super) fn validate_sample(s: &Scene) -> Result<()> {
    let p = &s.sample;
    let why = format!("for sample.kind = \"{}\"", p.kind.as_str());
    let n = require(s, "sample.elements", p.elements, &why)?;
    if n < 8 {
        return Err(s.key_error(
            "sample.elements",
            format!("= {n} is outside the allowed range [8, ∞)"),
        ));
    }
    // Each applies to its method only and is ignored by the others, so that one scene can
    // switch methods with --set.
    if let Some(d) = p.noise {
        check(s, "sample.noise", d, Range::closed(0.0, 1.0), "")?;
    }
    if let Some(delta) = p.radius_dispersion {
        check(
            s,
            "sample.radius_dispersion",
            delta,
            Range::closed(0.15, 0.9),
            "",
        )?;
    }
    let positive = |key: &str, v: Option<f64>| -> Result<f64> {
        let v = require(s, key, v, &why)?;
        check(s, key, v, Range::POSITIVE, "m")?;
        Ok(v)
    };
    match p.kind {
        SampleKind::VoronoiBox => match (p.box_size, p.length) {
            (Some(_), Some(_)) => {
                return Err(s.key_error(
                    "sample.length",
                    "and sample.box both give the box; keep one",
                ));
            }
            (Some(bx), None) => {
                for (axis, v) in ["x", "y", "z"].iter().zip(bx) {
                    if !Range::POSITIVE.contains(v) {
                        return Err(s.key_error(
                            "sample.box",
                            format!("has {axis} edge {v}, outside the allowed range (0, ∞) m"),
                        ));
                    }
                }
            }
            (None, l) => {
                positive("sample.length", l)?;
            }
        },
        SampleKind::VoronoiCylinder => {
            positive("sample.length", p.length)?;
            positive("sample.radius", p.radius)?;
        }
        SampleKind::VoronoiDisc => {
            positive("sample.diameter", p.diameter)?;
            positive("sample.thickness", p.thickness)?;
        }
        SampleKind::VoronoiBall => {
            positive("sample.radius", p.radius)?;
        }
        _ => {}
    }
    Ok(())
}

/// The keys of the dlsm loadings.
pub(super) fn validate_loading(s: &Scene) -> Result<()> {
    let l = &s.loading;
    let why = format!("for loading.kind = \"{}\"", loading_name(l.kind));
    if let Some(t) = l.ramp_time {
        check(s, "loading.ramp_time", t, Range::NON_NEGATIVE, "s")?;
    }
    if let Some(f) = l.stop_fraction {
        check(s, "loading.stop_fraction", f, Range::closed(0.0, 0.99), "")?;
    }
    match l.kind {
        LoadingKind::Tension => {
            let rate = require(s, "loading.strain_rate", l.strain_rate, &why)?;
            check(s, "loading.strain_rate", rate, Range::POSITIVE, "1/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, &why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
        }
        LoadingKind::FreeVibration => {
            let mode = require(s, "loading.mode", l.mode, &why)?;
            match mode {
                VibrationMode::Tension => {
                    if let Some(a) = l.initial_strain {
                        check(
                            s,
                            "loading.initial_strain",
                            a,
                            Range::closed(-0.01, 0.01),
                            "",
                        )?;
                    }
                }
                VibrationMode::Torsion => {
                    if let Some(t) = l.twist {
                        check(s, "loading.twist", t, Range::closed(-1.0, 1.0), "rad/m")?;
                    }
                }
            }
            let end = require(s, "loading.end_time", l.end_time, &why)?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
        }
        LoadingKind::Brazilian => {
            let v = require(s, "loading.speed", l.speed, &why)?;
            check(s, "loading.speed", v, Range::POSITIVE, "m/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, &why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
            if let Some(a) = l.arc_degrees {
                check(
                    s,
                    "loading.arc_degrees",
                    a,
                    Range::closed(0.0, 90.0),
                    "degrees",
                )?;
            }
        }
        LoadingKind::Drop => {
            let end = require(s, "loading.end_time", l.end_time, &why)?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
            if let Some(a) = l.ground_angle_degrees {
                check(
                    s,
                    "loading.ground_angle_degrees",
                    a,
                    Range::closed(0.0, 60.0),
                    "degrees",
                )?;
            }
            if let Some(h) = l.drop_height {
                check(s, "loading.drop_height", h, Range::NON_NEGATIVE, "m")?;
            }
            if let Some(v) = l.initial_velocity {
                if v.iter().any(|c| !c.is_finite()) {
                    return Err(
                        s.key_error("loading.initial_velocity", "has a non-finite component")
                    );
                }
            }
        }
        LoadingKind::None
        | LoadingKind::Oedometer
        | LoadingKind::Platens
        | LoadingKind::ElasticModuli
        | LoadingKind::ConfinedCompression
        | LoadingKind::Explosion
        | LoadingKind::Projectile => {}
    }
    Ok(())
}

/// What goes with which model.
pub(super) fn validate_model(s: &Scene) -> Result<()> {
    let m = &s.material;
    if let Some(sf) = m.tensile_strength {
        check(s, "material.tensile_strength", sf, Range::POSITIVE, "Pa")?;
    }
    if let Some(k) = m.contact_stiffness {
        check(s, "material.contact_stiffness", k, Range::POSITIVE, "N/m")?;
    }
    let t = &s.time;
    match (t.integrator, t.phi) {
        (IntegratorKind::TchamwaWielgosz, Some(phi)) => {
            check(s, "time.phi", phi, Range::closed(0.5, 10.0), "")?;
        }
        (IntegratorKind::VelocityVerlet, Some(_)) => {
            return Err(s.key_error(
                "time.phi",
                "applies to time.integrator = \"tchamwa_wielgosz\" (velocity Verlet is φ = 0.5)",
            ));
        }
        _ => {}
    }
    let sample = s.sample.kind.as_str();
    let loading = loading_name(s.loading.kind);
    match s.model.kind {
        ModelKind::Beam2d => {
            if t.integrator == IntegratorKind::TchamwaWielgosz {
                return Err(s.key_error(
                    "time.integrator",
                    "= \"tchamwa_wielgosz\" is available to model.kind = \"dlsm\" only",
                ));
            }
        }
        ModelKind::Granular => {
            if is_voronoi(s.sample.kind) {
                return Err(s.key_error(
                    "sample.kind",
                    format!("= \"{sample}\" needs model.kind = \"dlsm\""),
                ));
            }
            if is_dlsm_loading(s.loading.kind) {
                return Err(s.key_error(
                    "loading.kind",
                    format!("= \"{loading}\" needs model.kind = \"dlsm\""),
                ));
            }
            if t.integrator == IntegratorKind::TchamwaWielgosz {
                return Err(s.key_error(
                    "time.integrator",
                    "= \"tchamwa_wielgosz\" is available to model.kind = \"dlsm\" only",
                ));
            }
        }
        ModelKind::Dlsm => {
            if !is_voronoi(s.sample.kind) {
                return Err(s.key_error(
                    "sample.kind",
                    format!(
                        "= \"{sample}\" is not a Voronoi sample; model.kind = \"dlsm\" takes voronoi_box, voronoi_cylinder, voronoi_disc or voronoi_ball"
                    ),
                ));
            }
            let needs = match s.loading.kind {
                LoadingKind::Tension => Some(SampleKind::VoronoiBox),
                LoadingKind::FreeVibration => Some(SampleKind::VoronoiCylinder),
                LoadingKind::Brazilian => Some(SampleKind::VoronoiDisc),
                LoadingKind::Oedometer
                | LoadingKind::Platens
                | LoadingKind::ElasticModuli
                | LoadingKind::ConfinedCompression
                | LoadingKind::Explosion
                | LoadingKind::Projectile => {
                    return Err(s.key_error(
                        "loading.kind",
                        format!("= \"{loading}\" is not a dlsm loading; use none, tension, free_vibration, brazilian or drop"),
                    ));
                }
                LoadingKind::None | LoadingKind::Drop => None,
            };
            if let Some(k) = needs {
                if s.sample.kind != k {
                    return Err(s.key_error(
                        "loading.kind",
                        format!(
                            "= \"{loading}\" needs sample.kind = \"{}\", not \"{sample}\"",
                            k.as_str()
                        ),
                    ));
                }
            }
            for grain_effect in [EffectKind::Cohesion, EffectKind::Weibull] {
                if s.has_effect(grain_effect) {
                    return Err(s.key_error(
                        "effects",
                        format!(
                            "lists \"{}\", an effect of breaking grains (model.kind = \"granular\") that model.kind = \"dlsm\" does not have",
                            grain_effect.as_str()
                        ),
                    ));
                }
            }
            if s.has_effect(EffectKind::Damping) {
                return Err(s.key_error(
                    "effects",
                    "lists \"damping\", which model.kind = \"dlsm\" does not have (its integrator damps: time.integrator = \"tchamwa_wielgosz\" with time.phi)",
                ));
            }
            if s.has_effect(EffectKind::Fracture) {
                require(
                    s,
                    "material.tensile_strength",
                    m.tensile_strength,
                    "for the \"fracture\" effect",
                )?;
            }
            if s.has_effect(EffectKind::Contact) {
                if s.loading.kind != LoadingKind::Drop {
                    return Err(s.key_error(
                        "effects",
                        "lists \"contact\", the element–ground contact, which needs the ground of loading.kind = \"drop\"",
                    ));
                }
                require(
                    s,
                    "material.contact_stiffness",
                    m.contact_stiffness,
                    "for the \"contact\" effect of model.kind = \"dlsm\"",
                )?;
            }
        }
    }
    Ok(())
}
