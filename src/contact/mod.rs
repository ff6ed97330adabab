//! Contact detection and contact laws.
//!
//! * [`convex`]: contact geometry of poly-ellipsoids, spheres and walls (Newton on the
//!   support functions), with the Hertz equivalent radius from the local curvatures.
//! * [`neighbor`]: broad phase (cell list, Verlet half list, wall candidate lists).
//! * [`hertz_mindlin`]: the Hertz–Mindlin force kernel with optional damping and friction.
//! * [`restitution`]: the exact map from a coefficient of restitution to Hertz damping.
//! * [`polyhedron`]: dlsm: frictional polyhedron contacts (GJK/EPA) and the ground plane.

pub mod convex;
pub mod hertz_mindlin;
pub mod neighbor;
// beam2d: the overlap-area law between polygons (Eq. 2-6).
pub mod overlap_area_2d;
pub mod polyhedron;
pub mod restitution;
