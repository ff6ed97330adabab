//! Loadings of the `dlsm` model (dlsm paper, Section 8): what each
//! prescribes on the elements, what it measures in series.csv, and the results it adds to
//! summary.json.
//!
//! A prescribed velocity component is set before each step and the force component on it
//! is zeroed after the force evaluation, so the integrator keeps the prescribed value; the
//! force removed is the reaction, the load the machine applies.

mod arc_pressure;
mod brazilian;
mod drop;
mod free;
mod free_vibration;
mod tension;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

pub use arc_pressure::{ArcPressure, hold_free_motions};
pub use brazilian::{Brazilian, JAW_RADIUS, arc_factor};
pub use drop::Drop;
pub use free::Free;
pub use free_vibration::FreeVibration;
pub use tension::Tension;

use super::sample::DlsmSample;
use super::scene::{DlsmScene, LoadingSpec};
use crate::error::Result;
use crate::probe::Series;
use crate::scene::{EffectKind, Scene};
use crate::shape::polyhedron::Polyhedron;
use crate::state::{Bodies, Forces, Vec3};

/// Default ramp of prescribed speeds, as a fraction of the loading time.
const DEFAULT_RAMP: f64 = 0.1;
/// Default `stop_fraction` with fracture.
const DEFAULT_STOP: f64 = 0.2;

/// 0 → 1 over `ramp` seconds with zero slope at both ends (1 at once without a ramp): the
/// prescribed speeds start smoothly, which keeps the elastic waves of the start small.
pub fn ramp_factor(t: f64, ramp: f64) -> f64 {
    if ramp <= 0.0 || t >= ramp {
        1.0
    } else if t <= 0.0 {
        0.0
    } else {
        0.5 * (1.0 - (std::f64::consts::PI * t / ramp).cos())
    }
}

/// How far a speed rising by [`ramp_factor`] has carried a point by time `t`, per unit speed:
/// the integral of the ramp (s).
pub fn ramp_travel(t: f64, ramp: f64) -> f64 {
    if t <= 0.0 {
        0.0
    } else if ramp <= 0.0 {
        t
    } else if t >= ramp {
        0.5 * ramp + (t - ramp)
    } else {
        0.5 * (t - ramp / std::f64::consts::PI * (std::f64::consts::PI * t / ramp).sin())
    }
}

/// Mean of `f` over a set of elements.
fn mean_of(set: &[u32], f: impl Fn(usize) -> f64) -> f64 {
    set.iter().map(|&i| f(i as usize)).sum::<f64>() / set.len().max(1) as f64
}

/// With fracture (`on`): true once the last value of `column` has fallen below `fraction` of
/// the column's peak (0: never).
fn load_fell(series: &Series, column: &str, fraction: f64, on: bool) -> bool {
    if !on || fraction <= 0.0 {
        return false;
    }
    let Some(v) = series.column(column) else {
        return false;
    };
    let peak = v.iter().copied().fold(0.0, f64::max);
    peak > 0.0 && v.last().is_some_and(|&x| x < fraction * peak)
}

/// The sample's element vertices where they are (m).
fn vertices(s: &DlsmSample) -> impl Iterator<Item = Vec3> + '_ {
    s.shapes.iter().enumerate().flat_map(move |(i, shape)| {
        let (x, r) = (s.bodies.pos[i], s.bodies.orientation[i]);
        shape.vertices.iter().map(move |v| x + r * v)
    })
}

/// The lowest and highest projection (m) of the sample's element vertices on `direction`.
fn extent_along(s: &DlsmSample, direction: &Vec3) -> (f64, f64) {
    vertices(s).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
        let h = direction.dot(&p);
        (lo.min(h), hi.max(h))
    })
}

/// What a loading is built from: the scene, its dlsm tables and the sample they built.
pub struct Setting<'a> {
    /// The scene: its effects, gravity and key errors.
    pub scene: &'a Scene,
    /// The scene's dlsm tables: material, sample and loading.
    pub cfg: &'a DlsmScene,
    /// The sample built from them.
    pub sample: &'a DlsmSample,
}

impl Setting<'_> {
    /// With `fracture`: the material's tensile strength (Pa), which the loading watches for
    /// the specimen's failure.
    pub fn strength(&self) -> Option<f64> {
        if self.scene.has_effect(EffectKind::Fracture) {
            self.cfg.material.tensile_strength
        } else {
            None
        }
    }

    /// `loading.stop_fraction` (`given`), or its default.
    pub fn stop(&self, given: Option<f64>) -> f64 {
        given.unwrap_or(DEFAULT_STOP)
    }

    /// The mean coordinate `axis` (m) of a set of elements' positions (0 for none).
    pub fn mean(&self, set: &[u32], axis: usize) -> f64 {
        set.iter()
            .map(|&i| self.sample.bodies.pos[i as usize][axis])
            .sum::<f64>()
            / set.len().max(1) as f64
    }

    /// Refuses an empty set of loaded elements, `what` naming where they should be.
    pub fn nonempty(&self, set: &[u32], what: &str) -> Result<()> {
        if set.is_empty() {
            Err(self.scene.key_error(
                "sample.elements",
                format!("gives no element on {what}; ask for more elements"),
            ))
        } else {
            Ok(())
        }
    }
}

/// What a row needs besides the bodies.
pub struct RowInputs<'a> {
    /// Time of the row (s).
    pub time: f64,
    pub bodies: &'a Bodies,
    /// Undeformed centroids.
    pub reference: &'a [Vec3],
    /// Contacts broken so far.
    pub broken: usize,
    /// Strain energy of the lattice and energy of the ground springs (J), for `drop`.
    pub strain_energy: f64,
    pub contact_energy: f64,
    pub ground_contacts: usize,
}

/// What a loading does in a run. The methods a loading has nothing to do in do nothing.
pub trait Loading {
    /// Duration of the loading (s).
    fn end_time(&self) -> f64;

    /// Sets the prescribed velocity components for a step whose middle is at `t` (s).
    fn prescribe(&self, _bodies: &mut Bodies, _t: f64) {}

    /// Adds the loads of the loading's own surfaces or pressures, the elements at time `t`
    /// (s), for a step of `dt` (s).
    fn press(
        &mut self,
        _bodies: &Bodies,
        _shapes: &[Polyhedron],
        _forces: &mut Forces,
        _t: f64,
        _dt: f64,
    ) {
    }

    /// Takes the reactions out of the forces: records them and zeroes the prescribed
    /// components.
    fn constrain(&mut self, _forces: &mut Forces) {}

    /// The columns of series.csv.
    fn columns(&self) -> Vec<&'static str>;

    /// One row of series.csv.
    fn row(&mut self, r: &RowInputs) -> Vec<f64>;

    /// With fracture: true once the load has fallen below `stop_fraction` of its peak.
    fn failed(&self, _series: &Series) -> bool {
        false
    }

    /// The loading's results for summary.json, `dt_row` (s) apart the rows of `series`.
    fn summarize(&self, _series: &Series, _dt_row: f64, _out: &mut Map<String, Value>) {}
}

/// The loading of a dlsm run, `loading.kind` of its scene; a checkpoint keeps it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum DlsmLoading {
    /// Nothing prescribed.
    Free(Free),
    Tension(Tension),
    FreeVibration(FreeVibration),
    Brazilian(Brazilian),
    Drop(Drop),
}

impl DlsmLoading {
    /// The loading of a dlsm scene on its sample.
    pub fn build(s: &Setting) -> Result<Self> {
        Ok(match &s.cfg.loading {
            LoadingSpec::Tension(l) => DlsmLoading::Tension(Tension::build(s, l)?),
            LoadingSpec::FreeVibration(l) => {
                DlsmLoading::FreeVibration(FreeVibration::build(s, l)?)
            }
            LoadingSpec::Brazilian(l) => DlsmLoading::Brazilian(Brazilian::build(s, l)?),
            LoadingSpec::Drop(l) => DlsmLoading::Drop(Drop::build(s, l)?),
            &LoadingSpec::None { end_time } => DlsmLoading::Free(Free { end_time }),
        })
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table (the
    /// sample is not built to explain it).
    pub fn describe(l: &LoadingSpec) -> String {
        match l {
            LoadingSpec::Tension(l) => Tension::describe(l),
            LoadingSpec::FreeVibration(l) => FreeVibration::describe(l),
            LoadingSpec::Brazilian(l) => Brazilian::describe(l),
            LoadingSpec::Drop(l) => Drop::describe(l),
            &LoadingSpec::None { end_time } => Free::describe(end_time),
        }
    }

    /// The loading, whichever it is.
    pub fn as_loading(&self) -> &dyn Loading {
        match self {
            DlsmLoading::Free(l) => l,
            DlsmLoading::Tension(l) => l,
            DlsmLoading::FreeVibration(l) => l,
            DlsmLoading::Brazilian(l) => l,
            DlsmLoading::Drop(l) => l,
        }
    }

    /// The loading, whichever it is, to change.
    pub fn as_loading_mut(&mut self) -> &mut dyn Loading {
        match self {
            DlsmLoading::Free(l) => l,
            DlsmLoading::Tension(l) => l,
            DlsmLoading::FreeVibration(l) => l,
            DlsmLoading::Brazilian(l) => l,
            DlsmLoading::Drop(l) => l,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_keeps_the_checkpoint_bytes_of_the_struct_variant_it_was() {
        // Checkpoints written while `Free` was `Free { end_time }` restore as `Free(Free)`.
        #[derive(Serialize)]
        enum Before {
            Free { end_time: f64 },
        }
        let now = postcard::to_stdvec(&DlsmLoading::Free(Free { end_time: 1.25e-2 }));
        let before = postcard::to_stdvec(&Before::Free { end_time: 1.25e-2 });
        assert_eq!(now.expect("encodes"), before.expect("encodes"));
    }

    #[test]
    fn ramp_is_smooth_and_reaches_one() {
        assert_eq!(ramp_factor(0.0, 1.0), 0.0);
        assert!((ramp_factor(0.5, 1.0) - 0.5).abs() < 1e-15);
        assert_eq!(ramp_factor(2.0, 1.0), 1.0);
        assert_eq!(ramp_factor(0.3, 0.0), 1.0);
    }

    #[test]
    fn ramp_travel_is_the_integral_of_the_ramp() {
        // Midpoint sums of ramp_factor against the closed form, during and after the ramp.
        let ramp = 2e-3;
        for t in [0.3e-3, 1e-3, 2e-3, 3.7e-3] {
            let n = 200_000;
            let h = t / n as f64;
            let sum: f64 = (0..n)
                .map(|k| ramp_factor((k as f64 + 0.5) * h, ramp) * h)
                .sum();
            assert!((ramp_travel(t, ramp) - sum).abs() < 1e-12, "{t}");
        }
        assert_eq!(ramp_travel(-1.0, ramp), 0.0);
        assert_eq!(ramp_travel(0.5, 0.0), 0.5);
    }
}
