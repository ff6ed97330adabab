//! The `gravity` effect of the dlsm model: every element's weight m g, by the granular
//! pipeline's [`crate::effects::Gravity`] (the same sum over the same bodies).

use crate::effects::Gravity;
use crate::scene::{EffectKind, Scene};
use crate::state::Vec3;

/// The weight under the scene's `gravity.acceleration`; only with `gravity`.
pub(super) fn build(scene: &Scene) -> Option<Gravity> {
    scene
        .has_effect(EffectKind::Gravity)
        .then(|| Gravity::new(Vec3::from(scene.gravity.acceleration)))
}

/// The effect as `fractum explain` states it.
pub(super) fn describe(scene: &Scene) -> String {
    let g = scene.gravity.acceleration;
    format!("gravity: m g, g = ({}, {}, {}) m/s²", g[0], g[1], g[2])
}
