//! The state of a run: bodies as structure-of-arrays, walls, and the forces of the last step.
//! Everything here is plain data, serialisable for checkpoints.

// beam2d: rigid polygons in the plane.
pub mod polygons;
mod walls;

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::parallel::{on_team, team_blocks};
use crate::shape::{self, PolyEllipsoid, Shape};

pub use walls::{BoxFace, SLEEVE_SLICES, Sleeve, Wall, Walls, plane_distance, radial};

pub type Vec3 = Vector3<f64>;

/// Rigid bodies, one entry per body in every array.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Bodies {
    /// Centre of mass (m).
    pub pos: Vec<Vec3>,
    /// Velocity (m/s).
    pub vel: Vec<Vec3>,
    /// Angular velocity in the world frame (rad/s).
    pub omega: Vec<Vec3>,
    /// Orientation, body to world.
    pub orientation: Vec<UnitQuaternion<f64>>,
    /// Bounding radius (m); the radius of a sphere.
    pub radius: Vec<f64>,
    /// Mass (kg).
    pub mass: Vec<f64>,
    pub inv_mass: Vec<f64>,
    /// Principal moments of inertia in the body frame (kg·m²).
    pub inertia: Vec<Vec3>,
    pub inv_inertia: Vec<Vec3>,
    pub shape: Vec<Shape>,
}

impl Bodies {
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Whether every per-body array has one entry per body (a restored state is checked before
    /// it is stepped); the first that does not, named.
    pub fn check_lengths(&self) -> std::result::Result<(), String> {
        let n = self.len();
        let lens = [
            ("vel", self.vel.len()),
            ("omega", self.omega.len()),
            ("orientation", self.orientation.len()),
            ("radius", self.radius.len()),
            ("mass", self.mass.len()),
            ("inv_mass", self.inv_mass.len()),
            ("inertia", self.inertia.len()),
            ("inv_inertia", self.inv_inertia.len()),
            ("shape", self.shape.len()),
        ];
        check_lengths(n, &lens)
    }

    /// Whether every value of every body is one a step can start from: finite positions,
    /// velocities, spins, orientations and inertias, positive finite radii and masses (a
    /// restored state is checked before it is stepped: a NaN centre sent the neighbour search
    /// to a cell outside its grid and panicked); the first that is not, named.
    pub fn check_values(&self) -> std::result::Result<(), String> {
        let finite3 = |v: &Vec3| v.iter().all(|x| x.is_finite());
        for i in 0..self.len() {
            let q = &self.orientation[i];
            let bad = if !finite3(&self.pos[i]) {
                Some("position")
            } else if !finite3(&self.vel[i]) {
                Some("velocity")
            } else if !finite3(&self.omega[i]) {
                Some("angular velocity")
            } else if !q.coords.iter().all(|x| x.is_finite()) {
                Some("orientation")
            } else if !(self.radius[i].is_finite() && self.radius[i] > 0.0) {
                Some("radius")
            } else if !(self.mass[i].is_finite() && self.mass[i] > 0.0) {
                Some("mass")
            } else if !(self.inv_mass[i].is_finite()
                && finite3(&self.inertia[i])
                && finite3(&self.inv_inertia[i]))
            {
                Some("inverse mass or inertia")
            } else {
                None
            };
            if let Some(what) = bad {
                return Err(format!("body {i} has a non-finite or non-positive {what}"));
            }
        }
        Ok(())
    }

    /// Adds a sphere at rest.
    pub fn push_sphere(
        &mut self,
        pos: Vec3,
        radius: f64,
        density: f64,
        orientation: UnitQuaternion<f64>,
    ) {
        let m = shape::sphere_mass(radius, density);
        let i = shape::sphere_inertia(m, radius);
        self.pos.push(pos);
        self.vel.push(Vec3::zeros());
        self.omega.push(Vec3::zeros());
        self.orientation.push(orientation);
        self.radius.push(radius);
        self.mass.push(m);
        self.inv_mass.push(1.0 / m);
        self.inertia.push(Vec3::repeat(i));
        self.inv_inertia.push(Vec3::repeat(1.0 / i));
        self.shape.push(Shape::Sphere);
    }

    /// Adds a poly-ellipsoid of mass `mass` (kg) at rest, with its centroid at `centroid` and
    /// its shape frame turned by `shape_orientation` (shape to world). Its body frame is its
    /// principal frame of inertia. Returns its index.
    pub fn push_poly_ellipsoid(
        &mut self,
        pe: PolyEllipsoid,
        mass: f64,
        centroid: Vec3,
        shape_orientation: UnitQuaternion<f64>,
    ) -> usize {
        self.push(Body::poly_ellipsoid(pe, mass, centroid, shape_orientation))
    }

    /// Appends `body`; returns its index.
    pub fn push(&mut self, body: Body) -> usize {
        self.pos.push(body.pos);
        self.vel.push(body.vel);
        self.omega.push(body.omega);
        self.orientation.push(body.orientation);
        self.radius.push(body.radius);
        self.mass.push(body.mass);
        self.inv_mass.push(body.inv_mass);
        self.inertia.push(body.inertia);
        self.inv_inertia.push(body.inv_inertia);
        self.shape.push(body.shape);
        self.len() - 1
    }

    /// Turns body `i` into `body` (every array), keeping the array lengths.
    pub fn set(&mut self, i: usize, body: &Body) {
        self.pos[i] = body.pos;
        self.vel[i] = body.vel;
        self.omega[i] = body.omega;
        self.orientation[i] = body.orientation;
        self.radius[i] = body.radius;
        self.mass[i] = body.mass;
        self.inv_mass[i] = body.inv_mass;
        self.inertia[i] = body.inertia;
        self.inv_inertia[i] = body.inv_inertia;
        self.shape[i] = body.shape;
    }

    /// A copy of body `i`.
    pub fn body(&self, i: usize) -> Body {
        Body {
            pos: self.pos[i],
            vel: self.vel[i],
            omega: self.omega[i],
            orientation: self.orientation[i],
            radius: self.radius[i],
            mass: self.mass[i],
            inv_mass: self.inv_mass[i],
            inertia: self.inertia[i],
            inv_inertia: self.inv_inertia[i],
            shape: self.shape[i],
        }
    }

    /// Volume (m³) of body i.
    pub fn volume(&self, i: usize) -> f64 {
        self.shape[i].volume(self.radius[i])
    }

    /// The world octant origin (m) and the shape-to-world rotation of body i; for a sphere,
    /// its centre and its body frame.
    pub fn shape_placement(&self, i: usize) -> (Vec3, UnitQuaternion<f64>) {
        shape_placement(&self.pos[i], &self.orientation[i], &self.shape[i])
    }

    /// dlsm: adds a polyhedron at rest with its centroid at `pos`, principal moments of
    /// inertia `inertia` (kg·m²) and principal frame `orientation`, bounded by `radius`.
    pub fn push_polyhedron(
        &mut self,
        pos: Vec3,
        mass: f64,
        inertia: Vec3,
        orientation: UnitQuaternion<f64>,
        radius: f64,
    ) {
        self.pos.push(pos);
        self.vel.push(Vec3::zeros());
        self.omega.push(Vec3::zeros());
        self.orientation.push(orientation);
        self.radius.push(radius);
        self.mass.push(mass);
        self.inv_mass.push(1.0 / mass);
        self.inertia.push(inertia);
        self.inv_inertia.push(inertia.map(|v| 1.0 / v));
        self.shape.push(Shape::Polyhedron);
    }

    /// Total kinetic energy, translational and rotational (J), summed in index order.
    pub fn kinetic_energy(&self) -> f64 {
        let mut e = 0.0;
        for i in 0..self.len() {
            e += 0.5 * self.mass[i] * self.vel[i].norm_squared();
            let w = self.orientation[i].inverse_transform_vector(&self.omega[i]);
            e += 0.5 * w.component_mul(&w).dot(&self.inertia[i]);
        }
        e
    }

    /// Total solid volume (m³) of the bodies.
    pub fn solid_volume(&self) -> f64 {
        (0..self.len()).map(|i| self.volume(i)).sum()
    }

    pub fn min_radius(&self) -> f64 {
        self.radius.iter().copied().fold(f64::INFINITY, f64::min)
    }

    pub fn max_radius(&self) -> f64 {
        self.radius.iter().copied().fold(0.0, f64::max)
    }

    /// Puts the bodies in the order `order` (a permutation: new index k holds old `order[k]`).
    pub fn reorder(&mut self, order: &[usize]) {
        fn take<T: Clone>(v: &mut Vec<T>, order: &[usize]) {
            *v = order.iter().map(|&k| v[k].clone()).collect();
        }
        take(&mut self.pos, order);
        take(&mut self.vel, order);
        take(&mut self.omega, order);
        take(&mut self.orientation, order);
        take(&mut self.radius, order);
        take(&mut self.mass, order);
        take(&mut self.inv_mass, order);
        take(&mut self.inertia, order);
        take(&mut self.inv_inertia, order);
        take(&mut self.shape, order);
    }

    /// An order of the bodies by cells of edge `cell`, slab by slab along z, then y, then x:
    /// neighbours get nearby indices, which keeps the force loop in cache and each thread's
    /// range of partners narrow.
    pub fn spatial_order(&self, cell: f64) -> Vec<usize> {
        spatial_order(&self.pos, cell)
    }

    /// The first body with a non-finite position or velocity, if any.
    pub fn first_non_finite(&self) -> Option<usize> {
        // Checked after every step: across the run's team, each member over the bodies it
        // integrates (the data stays in that core's cache).
        let first = |mut range: std::ops::Range<usize>| {
            range.find(|&i| {
                !(self.pos[i].iter().all(|v| v.is_finite())
                    && self.vel[i].iter().all(|v| v.is_finite())
                    && self.omega[i].iter().all(|v| v.is_finite()))
            })
        };
        match team_blocks(self.len()) {
            Some(blocks) => on_team(blocks, |_, r| first(r))
                .into_iter()
                .flatten()
                .next(),
            None => first(0..self.len()),
        }
    }
}

/// One body: every array of [`Bodies`] at one index. The kernels that the C ABI exports
/// (contact, fracture) take and give bodies one at a time in this form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// Centre of mass (m).
    pub pos: Vec3,
    /// Velocity (m/s).
    pub vel: Vec3,
    /// Angular velocity in the world frame (rad/s).
    pub omega: Vec3,
    /// Orientation, body to world.
    pub orientation: UnitQuaternion<f64>,
    /// Bounding radius (m); the radius of a sphere.
    pub radius: f64,
    /// Mass (kg) and its inverse.
    pub mass: f64,
    pub inv_mass: f64,
    /// Principal moments of inertia in the body frame (kg·m²) and their inverses.
    pub inertia: Vec3,
    pub inv_inertia: Vec3,
    pub shape: Shape,
}

impl Body {
    /// A poly-ellipsoid of mass `mass` (kg) at rest, with its centroid at `centroid` and its
    /// shape frame turned by `shape_orientation` (shape to world). Its body frame is its
    /// principal frame of inertia.
    pub fn poly_ellipsoid(
        pe: PolyEllipsoid,
        mass: f64,
        centroid: Vec3,
        shape_orientation: UnitQuaternion<f64>,
    ) -> Body {
        let (moments, frame) = pe.principal_inertia(mass / pe.volume());
        let to_body = frame.inverse();
        Body {
            pos: centroid,
            vel: Vec3::zeros(),
            omega: Vec3::zeros(),
            orientation: shape_orientation * frame,
            radius: pe.bounding_radius(),
            mass,
            inv_mass: 1.0 / mass,
            inertia: moments,
            inv_inertia: moments.map(|m| 1.0 / m),
            shape: Shape::PolyEllipsoid {
                pe,
                origin: to_body * -pe.centroid(),
                to_body,
            },
        }
    }

    /// A body at rest from the parts a host keeps for it (the Fractum LAMMPS plugin's per-atom
    /// arrays, read back from its data files): centre `pos` (m), orientation (body to world; the
    /// body frame is the principal frame of inertia), bounding radius (m), mass (kg), the
    /// principal moments of inertia (kg·m²) and the shape.
    #[inline]
    pub fn rigid(
        pos: Vec3,
        orientation: UnitQuaternion<f64>,
        radius: f64,
        mass: f64,
        inertia: Vec3,
        shape: Shape,
    ) -> Body {
        Body {
            pos,
            vel: Vec3::zeros(),
            omega: Vec3::zeros(),
            orientation,
            radius,
            mass,
            inv_mass: 1.0 / mass,
            inertia,
            inv_inertia: inertia.map(|m| 1.0 / m),
            shape,
        }
    }

    /// Volume (m³).
    pub fn volume(&self) -> f64 {
        self.shape.volume(self.radius)
    }

    /// The world octant origin (m) and the shape-to-world rotation; for a sphere, its centre
    /// and its body frame.
    pub fn shape_placement(&self) -> (Vec3, UnitQuaternion<f64>) {
        shape_placement(&self.pos, &self.orientation, &self.shape)
    }
}

/// The world octant origin (m) and the shape-to-world rotation of a body of shape `shape` at
/// `pos` turned by `orientation` (body to world); for a sphere, its centre and its body frame.
#[inline]
pub fn shape_placement(
    pos: &Vec3,
    orientation: &UnitQuaternion<f64>,
    shape: &Shape,
) -> (Vec3, UnitQuaternion<f64>) {
    match shape {
        Shape::Sphere | Shape::Polyhedron => (*pos, *orientation),
        Shape::PolyEllipsoid {
            origin, to_body, ..
        } => (pos + orientation * origin, orientation * to_body),
    }
}

/// Forces and torques on the bodies (N, N·m), world frame.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Forces {
    pub force: Vec<Vec3>,
    pub torque: Vec<Vec3>,
}

impl Forces {
    pub fn new(n: usize) -> Self {
        Forces {
            force: vec![Vec3::zeros(); n],
            torque: vec![Vec3::zeros(); n],
        }
    }

    pub fn clear(&mut self) {
        self.force.iter_mut().for_each(|f| *f = Vec3::zeros());
        self.torque.iter_mut().for_each(|t| *t = Vec3::zeros());
    }
}

/// An order of `pos` by cells of edge `cell`, slab by slab along z, then y, then x (see
/// [`Bodies::spatial_order`]).
pub fn spatial_order(pos: &[Vec3], cell: f64) -> Vec<usize> {
    let mut lo = Vec3::repeat(f64::INFINITY);
    for p in pos {
        lo = lo.inf(p);
    }
    let key = |p: &Vec3| {
        let c = (p - lo) / cell;
        (c.z as u64, c.y as u64, c.x as u64)
    };
    let mut order: Vec<usize> = (0..pos.len()).collect();
    order.sort_by_key(|&i| key(&pos[i]));
    order
}

/// Whether each named array has `n` entries; the first that does not, named.
pub fn check_lengths(n: usize, lens: &[(&str, usize)]) -> std::result::Result<(), String> {
    match lens.iter().find(|(_, len)| *len != n) {
        Some((name, len)) => Err(format!("{name} has {len} entries for {n} bodies")),
        None => Ok(()),
    }
}
