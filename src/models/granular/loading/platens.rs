//! Flat platens: the top wall driven down through a displacement, the bottom fixed.

use serde::{Deserialize, Serialize};

use super::BoxLoading;
use crate::probe::Series;
use crate::state::{BoxFace, Walls};

/// Flat platens: the top (z+) wall moves down at `speed` (m/s) until it has travelled
/// `end_displacement` (m); the bottom (z-) wall is fixed.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Platens {
    pub speed: f64,
    pub end_displacement: f64,
}

impl BoxLoading for Platens {
    fn apply(&self, walls: &mut Walls) {
        let top = walls.face_mut(BoxFace::ZMax);
        top.velocity = top.normal * self.speed;
    }

    fn end_time(&self) -> f64 {
        self.end_displacement / self.speed
    }

    fn reads_platens(&self) -> bool {
        true
    }

    fn top_speed(&self) -> Option<f64> {
        Some(self.speed)
    }

    fn summarize(&self, series: &Series, out: &mut serde_json::Map<String, serde_json::Value>) {
        platen_summary(series, out);
    }
}

/// A force peak counts when the force afterwards drops below this fraction of it.
const PEAK_DROP: f64 = 0.7;

/// The force–displacement peaks between platens: `first_peak_force` and `second_peak_force`
/// (N) with their displacements (m), the first two local maxima of the top platen's force
/// each followed by a drop to below 70% of it (a crack through the grain unloads the platen);
/// and `max_force`.
fn platen_summary(series: &Series, out: &mut serde_json::Map<String, serde_json::Value>) {
    let (Some(disp), Some(force)) = (series.column("displacement"), series.column("force_top"))
    else {
        return;
    };
    let peaks = force_peaks(&force, PEAK_DROP);
    let keys = [
        ("first_peak_force", "first_peak_displacement"),
        ("second_peak_force", "second_peak_displacement"),
    ];
    for (k, (fk, dk)) in keys.iter().enumerate() {
        match peaks.get(k) {
            Some(&p) => {
                out.insert((*fk).into(), force[p].into());
                out.insert((*dk).into(), disp[p].into());
            }
            None => {
                out.insert((*fk).into(), serde_json::Value::Null);
                out.insert((*dk).into(), serde_json::Value::Null);
            }
        }
    }
    out.insert(
        "max_force".into(),
        force.iter().copied().fold(0.0, f64::max).into(),
    );
}

/// Indices of the peaks of `f`: each the largest value since the last peak's drop, followed by
/// a value below `drop` times it.
pub fn force_peaks(f: &[f64], drop: f64) -> Vec<usize> {
    let mut peaks = Vec::new();
    let mut best: Option<usize> = None;
    for (k, &v) in f.iter().enumerate() {
        match best {
            Some(b) if v < drop * f[b] => {
                peaks.push(b);
                best = None;
            }
            Some(b) if v > f[b] => best = Some(k),
            None if v > 0.0 => best = Some(k),
            _ => {}
        }
    }
    peaks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_peaks_of_a_crushing_curve() {
        // Rise, crack (drop), recompression to a higher peak, crushing.
        let f = [0.0, 5.0, 10.0, 12.0, 3.0, 6.0, 14.0, 16.0, 15.0, 2.0, 1.0];
        assert_eq!(force_peaks(&f, 0.7), vec![3, 7]);
        // A wobble that does not drop below 70% is no peak.
        assert_eq!(force_peaks(&[1.0, 2.0, 1.5, 3.0], 0.7), Vec::<usize>::new());
    }
}
