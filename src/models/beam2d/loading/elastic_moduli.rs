//! `loading.kind = "elastic_moduli"` (Section 3.1): the layers pulled apart to the end strain,
//! then, from the initial state again, pushed together to it; Young's moduli and Poisson's
//! ratios fitted from each phase.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::super::Beam2d;
use super::super::scene::DrivenSpec;
use super::Loading;
use super::driven::{DRIVEN_COLUMNS, Driven, DrivenSeries};
use crate::probe::Series;
use crate::state::polygons::Polygons;

/// Fraction of each phase's end strain from which the moduli are fitted.
pub const MODULUS_FIT_FROM: f64 = 0.25;

/// Elongation to `end_strain`, then compression from the initial state: two phases, each
/// to the end strain. A checkpoint keeps it as the [`Driven`] it holds.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ElasticModuli {
    pub driven: Driven,
}

impl ElasticModuli {
    /// The loading as `fractum explain` states it, from the scene's `[loading]` table.
    pub fn describe(d: &DrivenSpec) -> String {
        format!(
            "elastic moduli: top and bottom layers pulled apart at strain rate {} 1/s (ramp {} s) to strain {}, then compressed from the start to -{}",
            d.strain_rate, d.ramp_time, d.end_strain, d.end_strain
        )
    }
}

impl Loading for ElasticModuli {
    fn end_time(&self) -> f64 {
        2.0 * self.driven.phase_duration()
    }

    /// Each phase to the step that ends it: twice one phase's steps.
    fn end_step(&self, dt: f64) -> u64 {
        2 * crate::run::end_step(self.driven.phase_duration(), dt)
    }

    fn prescribe(&self, t: f64, p: &mut Polygons) {
        self.driven.prescribe(t, p);
    }

    fn restarts(&self) -> bool {
        true
    }

    /// Half the run's steps, while the elongation lasts.
    fn phase_end(&self, end_step: u64) -> Option<u64> {
        (self.driven.phase == 0).then_some(end_step / 2)
    }

    /// The compression: from `time` (s), the layers driven towards each other.
    fn next_phase(&mut self, time: f64) {
        let d = &mut self.driven;
        d.phase = 1;
        d.phase_start = time;
        d.sign = -1.0;
    }

    fn columns(&self) -> &'static [&'static str] {
        &DRIVEN_COLUMNS
    }

    fn row(&self, model: &Beam2d, time: f64) -> Vec<f64> {
        self.driven.row(model, time)
    }

    /// Young's modulus and Poisson's ratio of each phase, fitted from [`MODULUS_FIT_FROM`]
    /// of the end strain to the end strain.
    fn summarize(&self, _model: &Beam2d, series: &Series, out: &mut Map<String, Value>) {
        let Some(s) = DrivenSeries::read(series) else {
            return;
        };
        let end = self.driven.end_strain;
        let (lo, hi) = (MODULUS_FIT_FROM * end, end);
        for (name, lo, hi) in [("elongation", lo, hi), ("compression", -hi, -lo)] {
            if let (Some(k), Some(nu)) = (s.fit(&s.stress, lo, hi), s.fit(&s.lateral, lo, hi)) {
                out.insert(format!("young_{name}"), k.into());
                out.insert(format!("poisson_{name}"), (-nu).into());
            }
        }
        out.insert("modulus_strain_range".into(), serde_json::json!([lo, hi]));
    }
}
