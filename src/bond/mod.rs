//! Cohesive interactions between bodies.
//!
//! * [`beam2d`]: elastic beams between neighbouring polygons of the `beam2d` model (Eq. 7–13).
//! * [`dlsm`]: the distinct lattice spring model on Voronoi elements.

pub mod beam2d;
pub mod dlsm;
