//! The `fracture` effect of the dlsm model: a cohesive contact that breaks (Eq. 36) becomes a
//! frictional, non-cohesive contact between the two polyhedra
//! ([`crate::contact::polyhedron::BrokenContacts`]).

use super::super::scene::Material;
use crate::contact::polyhedron::BrokenContacts;
use crate::scene::{EffectKind, Scene};

/// The broken contacts, empty at the start; only with `fracture`.
pub(super) fn build(scene: &Scene, m: &Material) -> Option<BrokenContacts> {
    (scene.has_effect(EffectKind::Fracture) && m.tensile_strength.is_some())
        .then(|| BrokenContacts::new(m.friction, m.poisson))
}

/// The effect as `fractum explain` states it.
pub(super) fn describe(m: &Material) -> String {
    format!(
        "fracture: a contact breaks for good when sigma_xx > {:e} Pa (Eq. 36) and becomes a frictional (mu = {}) non-cohesive polyhedron contact (GJK/EPA)",
        m.tensile_strength.unwrap_or(0.0),
        m.friction
    )
}
