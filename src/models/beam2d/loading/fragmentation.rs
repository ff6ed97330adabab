//! What the two free loadings share (the explosion and the projectile): nothing is driven
//! after the start, the run stops once no beam has broken for a while, and a row counts the
//! fragments and the momentum.

use super::super::Beam2d;
use super::super::report::fragments;

/// Columns for free fragmentation: time, kinetic energy, overlapping pairs, broken beams,
/// fragments (components over intact beams) and the total momentum (kg·m/s).
pub const FREE_COLUMNS: [&str; 7] = [
    "time",
    "kinetic_energy",
    "contacts",
    "broken_beams",
    "fragments",
    "momentum_x",
    "momentum_y",
];

/// One row of [`FREE_COLUMNS`] at `time` (s).
pub fn row(model: &Beam2d, time: f64) -> Vec<f64> {
    let st = &model.state;
    let p = &st.polygons;
    let momentum = p.momentum();
    let (_, count) = fragments(p, &st.beams);
    vec![
        time,
        p.kinetic_energy(),
        st.contacts as f64,
        st.beams.broken() as f64,
        count as f64,
        momentum.x,
        momentum.y,
    ]
}
