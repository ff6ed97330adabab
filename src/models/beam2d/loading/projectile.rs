//! `loading.kind = "projectile"` (Section 3.3.2): the polygon at the lower middle of the
//! block shot into it, bonded to its neighbours or with its beams cut.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::super::Beam2d;
use super::super::scene::{Projectile as Start, QuietEnd};
use super::Loading;
use super::fragmentation::{self, FREE_COLUMNS};
use crate::error::Result;
use crate::probe::Series;
use crate::sample::lattice2d::{PolygonSample, SIDE_BOTTOM};
use crate::scene::Scene;

/// One polygon at the lower middle gets `speed` into the block.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Projectile {
    pub speed: f64,
    pub quiet_steps: u64,
    pub end_time: f64,
    pub polygon: usize,
    /// Its beams cut before the start (`loading.projectile = "free"`).
    #[serde(default)]
    pub free: bool,
}

impl Projectile {
    /// Picks the polygon on the lower side nearest its middle and gives it `speed` (m/s)
    /// upwards.
    pub fn build(
        scene: &Scene,
        sample: &mut PolygonSample,
        speed: f64,
        start: Start,
        end: QuietEnd,
    ) -> Result<Projectile> {
        let p = &sample.polygons;
        let middle = 0.5 * sample.info.size[0];
        let polygon = (0..p.len())
            .filter(|&k| sample.outline[k] & SIDE_BOTTOM != 0)
            .min_by(|&a, &b| {
                (p.q[a][0] - middle)
                    .abs()
                    .total_cmp(&(p.q[b][0] - middle).abs())
            })
            .ok_or_else(|| scene.key_error("sample", "has no polygon on its lower side"))?;
        sample.polygons.v[polygon] = [0.0, speed, 0.0];
        Ok(Projectile {
            speed,
            quiet_steps: end.quiet_steps,
            end_time: end.end_time,
            polygon,
            free: start == Start::Free,
        })
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table.
    pub fn describe(speed: f64, start: Start, end: &QuietEnd) -> String {
        format!(
            "projectile: the polygon at the lower middle{} starts at {speed} m/s upwards; stops after {} steps without a break or at {:e} s",
            match start {
                Start::Bonded => "",
                Start::Free => ", its beams cut,",
            },
            end.quiet_steps,
            end.end_time
        )
    }
}

impl Loading for Projectile {
    fn end_time(&self) -> f64 {
        self.end_time
    }

    fn quiet_steps(&self) -> Option<u64> {
        Some(self.quiet_steps)
    }

    fn loose_polygon(&self) -> Option<usize> {
        self.free.then_some(self.polygon)
    }

    fn conserves_momentum(&self) -> bool {
        true
    }

    fn columns(&self) -> &'static [&'static str] {
        &FREE_COLUMNS
    }

    fn row(&self, model: &Beam2d, time: f64) -> Vec<f64> {
        fragmentation::row(model, time)
    }

    /// The fragments, their power law and what stopped the run.
    fn summarize(&self, model: &Beam2d, _series: &Series, out: &mut Map<String, Value>) {
        model.fragment_summary(out);
    }
}
