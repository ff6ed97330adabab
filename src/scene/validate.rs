//! Range checks: each failure names the key, its value and the allowed range.

use super::{
    DtSpec, EffectKind, GrainShape, LoadingKind, ModelKind, SampleKind, Scene, dlsm,
    validate_beam2d,
};
use crate::error::Result;

/// An allowed interval, printed in the usual notation: (a, b] and so on.
#[derive(Clone, Copy)]
pub(crate) struct Range {
    lo: f64,
    lo_open: bool,
    hi: f64,
    hi_open: bool,
}

impl Range {
    pub(crate) const POSITIVE: Range = Range::open_closed(0.0, f64::INFINITY);
    pub(crate) const NON_NEGATIVE: Range = Range::closed(0.0, f64::INFINITY);

    pub(crate) const fn open(lo: f64, hi: f64) -> Range {
        Range {
            lo,
            lo_open: true,
            hi,
            hi_open: true,
        }
    }
    pub(crate) const fn open_closed(lo: f64, hi: f64) -> Range {
        Range {
            lo,
            lo_open: true,
            hi,
            hi_open: hi == f64::INFINITY,
        }
    }
    pub(crate) const fn closed(lo: f64, hi: f64) -> Range {
        Range {
            lo,
            lo_open: false,
            hi,
            hi_open: hi == f64::INFINITY,
        }
    }

    pub(crate) fn contains(&self, v: f64) -> bool {
        let above = if self.lo_open {
            v > self.lo
        } else {
            v >= self.lo
        };
        let below = if self.hi_open {
            v < self.hi
        } else {
            v <= self.hi
        };
        v.is_finite() && above && below
    }
}

impl std::fmt::Display for Range {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let l = if self.lo_open { '(' } else { '[' };
        let r = if self.hi_open { ')' } else { ']' };
        let hi = if self.hi.is_infinite() {
            "∞".to_string()
        } else {
            self.hi.to_string()
        };
        write!(f, "{l}{}, {hi}{r}", self.lo)
    }
}

pub(super) fn check(scene: &Scene, key: &str, value: f64, range: Range, unit: &str) -> Result<()> {
    if range.contains(value) {
        Ok(())
    } else {
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        Err(scene.key_error(
            key,
            format!("= {value} is outside the allowed range {range}{unit}"),
        ))
    }
}

pub(super) fn require<T: Copy>(scene: &Scene, key: &str, value: Option<T>, why: &str) -> Result<T> {
    value.ok_or_else(|| scene.key_error(key, format!("is required {why}")))
}

pub(super) fn validate(s: &Scene) -> Result<()> {
    if s.name.trim().is_empty() {
        return Err(s.key_error("name", "must not be empty"));
    }
    validate_beam2d::validate_model(s)?;
    let m = &s.material;
    check(s, "material.young", m.young, Range::POSITIVE, "Pa")?;
    // beam2d's rigid polygons have no Poisson's ratio: there it may be left out.
    if !(m.poisson.is_nan() && s.model.kind == ModelKind::Beam2d) {
        let why = format!("for model.kind = \"{}\"", s.model.kind.as_str());
        let nu = require(
            s,
            "material.poisson",
            (!m.poisson.is_nan()).then_some(m.poisson),
            &why,
        )?;
        check(s, "material.poisson", nu, Range::open(-1.0, 0.5), "")?;
    }
    check(s, "material.density", m.density, Range::POSITIVE, "kg/m³")?;
    check(s, "material.friction", m.friction, Range::NON_NEGATIVE, "")?;
    check(
        s,
        "material.restitution",
        m.restitution,
        Range::open_closed(0.0, 1.0),
        "",
    )?;

    validate_sample(s)?;
    validate_effects(s)?;
    validate_fracture(s)?;
    validate_beam2d::validate_keys(s)?;

    let l = &s.loading;
    match l.kind {
        LoadingKind::Oedometer => {
            let why = "for loading.kind = \"oedometer\"";
            let rate = require(s, "loading.strain_rate", l.strain_rate, why)?;
            check(s, "loading.strain_rate", rate, Range::POSITIVE, "1/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
        }
        LoadingKind::Platens => {
            let why = "for loading.kind = \"platens\"";
            let speed = require(s, "loading.speed", l.speed, why)?;
            check(s, "loading.speed", speed, Range::POSITIVE, "m/s")?;
            let travel = require(s, "loading.end_displacement", l.end_displacement, why)?;
            check(s, "loading.end_displacement", travel, Range::POSITIVE, "m")?;
        }
        LoadingKind::Tension
        | LoadingKind::FreeVibration
        | LoadingKind::Brazilian
        | LoadingKind::Drop => dlsm::validate_loading(s)?,
        LoadingKind::None => {
            let end = require(
                s,
                "loading.end_time",
                l.end_time,
                "for loading.kind = \"none\"",
            )?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
        }
        // Checked with the rest of the model's keys (validate_beam2d.rs).
        LoadingKind::ElasticModuli
        | LoadingKind::ConfinedCompression
        | LoadingKind::Explosion
        | LoadingKind::Projectile => {}
    }

    check(
        s,
        "time.safety",
        s.time.safety,
        Range::open_closed(0.0, 1.0),
        "",
    )?;
    if let DtSpec::Seconds(dt) = s.time.dt {
        check(s, "time.dt", dt, Range::POSITIVE, "s")?;
    }
    if s.output.every == 0 {
        return Err(s.key_error("output.every", "= 0 is outside the allowed range [1, ∞)"));
    }
    for (i, g) in s.gravity.acceleration.iter().enumerate() {
        if !g.is_finite() {
            return Err(s.key_error(
                "gravity.acceleration",
                format!("has a non-finite component {i}"),
            ));
        }
    }
    if let Some(mu) = s.walls.friction {
        check(s, "walls.friction", mu, Range::NON_NEGATIVE, "")?;
    }
    if let Some(skin) = s.neighbor.skin {
        check(s, "neighbor.skin", skin, Range::POSITIVE, "m")?;
    }
    if let Some(strains) = &s.output.report_strains {
        for &e in strains {
            check(s, "output.report_strains", e, Range::open(0.0, 1.0), "")?;
        }
    }
    dlsm::validate_model(s)?;
    Ok(())
}

/// The `[fracture]` keys, and what the fracture effects need.
fn validate_fracture(s: &Scene) -> Result<()> {
    let f = &s.fracture;
    check(s, "fracture.mi", f.mi, Range::POSITIVE, "")?;
    check(s, "fracture.sigma_c", f.sigma_c, Range::POSITIVE, "Pa")?;
    check(
        s,
        "fracture.weibull_modulus",
        f.weibull_modulus,
        Range::POSITIVE,
        "",
    )?;
    check(
        s,
        "fracture.toughness",
        f.toughness,
        Range::POSITIVE,
        "Pa m^0.5",
    )?;
    check(
        s,
        "fracture.critical_contacts",
        f.critical_contacts as f64,
        Range::closed(3.0, 64.0),
        "",
    )?;
    check(
        s,
        "fracture.springs",
        f.springs as f64,
        Range::closed(3.0, 16.0),
        "",
    )?;
    if let Some(v) = f.reference_strength {
        check(s, "fracture.reference_strength", v, Range::POSITIVE, "Pa")?;
    }
    if let Some(v) = f.reference_radius {
        check(s, "fracture.reference_radius", v, Range::POSITIVE, "m")?;
    }
    if s.has_effect(EffectKind::Fracture) && s.model.kind == ModelKind::Granular {
        require(
            s,
            "fracture.reference_strength",
            f.reference_strength,
            "with the \"fracture\" effect (the contact tensile strength)",
        )?;
    }
    if s.has_effect(EffectKind::Weibull) {
        require(
            s,
            "fracture.reference_radius",
            f.reference_radius,
            "with the \"weibull\" effect",
        )?;
    }
    Ok(())
}

fn validate_sample(s: &Scene) -> Result<()> {
    let p = &s.sample;
    let kind = p.kind.as_str();
    let why = format!("for sample.kind = \"{kind}\"");
    match p.kind {
        SampleKind::Random => {
            let mean = require(s, "sample.radius_mean", p.radius_mean, &why)?;
            check(s, "sample.radius_mean", mean, Range::POSITIVE, "m")?;
            let sd = p.radius_sd.unwrap_or(0.0);
            check(s, "sample.radius_sd", sd, Range::NON_NEGATIVE, "m")?;
            if let Some(rmin) = p.radius_min {
                check(
                    s,
                    "sample.radius_min",
                    rmin,
                    Range::open_closed(0.0, mean),
                    "m",
                )?;
            }
            if let Some(rmax) = p.radius_max {
                check(
                    s,
                    "sample.radius_max",
                    rmax,
                    Range::closed(mean, f64::INFINITY),
                    "m",
                )?;
            }
            let bx = require(s, "sample.box", p.box_size, &why)?;
            for (axis, v) in ["x", "y", "z"].iter().zip(bx) {
                if !Range::POSITIVE.contains(v) {
                    return Err(s.key_error(
                        "sample.box",
                        format!("has {axis} edge {v}, outside the allowed range (0, ∞) m"),
                    ));
                }
            }
            if let Some(n) = p.count {
                if n == 0 {
                    return Err(
                        s.key_error("sample.count", "= 0 is outside the allowed range [1, ∞)")
                    );
                }
            }
            if let Some(phi) = p.solid_fraction {
                check(
                    s,
                    "sample.solid_fraction",
                    phi,
                    Range::open_closed(0.0, 0.65),
                    "",
                )?;
            }
            if p.count.is_none() && p.solid_fraction.is_none() {
                return Err(s.key_error(
                    "sample.count",
                    format!("or sample.solid_fraction is required {why}"),
                ));
            }
            if let Some(pr) = p.pressure {
                check(s, "sample.pressure", pr, Range::POSITIVE, "Pa")?;
            }
            if let Some(mu) = p.compaction_friction {
                check(s, "sample.compaction_friction", mu, Range::NON_NEGATIVE, "")?;
            }
        }
        SampleKind::SimpleCubic | SampleKind::Hcp => {
            let r = require(s, "sample.radius_mean", p.radius_mean, &why)?;
            check(s, "sample.radius_mean", r, Range::POSITIVE, "m")?;
            let layers = require(s, "sample.layers", p.layers, &why)?;
            if layers.contains(&0) {
                return Err(s.key_error(
                    "sample.layers",
                    "has a zero entry; each of [nx, ny, nz] must be in [1, ∞)",
                ));
            }
        }
        SampleKind::Text | SampleKind::LammpsData | SampleKind::YadeText => {
            if p.file.is_none() {
                return Err(s.key_error("sample.file", format!("is required {why}")));
            }
        }
        SampleKind::VectorizableRandomLattice => validate_beam2d::validate_lattice(s)?,
        SampleKind::VoronoiBox
        | SampleKind::VoronoiCylinder
        | SampleKind::VoronoiDisc
        | SampleKind::VoronoiBall => dlsm::validate_sample(s)?,
        SampleKind::Single => {
            let semi = require(s, "sample.semi_axes", p.semi_axes, &why)?;
            for v in semi {
                if !Range::POSITIVE.contains(v) {
                    return Err(s.key_error(
                        "sample.semi_axes",
                        format!("has {v}, outside the allowed range (0, ∞) m"),
                    ));
                }
            }
            let bx = require(s, "sample.box", p.box_size, &why)?;
            let width = 2.0 * semi.iter().copied().fold(0.0, f64::max);
            for (axis, v) in ["x", "y"].iter().zip(bx) {
                if v <= width {
                    return Err(s.key_error(
                        "sample.box",
                        format!(
                            "has {axis} edge {v} m, which must exceed the grain's largest extent {width} m"
                        ),
                    ));
                }
            }
        }
    }
    if let Some(a) = p.aspect_ratio_max {
        check(s, "sample.aspect_ratio_max", a, Range::closed(1.0, 4.0), "")?;
    }
    if p.shape == Some(GrainShape::PolyEllipsoid) && p.kind != SampleKind::Random {
        return Err(s.key_error(
            "sample.shape",
            format!(
                "= \"poly_ellipsoid\" applies to sample.kind = \"random\" only, not \"{kind}\""
            ),
        ));
    }
    Ok(())
}

fn validate_effects(s: &Scene) -> Result<()> {
    let mut seen = Vec::new();
    for e in &s.effects {
        if seen.contains(e) {
            return Err(s.key_error(
                "effects",
                format!("lists \"{}\" twice; name each effect once", e.as_str()),
            ));
        }
        seen.push(*e);
    }
    for (effect, needs) in [
        (EffectKind::Cohesion, EffectKind::Fracture),
        (EffectKind::Weibull, EffectKind::Fracture),
    ] {
        if s.has_effect(effect) && !s.has_effect(needs) {
            return Err(s.key_error(
                "effects",
                format!(
                    "lists \"{}\" without \"{}\"; it acts on breaking grains, so add \"{}\"",
                    effect.as_str(),
                    needs.as_str(),
                    needs.as_str()
                ),
            ));
        }
    }
    // dlsm's fracture breaks its lattice springs; granular fracture breaks grains at contacts.
    let granular = s.model.kind == ModelKind::Granular;
    for needs_contact in [
        EffectKind::Damping,
        EffectKind::Friction,
        EffectKind::Fracture,
    ] {
        if needs_contact == EffectKind::Fracture && !granular {
            continue;
        }
        if s.has_effect(needs_contact) && !s.has_effect(EffectKind::Contact) {
            return Err(s.key_error(
                "effects",
                format!(
                    "lists \"{}\" without \"contact\"; it acts on contacts, so add \"contact\"",
                    needs_contact.as_str()
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_display_and_contains() {
        let r = Range::open(-1.0, 0.5);
        assert_eq!(r.to_string(), "(-1, 0.5)");
        assert!(r.contains(0.3));
        assert!(!r.contains(0.5));
        assert!(!r.contains(f64::NAN));
        assert_eq!(Range::POSITIVE.to_string(), "(0, ∞)");
        assert!(!Range::POSITIVE.contains(0.0));
        assert!(Range::NON_NEGATIVE.contains(0.0));
    }
}
