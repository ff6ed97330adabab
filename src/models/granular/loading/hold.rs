//! The walls held where they are for a time.

use serde::{Deserialize, Serialize};

use super::BoxLoading;
use crate::state::Walls;

/// Walls stay where they are for `end_time` seconds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Hold {
    pub end_time: f64,
}

impl BoxLoading for Hold {
    fn apply(&self, _walls: &mut Walls) {}

    fn end_time(&self) -> f64 {
        self.end_time
    }

    fn holds(&self) -> bool {
        true
    }
}
