//! Prescribed boundary motion.

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::probe::Series;
use crate::scene::{LoadingKind, Scene};
use crate::state::{BoxFace, Walls};

pub mod dlsm;

/// How the boundaries move during the run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Loading {
    /// Walls stay where they are for `end_time` seconds.
    None { end_time: f64 },
    /// Oedometric compression along z: the top wall (z+) moves down at `strain_rate × height0`,
    /// the other five walls are fixed, until the axial strain reaches `end_strain`.
    Oedometer {
        strain_rate: f64,
        end_strain: f64,
        /// Box height at the start of loading (m).
        height0: f64,
    },
    /// The top (z+) and bottom (z-) faces move at speeds set from outside (an embedding host,
    /// an FMU): positive speeds move a face into the sample (compression positive), as the
    /// incident and transmitted bars of a split Hopkinson pressure bar do. No end of its own.
    Faces { top: f64, bottom: f64 },
}

impl Loading {
    pub fn from_scene(scene: &Scene, walls: &Walls) -> Result<Loading> {
        let l = &scene.loading;
        Ok(match l.kind {
            LoadingKind::None => Loading::None {
                end_time: l.end_time.expect("validated"),
            },
            LoadingKind::Oedometer => {
                if !walls.is_box {
                    return Err(scene.key_error(
                        "loading.kind",
                        "= \"oedometer\" needs a sample in a box (random, simple_cubic, hcp, text or lammps_data)",
                    ));
                }
                Loading::Oedometer {
                    strain_rate: l.strain_rate.expect("validated"),
                    end_strain: l.end_strain.expect("validated"),
                    height0: walls.box_size().z,
                }
            }
            LoadingKind::Tension
            | LoadingKind::FreeVibration
            | LoadingKind::Brazilian
            | LoadingKind::Drop => {
                return Err(scene.key_error(
                    "loading.kind",
                    "is a dlsm loading, run by model.kind = \"dlsm\"",
                ));
            }
        })
    }

    /// Sets the wall velocities for the coming step.
    pub fn apply(&self, walls: &mut Walls) {
        match self {
            Loading::None { .. } => {}
            Loading::Oedometer {
                strain_rate,
                height0,
                ..
            } => {
                let top = walls.face_mut(BoxFace::ZMax);
                top.velocity = top.normal * (strain_rate * height0);
            }
            Loading::Faces { top, bottom } => {
                for (face, speed) in [(BoxFace::ZMax, top), (BoxFace::ZMin, bottom)] {
                    let wall = walls.face_mut(face);
                    wall.velocity = wall.normal * *speed;
                }
            }
        }
    }

    /// Duration of the run (s).
    pub fn end_time(&self) -> f64 {
        match self {
            Loading::None { end_time } => *end_time,
            Loading::Oedometer {
                strain_rate,
                end_strain,
                ..
            } => end_strain / strain_rate,
            Loading::Faces { .. } => f64::INFINITY,
        }
    }

    pub fn describe(&self) -> String {
        match self {
            Loading::None { end_time } => format!("none: walls fixed for {end_time:e} s"),
            Loading::Oedometer {
                strain_rate,
                end_strain,
                height0,
            } => format!(
                "oedometer: top wall (z+) moves down at {strain_rate} 1/s x {height0:e} m = {:e} m/s to axial strain {end_strain}; the other five walls are fixed",
                strain_rate * height0
            ),
            Loading::Faces { top, bottom } => format!(
                "faces driven from outside: top (z+) at {top} m/s and bottom (z-) at {bottom} m/s into the sample"
            ),
        }
    }

    /// Adds the loading's own results to the summary.
    pub fn summarize(&self, series: &Series, out: &mut serde_json::Map<String, serde_json::Value>) {
        if let Loading::Oedometer { end_strain, .. } = self {
            oedometer_summary(series, *end_strain, out);
        }
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

/// Slope of the least-squares line through `pts`.
pub fn least_squares_slope(pts: &[(f64, f64)]) -> f64 {
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_line() {
        let pts: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 3.0 * i as f64 + 1.0)).collect();
        assert!((least_squares_slope(&pts) - 3.0).abs() < 1e-12);
    }
}
