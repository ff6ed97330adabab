//! `loading.kind = "tension"`: quasi-static tension of a box along x (Section 8.2.1, 8.2.3).

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::{DEFAULT_RAMP, Loading, RowInputs, Setting, load_fell, mean_of, ramp_factor};
use crate::error::Result;
use crate::models::dlsm::scene::{Grip, TensionSpec};
use crate::probe::Series;
use crate::probe::fit::least_squares_slope;
use crate::sample::voronoi::{BOX_FACES, Domain};
use crate::state::{Bodies, Forces, Vec3};

/// Quasi-static tension of a box along x (Section 8.2.1, 8.2.3): the elements with a face
/// on x− and x+ move apart along x at the speed a uniform strain rate gives their seeds
/// (`strain_rate × (x − centre)`), so that the two faces move apart at constant speed; their
/// rotations are held, their y and z motions free.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Tension {
    pub strain_rate: f64,
    pub end_strain: f64,
    pub ramp_time: f64,
    /// Box edge along x (m) and cross-section (m²).
    pub length: f64,
    pub section: f64,
    /// Elements with a face on x−, x+, y−, y+, z−, z+.
    pub faces: [Vec<u32>; 6],
    /// Undeformed x of the seeds of the x− and x+ elements, relative to the box centre.
    pub lever: [Vec<f64>; 2],
    /// Initial distance between the mean positions of opposite face sets along x, y, z.
    pub gauge: [f64; 3],
    /// The elements whose undeformed position lies in the middle 60% of the box along x:
    /// the extensometer's gauge section.
    pub middle: Vec<u32>,
    /// Force (N, tension positive) the machine applies on the x− and x+ faces.
    pub reaction: [f64; 2],
    pub stop_fraction: f64,
    pub tensile_strength: Option<f64>,
    /// Clamped grips: the driven elements' y and z are held too.
    #[serde(default)]
    pub grip: Grip,
}

impl Tension {
    /// The tension test of a `voronoi_box` sample: its six face sets, none empty.
    pub fn build(s: &Setting, l: &TensionSpec) -> Result<Self> {
        let sample = s.sample;
        let Domain::Box { lo, hi } = sample.domain else {
            return Err(s.scene.key_error(
                "loading.kind",
                "= \"tension\" needs sample.kind = \"voronoi_box\"",
            ));
        };
        let size = hi - lo;
        let faces = BOX_FACES.map(|b| sample.elements_on(b));
        for (set, name) in faces.iter().zip(["x-", "x+", "y-", "y+", "z-", "z+"]) {
            s.nonempty(set, name)?;
        }
        let gauge = [0, 1, 2].map(|a| s.mean(&faces[2 * a + 1], a) - s.mean(&faces[2 * a], a));
        let (rate, end) = (l.strain_rate, l.end_strain);
        let middle = (0..sample.bodies.len() as u32)
            .filter(|&i| {
                let x = (sample.bodies.pos[i as usize].x - lo.x) / size.x;
                (0.2..=0.8).contains(&x)
            })
            .collect();
        let centre = lo.x + 0.5 * size.x;
        let lever = [0, 1].map(|k: usize| {
            faces[k]
                .iter()
                .map(|&i| sample.bodies.pos[i as usize].x - centre)
                .collect()
        });
        Ok(Tension {
            lever,
            strain_rate: rate,
            end_strain: end,
            ramp_time: l.ramp_time.unwrap_or(DEFAULT_RAMP * end / rate),
            length: size.x,
            section: size.y * size.z,
            faces,
            gauge,
            middle,
            reaction: [0.0; 2],
            stop_fraction: s.stop(l.stop_fraction),
            tensile_strength: s.strength(),
            grip: l.grip,
        })
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table.
    pub fn describe(l: &TensionSpec) -> String {
        format!(
            "tension: x- and x+ face elements pulled apart at {} 1/s to strain {}",
            l.strain_rate, l.end_strain
        )
    }
}

impl Loading for Tension {
    fn end_time(&self) -> f64 {
        0.5 * self.ramp_time + self.end_strain / self.strain_rate
    }

    fn prescribe(&self, bodies: &mut Bodies, t: f64) {
        let rate = self.strain_rate * ramp_factor(t, self.ramp_time);
        for k in 0..2 {
            for (&i, &x) in self.faces[k].iter().zip(&self.lever[k]) {
                let v = &mut bodies.vel[i as usize];
                v.x = rate * x;
                if self.grip == Grip::Clamped {
                    v.y = 0.0;
                    v.z = 0.0;
                }
                bodies.omega[i as usize] = Vec3::zeros();
            }
        }
    }

    fn constrain(&mut self, forces: &mut Forces) {
        let mut r = [0.0; 2];
        for (k, sign) in [(0usize, 1.0), (1, -1.0)] {
            for &i in &self.faces[k] {
                let f = &mut forces.force[i as usize];
                r[k] += sign * f.x;
                f.x = 0.0;
                if self.grip == Grip::Clamped {
                    f.y = 0.0;
                    f.z = 0.0;
                }
                forces.torque[i as usize] = Vec3::zeros();
            }
        }
        self.reaction = r;
    }

    fn columns(&self) -> Vec<&'static str> {
        vec![
            "time",
            "strain",
            "stress",
            "lateral_strain_y",
            "lateral_strain_z",
            "strain_faces",
            "lateral_strain_faces",
            "kinetic_energy",
            "broken_contacts",
        ]
    }

    fn row(&mut self, r: &RowInputs) -> Vec<f64> {
        let (l, b) = (&*self, r.bodies);
        let ke = b.kinetic_energy();
        let spread = |lo: &[u32], hi: &[u32], axis: usize| {
            mean_of(hi, |i| b.pos[i][axis]) - mean_of(lo, |i| b.pos[i][axis])
        };
        let faces = spread(&l.faces[0], &l.faces[1], 0) / l.gauge[0] - 1.0;
        let ly = spread(&l.faces[2], &l.faces[3], 1) / l.gauge[1] - 1.0;
        let lz = spread(&l.faces[4], &l.faces[5], 2) / l.gauge[2] - 1.0;
        // Extensometer: the slope of each displacement component along its own axis,
        // fitted over the gauge section, away from the gripped faces.
        let slope = |axis: usize| {
            let pts: Vec<(f64, f64)> = l
                .middle
                .iter()
                .map(|&i| {
                    let i = i as usize;
                    (r.reference[i][axis], b.pos[i][axis] - r.reference[i][axis])
                })
                .collect();
            least_squares_slope(&pts)
        };
        let stress = (l.reaction[0] + l.reaction[1]) / (2.0 * l.section);
        vec![
            r.time,
            slope(0),
            stress,
            slope(1),
            slope(2),
            faces,
            0.5 * (ly + lz),
            ke,
            r.broken as f64,
        ]
    }

    fn failed(&self, series: &Series) -> bool {
        load_fell(
            series,
            "stress",
            self.stop_fraction,
            self.tensile_strength.is_some(),
        )
    }

    fn summarize(&self, series: &Series, _dt_row: f64, out: &mut Map<String, Value>) {
        let (Some(strain), Some(stress), Some(ly), Some(lz)) = (
            series.column("strain"),
            series.column("stress"),
            series.column("lateral_strain_y"),
            series.column("lateral_strain_z"),
        ) else {
            return;
        };
        if strain.len() < 3 {
            return;
        }
        let (peak, rows) = loading_branch(&strain, &stress);
        if rows.len() >= 3 {
            let pts: Vec<(f64, f64)> = rows.iter().map(|&k| (strain[k], stress[k])).collect();
            out.insert("apparent_young".into(), least_squares_slope(&pts).into());
            let lat: Vec<(f64, f64)> = rows
                .iter()
                .map(|&k| (strain[k], -0.5 * (ly[k] + lz[k])))
                .collect();
            out.insert("apparent_poisson".into(), least_squares_slope(&lat).into());
            out.insert(
                "fit_strain_range".into(),
                serde_json::json!([strain[rows[0]], strain[peak]]),
            );
        }
        out.insert("strain_final".into(), strain[strain.len() - 1].into());
        if let Some(sf) = self.tensile_strength {
            out.insert("apparent_strength".into(), stress[peak].into());
            out.insert("local_strength".into(), sf.into());
            out.insert("strength_ratio".into(), (stress[peak] / sf).into());
            out.insert("strain_at_peak".into(), strain[peak].into());
        }
    }
}

/// The rows up to the peak of `load` whose `x` is at least a fifth of its value there: the
/// loading branch without its start-up transient.
fn loading_branch(x: &[f64], load: &[f64]) -> (usize, Vec<usize>) {
    let peak = load
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(k, _)| k);
    let from = 0.2 * x[peak];
    (peak, (0..=peak).filter(|&k| x[k] >= from).collect())
}
