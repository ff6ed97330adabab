//! Range checks of the `beam2d` model's keys, and which keys go with which model.

use super::validate::{Range, check, require};
use super::{EffectKind, IntegratorKind, LoadingKind, ModelKind, Outline, SampleKind, Scene};
use crate::beam2d::BEAM2D_EFFECTS;
use crate::error::Result;

fn is_beam2d_loading(kind: LoadingKind) -> bool {
    matches!(
        kind,
        LoadingKind::ElasticModuli
            | LoadingKind::ConfinedCompression
            | LoadingKind::Explosion
            | LoadingKind::Projectile
    )
}

/// Keys that belong to one model only: checked first, before their values.
pub(super) fn validate_model(s: &Scene) -> Result<()> {
    let model = s.model.kind.as_str();
    let beam2d = s.model.kind == ModelKind::Beam2d;
    let lattice = s.sample.kind == SampleKind::VectorizableRandomLattice;
    if beam2d != lattice {
        return Err(s.key_error(
            "sample.kind",
            format!(
                "= \"{}\" does not go with model.kind = \"{model}\"; the 2D polygons of model.kind = \"beam2d\" come from sample.kind = \"vectorizable_random_lattice\" and from nothing else",
                s.sample.kind.as_str()
            ),
        ));
    }
    if beam2d != is_beam2d_loading(s.loading.kind) {
        let allowed = match s.model.kind {
            ModelKind::Beam2d => "elastic_moduli, confined_compression, explosion, projectile",
            ModelKind::Granular => "none, oedometer, platens",
            ModelKind::Dlsm => "none, tension, free_vibration, brazilian, drop",
        };
        return Err(s.key_error(
            "loading.kind",
            format!(
                "= \"{}\" is not a loading of model.kind = \"{model}\"; allowed values: {allowed}",
                s.loading.kind.as_str()
            ),
        ));
    }
    for e in &s.effects {
        let ok = if beam2d {
            BEAM2D_EFFECTS.contains(e)
        } else {
            !matches!(e, EffectKind::Beams | EffectKind::BeamBreaking)
        };
        if !ok {
            return Err(s.key_error(
                "effects",
                format!(
                    "lists \"{}\", which model.kind = \"{model}\" does not have",
                    e.as_str()
                ),
            ));
        }
    }
    if !beam2d && s.time.integrator == IntegratorKind::Gear5 {
        return Err(s.key_error(
            "time.integrator",
            format!("= \"gear5\" is available for model.kind = \"beam2d\" only, not \"{model}\""),
        ));
    }
    Ok(())
}

/// The beam2d model's own keys (for other models, nothing).
pub(super) fn validate_keys(s: &Scene) -> Result<()> {
    if s.model.kind != ModelKind::Beam2d {
        return Ok(());
    }
    validate_beam2d_material(s)?;
    validate_beam2d_loading(s)?;
    let f = &s.fragments;
    let [lo, hi] = f.fit_range;
    check(
        s,
        "fragments.fit_range",
        lo,
        Range::POSITIVE,
        "mean polygon masses",
    )?;
    check(
        s,
        "fragments.fit_range",
        hi,
        Range::open(lo, f64::INFINITY),
        "mean polygon masses (the upper end must exceed the lower)",
    )?;
    if f.bins_per_decade == 0 {
        return Err(s.key_error(
            "fragments.bins_per_decade",
            "= 0 is outside the allowed range [1, ∞)",
        ));
    }
    Ok(())
}

fn validate_beam2d_material(s: &Scene) -> Result<()> {
    let m = &s.material;
    if s.has_effect(EffectKind::BeamBreaking) && !s.has_effect(EffectKind::Beams) {
        return Err(s.key_error(
            "effects",
            "lists \"beam_breaking\" without \"beams\"; it breaks beams, so add \"beams\"",
        ));
    }
    if s.has_effect(EffectKind::Beams) {
        let why = "for the \"beams\" effect";
        let e = require(s, "material.beam_young", m.beam_young, why)?;
        check(s, "material.beam_young", e, Range::POSITIVE, "Pa")?;
    }
    if s.has_effect(EffectKind::BeamBreaking) {
        let why = "for the \"beam_breaking\" effect";
        let t = require(
            s,
            "material.beam_strain_threshold",
            m.beam_strain_threshold,
            why,
        )?;
        check(s, "material.beam_strain_threshold", t, Range::POSITIVE, "")?;
        let t = require(
            s,
            "material.beam_bending_threshold",
            m.beam_bending_threshold,
            why,
        )?;
        check(
            s,
            "material.beam_bending_threshold",
            t,
            Range::POSITIVE,
            "rad",
        )?;
    }
    if s.has_effect(EffectKind::Damping) {
        let g = require(
            s,
            "material.normal_damping",
            m.normal_damping,
            "for the \"damping\" effect of model.kind = \"beam2d\"",
        )?;
        check(s, "material.normal_damping", g, Range::NON_NEGATIVE, "1/s")?;
    }
    if s.has_effect(EffectKind::Friction) {
        let g = require(
            s,
            "material.tangential_damping",
            m.tangential_damping,
            "for the \"friction\" effect of model.kind = \"beam2d\"",
        )?;
        check(
            s,
            "material.tangential_damping",
            g,
            Range::NON_NEGATIVE,
            "1/s",
        )?;
    }
    Ok(())
}

fn validate_beam2d_loading(s: &Scene) -> Result<()> {
    let l = &s.loading;
    let kind = l.kind.as_str();
    let why = format!("for loading.kind = \"{kind}\"");
    let outline = require(
        s,
        "sample.outline",
        s.sample.outline,
        "for sample.kind = \"vectorizable_random_lattice\"",
    )?;
    match l.kind {
        LoadingKind::ElasticModuli | LoadingKind::ConfinedCompression => {
            if outline != Outline::Rectangle {
                return Err(s.key_error(
                    "sample.outline",
                    format!("= \"{}\" cannot be loaded {why}, which drives the top and bottom of a rectangle; use \"rectangle\"", outline.as_str()),
                ));
            }
            let rate = require(s, "loading.strain_rate", l.strain_rate, &why)?;
            check(s, "loading.strain_rate", rate, Range::POSITIVE, "1/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, &why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 0.5), "")?;
            if let Some(ramp) = l.ramp_time {
                check(s, "loading.ramp_time", ramp, Range::NON_NEGATIVE, "s")?;
            }
        }
        LoadingKind::Explosion | LoadingKind::Projectile => {
            if l.kind == LoadingKind::Explosion {
                let e = require(s, "loading.energy", l.energy, &why)?;
                check(s, "loading.energy", e, Range::POSITIVE, "J")?;
            } else {
                if outline != Outline::Rectangle {
                    return Err(s.key_error(
                        "sample.outline",
                        format!(
                            "= \"{}\" has no lower middle to shoot from {why}; use \"rectangle\"",
                            outline.as_str()
                        ),
                    ));
                }
                let v = require(s, "loading.speed", l.speed, &why)?;
                check(s, "loading.speed", v, Range::POSITIVE, "m/s")?;
            }
            let end = require(
                s,
                "loading.end_time",
                l.end_time,
                &format!("{why} (the longest the run may last)"),
            )?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
            if l.quiet_steps == Some(0) {
                return Err(s.key_error(
                    "loading.quiet_steps",
                    "= 0 is outside the allowed range [1, ∞)",
                ));
            }
        }
        LoadingKind::None
        | LoadingKind::Oedometer
        | LoadingKind::Platens
        | LoadingKind::Tension
        | LoadingKind::FreeVibration
        | LoadingKind::Brazilian
        | LoadingKind::Drop => {
            unreachable!("checked by validate_model")
        }
    }
    Ok(())
}

/// The vectorizable random lattice's keys.
pub(super) fn validate_lattice(s: &Scene) -> Result<()> {
    let p = &s.sample;
    let why = "for sample.kind = \"vectorizable_random_lattice\"";
    let spacing = require(s, "sample.spacing", p.spacing, why)?;
    check(s, "sample.spacing", spacing, Range::POSITIVE, "m")?;
    let disorder = require(s, "sample.disorder", p.disorder, why)?;
    check(
        s,
        "sample.disorder",
        disorder,
        Range::closed(0.0, spacing),
        "m (0 to sample.spacing)",
    )?;
    if let Some(t) = p.thickness {
        check(s, "sample.thickness", t, Range::POSITIVE, "m")?;
    }
    let outline = require(s, "sample.outline", p.outline, why)?;
    let squares = match outline {
        Outline::Rectangle => {
            let cells = require(
                s,
                "sample.cells",
                p.cells,
                "for sample.outline = \"rectangle\"",
            )?;
            if cells.iter().any(|&c| c < 2) {
                return Err(s.key_error(
                    "sample.cells",
                    format!("= {cells:?} has an entry below 2; each of [nx, ny] must be in [2, ∞)"),
                ));
            }
            cells[0] as f64 * cells[1] as f64
        }
        Outline::Disc => {
            let d = require(
                s,
                "sample.diameter",
                p.diameter,
                "for sample.outline = \"disc\"",
            )?;
            check(
                s,
                "sample.diameter",
                d,
                Range::open(3.0 * spacing, f64::INFINITY),
                "m (more than three lattice spacings)",
            )?;
            (d / spacing).powi(2)
        }
    };
    if squares > 1e7 {
        return Err(s.key_error(
            "sample.spacing",
            format!(
                "= {spacing} m gives about {squares:.0} polygons, more than the 10^7 this model is built for"
            ),
        ));
    }
    Ok(())
}
