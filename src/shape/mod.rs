//! Particle shapes. Spheres are the fast special case: their radius lives in
//! `Bodies::radius` and their contact needs no orientation. Poly-ellipsoids
//! ([`poly_ellipsoid`]) come from breaking grains or from poly-ellipsoid samples.

pub mod poly_ellipsoid;
// beam2d: convex polygons and half-plane clipping.
pub mod polygon;
// dlsm: Voronoi polyhedra.
pub mod polyhedron;

use nalgebra::UnitQuaternion;
use serde::{Deserialize, Serialize};

use crate::state::Vec3;
pub use poly_ellipsoid::PolyEllipsoid;

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    Sphere,
    /// A poly-ellipsoid in its body. The body frame is the principal frame of inertia with the
    /// centre of mass at the body's position; the shape frame (the octants' axes) sits in it at
    /// `origin`, turned by `to_body`.
    PolyEllipsoid {
        pe: PolyEllipsoid,
        /// The octant origin in the body frame (m).
        origin: Vec3,
        /// Turns shape-frame vectors into the body frame.
        to_body: UnitQuaternion<f64>,
    },
    /// dlsm: a Voronoi cell; its geometry lives with the model, its principal moments in
    /// `Bodies::inertia` and its principal frame in `Bodies::orientation`.
    Polyhedron,
}

impl Shape {
    /// Volume (m³) of a body of this shape with bounding radius `radius`.
    pub fn volume(&self, radius: f64) -> f64 {
        match self {
            Shape::Sphere => sphere_volume(radius),
            Shape::PolyEllipsoid { pe, .. } => pe.volume(),
            // The cell's volume lives with the dlsm model, not in the shape.
            Shape::Polyhedron => f64::NAN,
        }
    }

    /// Semi-axes [a+, a-, b+, b-, c+, c-] (m): a sphere's are all its radius.
    pub fn semi_axes(&self, radius: f64) -> [f64; 6] {
        match self {
            Shape::Sphere => [radius; 6],
            Shape::PolyEllipsoid { pe, .. } => pe.semi,
            Shape::Polyhedron => [radius; 6],
        }
    }

    pub fn is_sphere(&self) -> bool {
        matches!(self, Shape::Sphere)
    }
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
