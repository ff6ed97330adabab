//! Particle shapes. Spheres are the fast special case: their radius lives in
//! `Bodies::radius` and their contact needs no orientation.

pub mod polyhedron;

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    Sphere,
    /// dlsm: a Voronoi cell; its geometry lives with the model, its principal moments in
    /// `Bodies::inertia` and its principal frame in `Bodies::orientation`.
    Polyhedron,
}

/// Mass (kg) of a sphere of radius `r` (m) and density `rho` (kg/m³).
pub fn sphere_mass(r: f64, rho: f64) -> f64 {
    rho * 4.0 / 3.0 * std::f64::consts::PI * r * r * r
}

/// Volume (m³) of a sphere of radius `r`.
pub fn sphere_volume(r: f64) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * r * r * r
}

/// Moment of inertia (kg·m²) of a solid sphere about any axis through its centre.
pub fn sphere_inertia(mass: f64, r: f64) -> f64 {
    0.4 * mass * r * r
}
