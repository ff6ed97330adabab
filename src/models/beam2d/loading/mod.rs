//! The loadings of the `beam2d` model (Kun et al., Section 3): the boundary layers of a
//! rectangle driven apart or together (elastic moduli, Section 3.1; confined compression,
//! Section 3.2), an explosion at the centre (Section 3.3.1) and a projectile (Section 3.3.2).
//! One file each; what the driven ones share is in `driven.rs`, what the free ones share in
//! `fragmentation.rs`.
//!
//! Driven boundaries start from rest and accelerate uniformly to their final speed over
//! `ramp_time`, then keep it: "with this slow loading the vibrations of the solid can be
//! reduced drastically". A driven degree of freedom has zero inverse mass, so the integrators
//! leave it alone, and [`Loading::prescribe`] writes its exact position and velocity.

mod confined_compression;
mod driven;
mod elastic_moduli;
mod explosion;
mod fragmentation;
mod projectile;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

pub use confined_compression::{COMPRESSION_FIT, ConfinedCompression};
pub use driven::{DRIVEN_COLUMNS, Driven};
pub use elastic_moduli::{ElasticModuli, MODULUS_FIT_FROM};
pub use explosion::Explosion;
pub use fragmentation::FREE_COLUMNS;
pub use projectile::Projectile;

use super::Beam2d;
use super::scene::{Beam2dScene, LoadingSpec};
use crate::error::Result;
use crate::probe::Series;
use crate::sample::lattice2d::PolygonSample;
use crate::scene::Scene;
use crate::state::polygons::Polygons;

/// What a loading does in a beam2d run. The methods a loading has nothing to do in do
/// nothing.
pub trait Loading {
    /// The time (s) at which the run ends at the latest.
    fn end_time(&self) -> f64;

    /// The step at which the run ends at the latest.
    fn end_step(&self, dt: f64) -> u64 {
        crate::run::end_step(self.end_time(), dt)
    }

    /// Writes the driven degrees of freedom's positions and velocities at time `t` (s).
    fn prescribe(&self, _t: f64, _p: &mut Polygons) {}

    /// Steps without a broken beam after which the run stops.
    fn quiet_steps(&self) -> Option<u64> {
        None
    }

    /// The polygon whose beams are cut before the start.
    fn loose_polygon(&self) -> Option<usize> {
        None
    }

    /// Whether nothing acts on the sample from outside after the start, so that its total
    /// momentum stays what it was (the run watches its drift).
    fn conserves_momentum(&self) -> bool {
        false
    }

    /// Whether a later phase starts again from the initial positions and velocities (the run
    /// keeps them for it).
    fn restarts(&self) -> bool {
        false
    }

    /// The step at which the current phase ends when another follows, in a run of
    /// `end_step` steps.
    fn phase_end(&self, _end_step: u64) -> Option<u64> {
        None
    }

    /// Starts the next phase at `time` (s).
    fn next_phase(&mut self, _time: f64) {}

    /// The columns of series.csv.
    fn columns(&self) -> &'static [&'static str];

    /// One row of series.csv at `time` (s).
    fn row(&self, model: &Beam2d, time: f64) -> Vec<f64>;

    /// The loading's results for summary.json, from the run's `series` and the model.
    fn summarize(&self, _model: &Beam2d, _series: &Series, _out: &mut Map<String, Value>) {}
}

/// The loading of a beam2d run, `loading.kind` of its scene; a checkpoint keeps it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Beam2dLoading {
    ElasticModuli(ElasticModuli),
    ConfinedCompression(ConfinedCompression),
    Explosion(Explosion),
    Projectile(Projectile),
}

impl Beam2dLoading {
    /// Sets the sample up for the scene's loading: removes the explosive, gives initial
    /// velocities, fixes the driven degrees of freedom (zero inverse mass).
    pub fn prepare(
        scene: &Scene,
        cfg: &Beam2dScene,
        sample: &mut PolygonSample,
    ) -> Result<Beam2dLoading> {
        let thickness = cfg.sample.thickness;
        Ok(match cfg.loading {
            LoadingSpec::ElasticModuli(l) => Beam2dLoading::ElasticModuli(ElasticModuli {
                driven: Driven::build(scene, &l, sample, false, thickness)?,
            }),
            LoadingSpec::ConfinedCompression(l) => {
                Beam2dLoading::ConfinedCompression(ConfinedCompression {
                    driven: Driven::build(scene, &l, sample, true, thickness)?,
                })
            }
            LoadingSpec::Explosion {
                energy,
                explosive,
                end,
            } => Beam2dLoading::Explosion(Explosion::build(
                scene, cfg, sample, energy, explosive, end,
            )?),
            LoadingSpec::Projectile {
                speed,
                projectile,
                end,
            } => {
                Beam2dLoading::Projectile(Projectile::build(scene, sample, speed, projectile, end)?)
            }
        })
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table (the
    /// lattice, which sets the layers and the polygons kicked, is not built to explain it).
    pub fn describe(l: &LoadingSpec) -> String {
        match l {
            LoadingSpec::ElasticModuli(d) => ElasticModuli::describe(d),
            LoadingSpec::ConfinedCompression(d) => ConfinedCompression::describe(d),
            LoadingSpec::Explosion {
                energy,
                explosive,
                end,
            } => Explosion::describe(*energy, *explosive, end),
            LoadingSpec::Projectile {
                speed,
                projectile,
                end,
            } => Projectile::describe(*speed, *projectile, end),
        }
    }

    /// The loading, whichever it is.
    pub fn as_loading(&self) -> &dyn Loading {
        match self {
            Beam2dLoading::ElasticModuli(l) => l,
            Beam2dLoading::ConfinedCompression(l) => l,
            Beam2dLoading::Explosion(l) => l,
            Beam2dLoading::Projectile(l) => l,
        }
    }

    /// The loading, whichever it is, to change.
    pub fn as_loading_mut(&mut self) -> &mut dyn Loading {
        match self {
            Beam2dLoading::ElasticModuli(l) => l,
            Beam2dLoading::ConfinedCompression(l) => l,
            Beam2dLoading::Explosion(l) => l,
            Beam2dLoading::Projectile(l) => l,
        }
    }
}

#[cfg(test)]
mod tests;
