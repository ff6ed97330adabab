//! Range checks: each failure names the key, its value and the allowed range.

use super::{DtSpec, EffectKind, LoadingKind, SampleKind, Scene, dlsm};
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
    let m = &s.material;
    check(s, "material.young", m.young, Range::POSITIVE, "Pa")?;
    check(s, "material.poisson", m.poisson, Range::open(-1.0, 0.5), "")?;
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

    let l = &s.loading;
    match l.kind {
        LoadingKind::Oedometer => {
            let why = "for loading.kind = \"oedometer\"";
            let rate = require(s, "loading.strain_rate", l.strain_rate, why)?;
            check(s, "loading.strain_rate", rate, Range::POSITIVE, "1/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
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
    dlsm::validate_model(s)?;
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
        SampleKind::VoronoiBox
        | SampleKind::VoronoiCylinder
        | SampleKind::VoronoiDisc
        | SampleKind::VoronoiBall => dlsm::validate_sample(s)?,
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
    for needs_contact in [EffectKind::Damping, EffectKind::Friction] {
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
