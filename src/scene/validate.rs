//! Range checks: each failure names the key, its value and the allowed range.

use super::{DtSpec, Scene};
use crate::error::Result;

/// An allowed interval, printed in the usual notation: (a, b] and so on.
#[derive(Clone, Copy)]
pub struct Range {
    lo: f64,
    lo_open: bool,
    hi: f64,
    hi_open: bool,
}

impl Range {
    pub const POSITIVE: Range = Range::open_closed(0.0, f64::INFINITY);
    pub const NON_NEGATIVE: Range = Range::closed(0.0, f64::INFINITY);

    pub const fn open(lo: f64, hi: f64) -> Range {
        Range {
            lo,
            lo_open: true,
            hi,
            hi_open: true,
        }
    }
    pub const fn open_closed(lo: f64, hi: f64) -> Range {
        Range {
            lo,
            lo_open: true,
            hi,
            hi_open: hi == f64::INFINITY,
        }
    }
    pub const fn closed(lo: f64, hi: f64) -> Range {
        Range {
            lo,
            lo_open: false,
            hi,
            hi_open: hi == f64::INFINITY,
        }
    }

    pub fn contains(&self, v: f64) -> bool {
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

/// The most bodies (grains, elements, polygons) a scene may ask for: about 1 kB each with their
/// contacts and history, 10 GB at the limit. More is refused at validation, before anything is
/// allocated (10^9 spheres used to allocate until the process aborted).
pub const MAX_BODIES: f64 = 1e7;

/// `key` asks for about `n` bodies: refused above [`MAX_BODIES`], naming the key and the count.
pub fn check_bodies(scene: &Scene, key: &str, n: f64, what: &str) -> Result<()> {
    if n <= MAX_BODIES {
        return Ok(());
    }
    Err(scene.key_error(
        key,
        format!("gives about {n:.3e} {what}, more than the 10^7 a run is built for (about 10 GB)"),
    ))
}

/// `value` of `key` must lie in `range`, else one sentence naming both.
pub fn check(scene: &Scene, key: &str, value: f64, range: Range, unit: &str) -> Result<()> {
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
            format!(
                "= {} is outside the allowed range {range}{unit}",
                number(value)
            ),
        ))
    }
}

/// `v` as a reader would write it: 1e308, not 309 digits.
fn number(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e16).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// The value of `key`, which is required `why`.
pub fn require<T: Copy>(scene: &Scene, key: &str, value: Option<T>, why: &str) -> Result<T> {
    value.ok_or_else(|| scene.key_error(key, format!("is required {why}")))
}

/// The shared keys every model reads.
pub(super) fn validate_common(s: &Scene) -> Result<()> {
    if s.name.trim().is_empty() {
        return Err(s.key_error("name", "must not be empty"));
    }
    // The name becomes the output folder out/NAME when no --out is given: a plain file name.
    let plain = s.name.len() <= 100
        && !s.name.starts_with('.')
        && s.name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
    if !plain {
        return Err(s.key_error(
            "name",
            format!(
                "= {:?} must be a plain file name of at most 100 characters: letters, digits, '_', '-' and '.', not starting with '.' (it names the output folder out/NAME)",
                s.name
            ),
        ));
    }
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
