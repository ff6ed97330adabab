//! `loading.kind = "none"`: nothing prescribed, the sample left to itself.

use serde::{Deserialize, Serialize};

use super::{Loading, RowInputs};

/// Nothing prescribed for `end_time` seconds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Free {
    /// Duration of the run (s).
    pub end_time: f64,
}

impl Free {
    /// The loading as `fractum explain` states it, from `loading.end_time` (s).
    pub fn describe(end_time: f64) -> String {
        format!("none: nothing prescribed for {end_time:e} s")
    }
}

impl Loading for Free {
    fn end_time(&self) -> f64 {
        self.end_time
    }

    fn columns(&self) -> Vec<&'static str> {
        vec!["time", "kinetic_energy", "broken_contacts"]
    }

    fn row(&mut self, r: &RowInputs) -> Vec<f64> {
        vec![r.time, r.bodies.kinetic_energy(), r.broken as f64]
    }
}
