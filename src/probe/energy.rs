//! The energy account of a run with fracture: where the work done on the sample went.
//!
//! ```text
//! ΔE_mech = W_boundary + W_springs − D + ΔE_splits + error,    E_mech = K + U_contacts + U_gravity
//! ```
//!
//! `W_boundary` is the work the moving walls did on the bodies (trapezoid rule per step),
//! `W_springs` the work of the cohesive springs (negative: energy spent in fracture), `D` the
//! energy damping and sliding dissipated (summed per contact per step by the contact kernel),
//! `ΔE_splits` the jumps of kinetic and elastic energy when grains change shape at a split,
//! and what is left, `error`, the integrator's: small while the run is stable.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value, json};

use crate::state::{Vec3, Walls};

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct EnergyAccount {
    /// Work done on the bodies by the walls (J).
    pub boundary_work: f64,
    /// Energy dissipated by contact damping and sliding (J).
    pub dissipated: f64,
    /// Mechanical energy at the start (J).
    pub initial: f64,
    /// Wall forces at the end of the last step (N).
    last_wall_forces: Vec<Vec3>,
}

/// The mechanical energy terms at one instant (J).
#[derive(Debug, Clone, Copy, Default)]
pub struct Mechanical {
    pub kinetic: f64,
    pub elastic: f64,
    pub gravity: f64,
}

impl Mechanical {
    pub fn total(&self) -> f64 {
        self.kinetic + self.elastic + self.gravity
    }
}

impl EnergyAccount {
    pub fn new(walls: &Walls, start: Mechanical) -> Self {
        EnergyAccount {
            initial: start.total(),
            last_wall_forces: walls.walls.iter().map(|w| w.force).collect(),
            ..Default::default()
        }
    }

    /// Adds a step of `dt`: the walls' work with their forces before and after it, and what
    /// the contacts dissipated in it.
    pub fn add_step(&mut self, walls: &Walls, dissipated: f64, dt: f64) {
        for (w, last) in walls.walls.iter().zip(&mut self.last_wall_forces) {
            // `force` is what the bodies exert on the wall; the wall exerts the opposite.
            self.boundary_work -= 0.5 * (w.force + *last).dot(&w.velocity) * dt;
            *last = w.force;
        }
        self.dissipated += dissipated;
    }

    /// The account as summary.json keys.
    pub fn report(&self, now: Mechanical, spring_work: f64, split_change: f64) -> Value {
        let change = now.total() - self.initial;
        let error = change - self.boundary_work - spring_work + self.dissipated - split_change;
        let scale = self
            .boundary_work
            .abs()
            .max(self.initial.abs())
            .max(f64::MIN_POSITIVE);
        let mut m = Map::new();
        m.insert("initial".into(), self.initial.into());
        m.insert("kinetic".into(), now.kinetic.into());
        m.insert("elastic".into(), now.elastic.into());
        m.insert("gravity_potential".into(), now.gravity.into());
        m.insert("boundary_work".into(), self.boundary_work.into());
        m.insert("dissipated".into(), self.dissipated.into());
        m.insert("fracture".into(), (-spring_work).into());
        m.insert("split_change".into(), split_change.into());
        m.insert("balance_error".into(), error.into());
        m.insert("balance_error_relative".into(), json!(error / scale));
        Value::Object(m)
    }
}
