//! `loading.kind = "none"`: nothing prescribed, the sample left to itself.

use serde::{Deserialize, Serialize};

use super::{Loading, RowInputs, Setting};
use crate::error::Result;
use crate::models::dlsm::scene::LoadingSpec;

/// Nothing prescribed for `end_time` seconds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Free {
    /// Duration of the run (s).
    pub end_time: f64,
}

impl Free {
    /// The loading of `loading.kind = "none"`.
    pub fn build(s: &Setting) -> Result<Self> {
        Ok(Free {
            end_time: s.spec().end_time.expect("validated"),
        })
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table.
    pub fn describe(l: &LoadingSpec) -> String {
        format!(
            "none: nothing prescribed for {:e} s",
            l.end_time.unwrap_or(0.0)
        )
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
