//! Rigid convex polygons of the 2D `beam2d` model, as structure of arrays. Each polygon has
//! three degrees of freedom: the two coordinates of its centre of mass and its rotation angle
//! (Kun et al., Section 2.1). Positions, velocities, forces and inverse masses are kept as
//! `[x, y, θ]` triples so that integrators see one flat array of degrees of freedom.

use serde::{Deserialize, Serialize};

use crate::shape::polygon::{MAX_VERTICES, Vec2, area_properties};

/// Polygons: dynamic state and fixed properties, one entry per polygon in every array.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Polygons {
    /// Centre of mass (m) and rotation angle (rad) from the initial orientation.
    pub q: Vec<[f64; 3]>,
    /// Velocity (m/s) and angular velocity (rad/s).
    pub v: Vec<[f64; 3]>,
    /// 1/m, 1/m and 1/I; zero for a prescribed degree of freedom.
    pub inv_m: Vec<[f64; 3]>,
    /// Mass (kg) and moment of inertia about the centre of mass (kg·m²).
    pub mass: Vec<f64>,
    pub inertia: Vec<f64>,
    /// Area (m²).
    pub area: Vec<f64>,
    /// Diameter of the circle of the same area (m): the r_i of Eq. 2.
    pub equivalent_diameter: Vec<f64>,
    /// Largest distance of a vertex from the centre of mass (m).
    pub bound_radius: Vec<f64>,
    /// Number of vertices and the vertices relative to the centre of mass at θ = 0,
    /// counter-clockwise.
    pub n_vertices: Vec<u8>,
    pub local: Vec<[Vec2; MAX_VERTICES]>,
}

impl Polygons {
    pub fn len(&self) -> usize {
        self.q.len()
    }

    pub fn is_empty(&self) -> bool {
        self.q.is_empty()
    }

    /// Adds a polygon at rest from its vertices (counter-clockwise, at most MAX_VERTICES) in a
    /// solid of `density` (kg/m³) and `thickness` (m).
    pub fn push(&mut self, vertices: &[Vec2], density: f64, thickness: f64) {
        assert!(vertices.len() <= MAX_VERTICES, "too many vertices");
        let p = area_properties(vertices);
        let mass = density * thickness * p.area;
        let inertia = density * thickness * p.polar_moment;
        let mut local = [Vec2::zeros(); MAX_VERTICES];
        let mut bound: f64 = 0.0;
        for (l, v) in local.iter_mut().zip(vertices) {
            *l = v - p.centroid;
            bound = bound.max(l.norm());
        }
        self.q.push([p.centroid.x, p.centroid.y, 0.0]);
        self.v.push([0.0; 3]);
        self.inv_m.push([1.0 / mass, 1.0 / mass, 1.0 / inertia]);
        self.mass.push(mass);
        self.inertia.push(inertia);
        self.area.push(p.area);
        self.equivalent_diameter
            .push(2.0 * (p.area / std::f64::consts::PI).sqrt());
        self.bound_radius.push(bound);
        self.n_vertices.push(vertices.len() as u8);
        self.local.push(local);
    }

    /// Keeps the polygons `keep` says to, in order; returns the new index of each old one.
    pub fn retain(&mut self, keep: &[bool]) -> Vec<Option<usize>> {
        let mut map = Vec::with_capacity(keep.len());
        let mut next = 0;
        for &k in keep {
            map.push(k.then(|| {
                next += 1;
                next - 1
            }));
        }
        fn take<T: Clone>(v: &mut Vec<T>, keep: &[bool]) {
            let mut k = keep.iter();
            v.retain(|_| *k.next().expect("one flag per polygon"));
        }
        take(&mut self.q, keep);
        take(&mut self.v, keep);
        take(&mut self.inv_m, keep);
        take(&mut self.mass, keep);
        take(&mut self.inertia, keep);
        take(&mut self.area, keep);
        take(&mut self.equivalent_diameter, keep);
        take(&mut self.bound_radius, keep);
        take(&mut self.n_vertices, keep);
        take(&mut self.local, keep);
        map
    }

    pub fn centre(&self, i: usize) -> Vec2 {
        Vec2::new(self.q[i][0], self.q[i][1])
    }

    pub fn velocity(&self, i: usize) -> Vec2 {
        Vec2::new(self.v[i][0], self.v[i][1])
    }

    /// Writes polygon i's vertices in the world frame into `out`; returns how many.
    #[inline(always)]
    pub fn world_vertices(&self, i: usize, out: &mut [Vec2; MAX_VERTICES]) -> usize {
        let [x, y, th] = self.q[i];
        let (s, c) = th.sin_cos();
        let n = self.n_vertices[i] as usize;
        for (o, l) in out.iter_mut().zip(&self.local[i][..n]) {
            *o = Vec2::new(x + c * l.x - s * l.y, y + s * l.x + c * l.y);
        }
        n
    }

    /// Kinetic energy (J), translational and rotational, summed in index order.
    pub fn kinetic_energy(&self) -> f64 {
        let mut e = 0.0;
        for i in 0..self.len() {
            let [vx, vy, w] = self.v[i];
            e += 0.5 * (self.mass[i] * (vx * vx + vy * vy) + self.inertia[i] * w * w);
        }
        e
    }

    /// Total linear momentum (kg·m/s), summed in index order.
    pub fn momentum(&self) -> Vec2 {
        let mut p = Vec2::zeros();
        for i in 0..self.len() {
            p += self.velocity(i) * self.mass[i];
        }
        p
    }

    /// Σ m |v| (kg·m/s): the scale against which momentum drift is measured.
    pub fn momentum_scale(&self) -> f64 {
        (0..self.len())
            .map(|i| self.mass[i] * self.velocity(i).norm())
            .sum()
    }

    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }

    /// The first polygon with a non-finite position or velocity, if any.
    pub fn first_non_finite(&self) -> Option<usize> {
        (0..self.len()).find(|&i| {
            !(self.q[i].iter().all(|v| v.is_finite()) && self.v[i].iter().all(|v| v.is_finite()))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_polygon_mass_inertia_and_rotation() {
        let mut p = Polygons::default();
        let sq = [
            Vec2::new(0.0, 0.0),
            Vec2::new(0.02, 0.0),
            Vec2::new(0.02, 0.02),
            Vec2::new(0.0, 0.02),
        ];
        p.push(&sq, 5000.0, 0.01);
        let m = 5000.0 * 0.01 * 4e-4;
        assert!((p.mass[0] - m).abs() < 1e-15);
        // m a² / 6 for a square of side a about its centre.
        assert!((p.inertia[0] - m * 4e-4 / 6.0).abs() < 1e-18);
        assert!(
            (p.equivalent_diameter[0] - 2.0 * (4e-4 / std::f64::consts::PI).sqrt()).abs() < 1e-15
        );
        p.q[0][2] = std::f64::consts::FRAC_PI_2;
        let mut w = [Vec2::zeros(); MAX_VERTICES];
        let n = p.world_vertices(0, &mut w);
        assert_eq!(n, 4);
        // The corner (0, 0) turned by 90° about the centre (0.01, 0.01) lands on (0.02, 0).
        assert!((w[0] - Vec2::new(0.02, 0.0)).norm() < 1e-15);
        let keep = p.retain(&[false]);
        assert_eq!(keep, vec![None]);
        assert!(p.is_empty());
    }
}
