//! The `contact` effect of the dlsm model: the elements against the ground of a drop, with
//! Coulomb friction under `friction` ([`crate::contact::polyhedron::GroundContact`]).

use super::super::loading::DlsmLoading;
use super::super::scene::Material;
use crate::contact::polyhedron::GroundContact;
use crate::scene::{EffectKind, Scene};

/// The ground the drop placed, for `elements` elements; only with `contact`, a contact
/// stiffness and a drop.
pub(super) fn build(
    scene: &Scene,
    m: &Material,
    loading: &DlsmLoading,
    elements: usize,
) -> Option<GroundContact> {
    match (
        loading,
        m.contact_stiffness,
        scene.has_effect(EffectKind::Contact),
    ) {
        (DlsmLoading::Drop(d), Some(k), true) => Some(GroundContact::new(
            d.ground_point,
            d.ground_normal,
            k,
            if scene.has_effect(EffectKind::Friction) {
                m.friction
            } else {
                0.0
            },
            elements,
        )),
        _ => None,
    }
}

/// The effect as `fractum explain` states it.
pub(super) fn describe(scene: &Scene, m: &Material) -> String {
    format!(
        "contact: elements against the ground plane, stiffness {:e} N/m{}",
        m.contact_stiffness.unwrap_or(0.0),
        if scene.has_effect(EffectKind::Friction) {
            format!(", Coulomb friction mu = {}", m.friction)
        } else {
            ", frictionless".to_string()
        }
    )
}
