//! Prescribed boundary motion of the granular model: walls and platens.

use serde::{Deserialize, Serialize};

use super::scene::{GranularScene, LoadingSpec};
use crate::error::Result;
use crate::probe::Series;
use crate::probe::fit::least_squares_slope;
use crate::scene::Scene;
use crate::state::{BoxFace, Walls};

/// The top (z+) and bottom (z-) faces of a box driven at speeds set from outside (an embedding
/// host, an FMU) in place of the scene's loading: positive speeds move a face into the sample
/// (compression positive), as the incident and transmitted bars of a split Hopkinson pressure
/// bar do. No end of its own.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DrivenFaces {
    pub top: f64,
    pub bottom: f64,
}

impl DrivenFaces {
    /// Sets the two faces' velocities for the coming step.
    pub fn apply(&self, walls: &mut Walls) {
        for (face, speed) in [(BoxFace::ZMax, self.top), (BoxFace::ZMin, self.bottom)] {
            let wall = walls.face_mut(face);
            wall.velocity = wall.normal * speed;
        }
    }
}

/// How the boundaries move during the run, as the scene says.
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
    /// Flat platens: the top (z+) wall moves down at `speed` (m/s) until it has travelled
    /// `end_displacement` (m); the bottom (z-) wall is fixed.
    Platens { speed: f64, end_displacement: f64 },
}

impl Loading {
    pub fn from_scene(scene: &Scene, cfg: &GranularScene, walls: &Walls) -> Result<Loading> {
        Ok(match cfg.loading {
            LoadingSpec::None { end_time } => Loading::None { end_time },
            LoadingSpec::Oedometer {
                strain_rate,
                end_strain,
            } => {
                if !walls.is_box {
                    return Err(scene.key_error(
                        "loading.kind",
                        "= \"oedometer\" needs a sample in a box (random, simple_cubic, hcp, text or lammps_data)",
                    ));
                }
                Loading::Oedometer {
                    strain_rate,
                    end_strain,
                    height0: walls.box_size().z,
                }
            }
            LoadingSpec::Platens {
                speed,
                end_displacement,
            } => {
                if !walls.is_box {
                    return Err(scene.key_error(
                        "loading.kind",
                        "= \"platens\" needs a sample in a box (single, random, lattice or file)",
                    ));
                }
                Loading::Platens {
                    speed,
                    end_displacement,
                }
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
            Loading::Platens { speed, .. } => {
                let top = walls.face_mut(BoxFace::ZMax);
                top.velocity = top.normal * *speed;
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
            Loading::Platens {
                speed,
                end_displacement,
            } => end_displacement / speed,
        }
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table (the
    /// sample, which sets the oedometer's speed, is not built to explain it).
    pub fn describe(l: &LoadingSpec) -> String {
        match *l {
            LoadingSpec::None { end_time } => format!("none: walls fixed for {end_time:e} s"),
            LoadingSpec::Oedometer {
                strain_rate,
                end_strain,
            } => format!(
                "oedometer: top wall (z+) driven down at {strain_rate} 1/s to axial strain {end_strain}; the other five walls fixed"
            ),
            LoadingSpec::Platens {
                speed,
                end_displacement,
            } => format!(
                "platens: top wall (z+) driven down at {speed} m/s for {end_displacement:e} m; the bottom fixed"
            ),
        }
    }

    /// Adds the loading's own results to the summary.
    pub fn summarize(&self, series: &Series, out: &mut serde_json::Map<String, serde_json::Value>) {
        match self {
            Loading::Oedometer { end_strain, .. } => oedometer_summary(series, *end_strain, out),
            Loading::Platens { .. } => platen_summary(series, out),
            _ => {}
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
