//! Contact detection and contact laws.
//!
//! * [`convex`]: contact geometry of poly-ellipsoids, spheres and walls (Newton on the
//!   support functions), with the Hertz equivalent radius from the local curvatures.
//! * [`neighbor`]: broad phase (cell list, Verlet half list, wall candidate lists).
//! * [`hertz_mindlin`]: the Hertz–Mindlin force kernel with optional damping and friction.
//! * [`restitution`]: the exact map from a coefficient of restitution to Hertz damping.
//! * [`pair`]: one pair's contact (and a body's against a wall) by that law on that
//!   geometry, with what the pair remembers; the separated pairs' skip.
//! * [`records`]: the contacts of an evaluation as records, and the frequency bound on
//!   their springs that the step check and adaptation read.
//! * [`polyhedron`]: dlsm: frictional polyhedron contacts (GJK/EPA) and the ground plane.

pub mod convex;
pub mod hertz_mindlin;
pub mod neighbor;
// beam2d: the overlap-area law between polygons (Eq. 2-6).
pub mod overlap_area_2d;
pub mod pair;
pub mod polyhedron;
pub mod records;
pub mod restitution;
