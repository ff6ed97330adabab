//! `loading.kind = "confined_compression"` (Section 3.2): the layers pushed together with
//! their horizontal coordinates and rotations fixed; the peak stress, the strain at failure,
//! the modulus before it and which way the broken beams lay.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value, json};

use super::super::Beam2d;
use super::super::scene::DrivenSpec;
use super::Loading;
use super::driven::{DRIVEN_COLUMNS, Driven, DrivenSeries};
use crate::probe::Series;
use crate::state::polygons::Polygons;

/// Fractions of the failure strain between which the confined compression's modulus is fitted.
pub const COMPRESSION_FIT: [f64; 2] = [0.2, 0.6];

/// Compression between confined boundary layers to `end_strain`. A checkpoint keeps it as the
/// [`Driven`] it holds.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ConfinedCompression {
    pub driven: Driven,
}

impl ConfinedCompression {
    /// The loading as `fractum explain` states it, from the scene's `[loading]` table.
    pub fn describe(d: &DrivenSpec) -> String {
        format!(
            "confined compression at strain rate {} 1/s (ramp {} s) to strain -{}; layers' x and rotation fixed",
            d.strain_rate, d.ramp_time, d.end_strain
        )
    }
}

impl Loading for ConfinedCompression {
    fn end_time(&self) -> f64 {
        self.driven.phase_duration()
    }

    fn prescribe(&self, t: f64, p: &mut Polygons) {
        self.driven.prescribe(t, p);
    }

    fn columns(&self) -> &'static [&'static str] {
        &DRIVEN_COLUMNS
    }

    fn row(&self, model: &Beam2d, time: f64) -> Vec<f64> {
        self.driven.row(model, time)
    }

    /// The peak stress and when it came, the final stress, the modulus over
    /// [`COMPRESSION_FIT`] of the failure strain; the share of beams that lay across the load
    /// among all beams, among the broken ones and among those broken by the peak.
    fn summarize(&self, model: &Beam2d, series: &Series, out: &mut Map<String, Value>) {
        if let Some(s) = DrivenSeries::read(series) {
            peak(series, &s, out);
        }
        let all = &model.state.beams.rest_direction;
        let baseline =
            all.iter().filter(|d| d.y.abs() <= 0.5).count() as f64 / all.len().max(1) as f64;
        out.insert("beams_lateral_fraction".into(), baseline.into());
        out.insert(
            "broken_beams_lateral_fraction".into(),
            json!(model.broken_lateral_fraction(f64::INFINITY)),
        );
        if let Some(t) = out.get("peak_time").and_then(Value::as_f64) {
            out.insert(
                "broken_beams_lateral_fraction_at_peak".into(),
                json!(model.broken_lateral_fraction(t)),
            );
        }
    }
}

/// The peak of the compressive stress and what follows from it.
fn peak(series: &Series, s: &DrivenSeries, out: &mut Map<String, Value>) {
    let (strain, stress) = (&s.strain, &s.stress);
    let peak = (0..stress.len()).max_by(|&a, &b| (-stress[a]).total_cmp(&-stress[b]));
    let Some(k) = peak else { return };
    let failure = -strain[k];
    out.insert("peak_stress".into(), (-stress[k]).into());
    out.insert("failure_strain".into(), failure.into());
    out.insert("peak_time".into(), series.rows[k][0].into());
    if let Some(last) = stress.last() {
        out.insert("stress_final".into(), (-last).into());
    }
    // The linear part before failure: 20% to 60% of the failure strain.
    let (lo, hi) = (COMPRESSION_FIT[0] * failure, COMPRESSION_FIT[1] * failure);
    if let Some(k) = s.fit(stress, -hi, -lo) {
        out.insert("young_compression".into(), k.into());
        out.insert("modulus_strain_range".into(), serde_json::json!([lo, hi]));
    }
}
