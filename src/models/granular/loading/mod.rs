//! Prescribed boundary motion of the granular model: walls and platens.

mod hold;
mod oedometer;
mod platens;

use serde::{Deserialize, Serialize};

pub use hold::Hold;
pub use oedometer::Oedometer;
pub use platens::{Platens, force_peaks};

use super::scene::{GranularScene, LoadingSpec};
use crate::error::Result;
use crate::probe::Series;
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

/// What a loading of the box does: moves its walls, says when it ends, and what the run
/// measures and reports under it. One file each: [`Hold`], [`Oedometer`], [`Platens`].
pub trait BoxLoading {
    /// Sets the wall velocities for the coming step.
    fn apply(&self, walls: &mut Walls);
    /// Duration of the run (s).
    fn end_time(&self) -> f64;
    /// Whether the walls stay where they are (no face is driven).
    fn holds(&self) -> bool {
        false
    }
    /// Whether the series is the platens' (force and travel of the top wall) rather than the
    /// box's stresses.
    fn reads_platens(&self) -> bool {
        false
    }
    /// The axial strain the loading ends at, for a loading that has one.
    fn end_strain(&self) -> Option<f64> {
        None
    }
    /// The speed (m/s) at which the top wall (z+) moves down, for a loading that drives it.
    fn top_speed(&self) -> Option<f64> {
        None
    }
    /// Adds the loading's own results to the summary.
    fn summarize(&self, _series: &Series, _out: &mut serde_json::Map<String, serde_json::Value>) {}
}

/// How the boundaries move during the run, as the scene says: one variant per loading kind,
/// each a [`BoxLoading`] (see [`Loading::as_loading`]).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Loading {
    Hold(Hold),
    Oedometer(Oedometer),
    Platens(Platens),
}

impl Loading {
    pub fn from_scene(scene: &Scene, cfg: &GranularScene, walls: &Walls) -> Result<Loading> {
        Ok(match cfg.loading {
            LoadingSpec::None { end_time } => Loading::Hold(Hold { end_time }),
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
                Loading::Oedometer(Oedometer {
                    strain_rate,
                    end_strain,
                    height0: walls.box_size().z,
                })
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
                Loading::Platens(Platens {
                    speed,
                    end_displacement,
                })
            }
        })
    }

    /// The loading as its trait: what every caller uses.
    pub fn as_loading(&self) -> &dyn BoxLoading {
        match self {
            Loading::Hold(l) => l,
            Loading::Oedometer(l) => l,
            Loading::Platens(l) => l,
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
}
