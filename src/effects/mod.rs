//! The granular model's force pipeline ([`BodyPipeline`]): the effects a scene names, in a
//! fixed order, and nothing else; one effect a file (`contact.rs`, `gravity.rs`). It lives
//! below the models because sample preparation (compaction) runs the contact effect too. The
//! dlsm and beam2d models' pipelines (`ElementPipeline`, `PolygonPipeline`) are built the
//! same way in their folders.
//!
//! An effect that a scene does not list is never constructed: no allocation, no loop, no
//! branch in the hot path. The contact effect is monomorphised over its optional sub-models
//! (damping, friction), so a frictionless scene runs a kernel with no tangential code in it
//! and keeps no contact history.

pub mod contact;
pub mod gravity;

use crate::error::{Error, Result};
use crate::state::{Bodies, Forces, Vec3, Walls};

pub use crate::contact::records::{ContactRecord, ContactRecords, WALL};
pub use contact::{ContactParams, PairParts, build_contact};
pub use gravity::Gravity;

/// What an effect needs to know about the step being taken.
#[derive(Debug, Clone, Copy)]
pub struct StepContext {
    /// Time step (s).
    pub dt: f64,
    /// False only for the force evaluation before the first step: contact histories must not
    /// advance then.
    pub update_history: bool,
}

/// One term of the force pipeline.
pub trait Effect: Send {
    /// The scene name of the effect (as in `effects = [...]`).
    fn name(&self) -> &'static str;
    /// One line for `fractum explain`: the model and its constants.
    fn describe(&self) -> String;
    /// Adds this effect's forces and torques.
    fn accumulate(
        &mut self,
        ctx: &StepContext,
        bodies: &Bodies,
        walls: &mut Walls,
        forces: &mut Forces,
    );
    /// Body–body contacts active in the last evaluation.
    fn contacts(&self) -> usize {
        0
    }
    /// Every contact of the last evaluation, when this effect records them (the contact
    /// effect with poly-ellipsoids or fracture).
    fn records(&self) -> Option<&ContactRecords> {
        None
    }
    /// Bodies whose shape has just changed (a grain split): what the effect remembers of
    /// their contacts (held Hertz radii) no longer holds.
    fn reshaped(&mut self, _bodies: &[usize]) {}
    /// Persistent state (contact histories) for checkpoints; empty when there is none.
    fn save(&self) -> Vec<u8> {
        Vec::new()
    }
    /// Restores what [`Effect::save`] wrote, for a state of `bodies` bodies.
    fn restore(&mut self, _data: &[u8], _bodies: usize) -> Result<()> {
        Ok(())
    }
    /// Length of the contact history this effect keeps (0 when it keeps none).
    fn history_len(&self) -> usize {
        0
    }
    /// An upper estimate of the highest angular frequency (rad/s) this effect's springs give
    /// any body at the current positions; 0 for effects without springs.
    fn max_frequency(&self, _bodies: &Bodies, _walls: &Walls) -> f64 {
        0.0
    }
}

/// The effects of a granular scene in evaluation order, over its bodies.
pub struct BodyPipeline {
    pub effects: Vec<Box<dyn Effect>>,
}

impl BodyPipeline {
    /// Builds exactly the effects asked for: a contact model and gravity (m/s²). The order
    /// of evaluation is fixed (contact, then body forces).
    pub fn new(contact: Option<ContactParams>, gravity: Option<Vec3>) -> BodyPipeline {
        let mut effects: Vec<Box<dyn Effect>> = Vec::new();
        if let Some(params) = contact {
            effects.push(build_contact(params));
        }
        if let Some(g) = gravity {
            effects.push(Box::new(Gravity::new(g)));
        }
        BodyPipeline { effects }
    }

    pub fn accumulate(
        &mut self,
        ctx: &StepContext,
        bodies: &Bodies,
        walls: &mut Walls,
        forces: &mut Forces,
    ) {
        for e in &mut self.effects {
            e.accumulate(ctx, bodies, walls, forces);
        }
    }

    /// One line per effect, in evaluation order.
    pub fn describe(&self) -> Vec<String> {
        self.effects
            .iter()
            .map(|e| format!("{}: {}", e.name(), e.describe()))
            .collect()
    }

    pub fn names(&self) -> Vec<&'static str> {
        self.effects.iter().map(|e| e.name()).collect()
    }

    pub fn contacts(&self) -> usize {
        self.effects.iter().map(|e| e.contacts()).sum()
    }

    /// The contact records of the last evaluation, if an effect keeps them.
    pub fn records(&self) -> Option<&ContactRecords> {
        self.effects.iter().find_map(|e| e.records())
    }

    /// See [`Effect::reshaped`].
    pub fn reshaped(&mut self, bodies: &[usize]) {
        for e in &mut self.effects {
            e.reshaped(bodies);
        }
    }

    pub fn history_len(&self) -> usize {
        self.effects.iter().map(|e| e.history_len()).sum()
    }

    /// The highest frequency estimate of all effects (rad/s).
    pub fn max_frequency(&self, bodies: &Bodies, walls: &Walls) -> f64 {
        self.effects
            .iter()
            .map(|e| e.max_frequency(bodies, walls))
            .fold(0.0, f64::max)
    }

    pub fn save(&self) -> Vec<(String, Vec<u8>)> {
        self.effects
            .iter()
            .map(|e| (e.name().to_string(), e.save()))
            .collect()
    }

    pub fn restore(&mut self, saved: &[(String, Vec<u8>)], bodies: usize) -> Result<()> {
        if saved.len() != self.effects.len() {
            return Err(Error::run(
                "the checkpoint's force pipeline does not match its scene",
            ));
        }
        for (e, (name, data)) in self.effects.iter_mut().zip(saved) {
            if e.name() != name {
                return Err(Error::run(format!(
                    "the checkpoint has effect `{name}` where the scene builds `{}`",
                    e.name()
                )));
            }
            e.restore(data, bodies)?;
        }
        Ok(())
    }
}
