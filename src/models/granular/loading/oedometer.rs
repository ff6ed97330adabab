//! Oedometric compression: the top wall driven down at a strain rate, the other five fixed.

use serde::{Deserialize, Serialize};

use super::BoxLoading;
use crate::probe::Series;
use crate::probe::fit::least_squares_slope;
use crate::state::{BoxFace, Walls};

/// Oedometric compression along z: the top wall (z+) moves down at `strain_rate × height0`,
/// the other five walls are fixed, until the axial strain reaches `end_strain`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Oedometer {
    pub strain_rate: f64,
    pub end_strain: f64,
    /// Box height at the start of loading (m).
    pub height0: f64,
}

impl BoxLoading for Oedometer {
    fn apply(&self, walls: &mut Walls) {
        let top = walls.face_mut(BoxFace::ZMax);
        top.velocity = top.normal * (self.strain_rate * self.height0);
    }

    fn end_time(&self) -> f64 {
        self.end_strain / self.strain_rate
    }

    fn end_strain(&self) -> Option<f64> {
        Some(self.end_strain)
    }

    fn top_speed(&self) -> Option<f64> {
        Some(self.strain_rate * self.height0)
    }

    fn summarize(&self, series: &Series, out: &mut serde_json::Map<String, serde_json::Value>) {
        oedometer_summary(series, self.end_strain, out);
    }
}

/// Constrained modulus (secant over the run and tangent at half the end strain), the stress
/// at both ends and the lateral stress ratio K0 at the end.
fn oedometer_summary(
    series: &Series,
    end_strain: f64,
    out: &mut serde_json::Map<String, serde_json::Value>,
) {
    let (Some(eps), Some(top), Some(bottom), Some(lx), Some(ly)) = (
        series.column("axial_strain"),
        series.column("stress_driven"),
        series.column("stress_opposite"),
        series.column("stress_lateral_x"),
        series.column("stress_lateral_y"),
    ) else {
        return;
    };
    if eps.len() < 2 {
        return;
    }
    let axial: Vec<f64> = top
        .iter()
        .zip(&bottom)
        .map(|(a, b)| 0.5 * (a + b))
        .collect();
    let last = eps.len() - 1;
    let secant = (axial[last] - axial[0]) / (eps[last] - eps[0]);
    out.insert("stress_initial".into(), axial[0].into());
    out.insert("stress_final".into(), axial[last].into());
    out.insert("strain_final".into(), eps[last].into());
    out.insert("constrained_modulus_secant".into(), secant.into());
    let (a, b) = (0.4 * end_strain, 0.6 * end_strain);
    let pts: Vec<(f64, f64)> = eps
        .iter()
        .zip(&axial)
        .filter(|(e, _)| **e >= a && **e <= b)
        .map(|(e, s)| (*e, *s))
        .collect();
    if pts.len() >= 3 {
        out.insert(
            "constrained_modulus_tangent".into(),
            least_squares_slope(&pts).into(),
        );
        out.insert("tangent_strain_range".into(), serde_json::json!([a, b]));
    }
    let lateral = 0.5 * (lx[last] + ly[last]);
    out.insert("lateral_stress_final".into(), lateral.into());
    out.insert(
        "lateral_stress_ratio".into(),
        (lateral / axial[last]).into(),
    );
}
