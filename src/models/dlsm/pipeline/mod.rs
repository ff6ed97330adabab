//! The force pipeline of the `dlsm` model: after the cohesive lattice (the bonds, always
//! there, evaluated first: they write the forces afresh), exactly the effects the scene names,
//! in a fixed order: the contacts broken bonds leave (`fracture`, `broken.rs`), the ground of
//! a drop (`contact`, with `friction`, `ground.rs`), the weight (`gravity`, `gravity.rs`). An
//! effect the scene does not list is not built.
//!
//! The broken contacts and the ground keep contact history, so the pipeline is part of the
//! run's state and a checkpoint keeps it; gravity is rebuilt from the scene and not written.

mod broken;
mod gravity;
mod ground;

use serde::{Deserialize, Serialize};

use super::loading::DlsmLoading;
use super::scene::DlsmScene;
use crate::contact::polyhedron::{BrokenContacts, GroundContact};
use crate::effects::Gravity;
use crate::scene::{EffectKind, Scene};
use crate::shape::polyhedron::Polyhedron;
use crate::state::{Bodies, Forces};

/// The effects of a dlsm scene after the cohesive lattice, in evaluation order.
#[derive(Clone, Default, Serialize, Deserialize)]
pub struct ElementPipeline {
    /// `fracture`: the contacts broken bonds leave.
    pub broken: Option<BrokenContacts>,
    /// `contact` (with `friction`): the ground.
    pub ground: Option<GroundContact>,
    /// `gravity`: rebuilt from the scene, not saved.
    #[serde(skip)]
    pub gravity: Option<Gravity>,
}

impl ElementPipeline {
    /// Builds exactly the effects the scene lists, for `elements` elements under `loading`
    /// (the drop's, which places the ground).
    pub fn build(
        scene: &Scene,
        cfg: &DlsmScene,
        loading: &DlsmLoading,
        elements: usize,
    ) -> ElementPipeline {
        ElementPipeline {
            broken: broken::build(scene, &cfg.material),
            ground: ground::build(scene, &cfg.material, loading, elements),
            gravity: gravity::build(scene),
        }
    }

    /// Keeps of a checkpoint's pipeline the effects the scene builds (`built`), with their
    /// history; gravity is the scene's.
    pub fn keep_built(&mut self, built: ElementPipeline) {
        if built.broken.is_none() {
            self.broken = None;
        }
        if built.ground.is_none() {
            self.ground = None;
        }
        self.gravity = built.gravity;
    }

    /// Adds the effects' forces and torques at the elements' current places, for a step of
    /// `dt` (s).
    pub fn accumulate(
        &mut self,
        bodies: &Bodies,
        shapes: &[Polyhedron],
        forces: &mut Forces,
        dt: f64,
    ) {
        if let Some(b) = &mut self.broken {
            b.accumulate(bodies, shapes, forces, dt);
        }
        if let Some(g) = &mut self.ground {
            g.accumulate(bodies, shapes, forces, dt);
        }
        if let Some(g) = &self.gravity {
            g.add_weight(bodies, forces);
        }
    }

    /// One line per effect the scene lists, in evaluation order, as `fractum explain` states
    /// them (the sample, which places the ground, is not built to explain it).
    pub fn describe(scene: &Scene, cfg: &DlsmScene) -> Vec<String> {
        let m = &cfg.material;
        let mut lines = Vec::new();
        if scene.has_effect(EffectKind::Fracture) {
            lines.push(broken::describe(m));
        }
        if scene.has_effect(EffectKind::Contact) {
            lines.push(ground::describe(scene, m));
        }
        if scene.has_effect(EffectKind::Gravity) {
            lines.push(gravity::describe(scene));
        }
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::Vec3;

    #[test]
    fn the_pipeline_keeps_the_checkpoint_bytes_of_the_two_fields_it_replaced() {
        // Checkpoints written while the state held `broken` and `ground` side by side restore
        // into the pipeline, and the pipeline writes the same bytes; gravity is not written.
        #[derive(Serialize)]
        struct Before {
            broken: Option<BrokenContacts>,
            ground: Option<GroundContact>,
        }
        let mut broken = BrokenContacts::new(0.3, 0.25);
        broken.add([2, 7], 1.5e6);
        let ground = GroundContact::new(Vec3::zeros(), Vec3::new(0.0, 0.0, 1.0), 2e6, 0.4, 3);
        let now = ElementPipeline {
            broken: Some(broken.clone()),
            ground: Some(ground.clone()),
            gravity: Some(Gravity::new(Vec3::new(0.0, 0.0, -9.81))),
        };
        let before = Before {
            broken: Some(broken),
            ground: Some(ground),
        };
        let bytes = postcard::to_stdvec(&now).expect("encodes");
        assert_eq!(bytes, postcard::to_stdvec(&before).expect("encodes"));
        let back: ElementPipeline = postcard::from_bytes(&bytes).expect("decodes");
        assert!(back.broken.is_some() && back.ground.is_some() && back.gravity.is_none());
    }
}
