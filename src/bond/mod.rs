//! Cohesive interactions between bodies: `dlsm` (the distinct lattice spring model on
//! Voronoi elements).

pub mod dlsm;
