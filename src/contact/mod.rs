//! Contact detection and contact laws.
//!
//! * [`neighbor`]: broad phase (cell list, Verlet half list, wall candidate lists).
//! * [`hertz_mindlin`]: the Hertz–Mindlin force kernel with optional damping and friction.
//! * [`restitution`]: the exact map from a coefficient of restitution to Hertz damping.
//! * [`polyhedron`]: dlsm: frictional polyhedron contacts (GJK/EPA) and the ground plane.

pub mod hertz_mindlin;
pub mod neighbor;
pub mod polyhedron;
pub mod restitution;
