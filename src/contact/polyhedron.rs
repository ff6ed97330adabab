//! Frictional, non-cohesive contacts of convex polyhedra (the `dlsm` model's elements):
//! between the two elements of a broken cohesive contact, and between elements and a rigid
//! surface (a ground plane, a platen, a concave cylindrical jaw).
//!
//! Detection. Element pairs: GJK, then EPA when they overlap (parry3d-f64), on the support
//! maps of the two polyhedra in their current poses; GJK/EPA returns the penetration depth
//! δ, the normal and a witness point on each surface, and the force acts at the midpoint of
//! the two. Plane: the vertex deepest below it (the support point along the inward normal,
//! which is what GJK/EPA returns against a half-space), acting at that vertex. Concave
//! cylinder: the vertex farthest from the axis (the distance from a line is convex, and a
//! convex function's maximum over a convex polyhedron is at a vertex), with the radial
//! normal there. A bounding-sphere test skips pairs and elements that cannot touch.
//!
//! Law. Normal force k δ; tangential force from an elastic spring of stiffness k_t on the
//! accumulated relative tangential displacement (kept per contact, turned into the current
//! tangent plane each step), capped at μ times the normal force (Coulomb); no cohesion,
//! no damping. A contact that opens forgets its tangential displacement.

use nalgebra::Matrix3;
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::contact::contact_support_map_support_map;
use parry3d_f64::shape::SupportMap;
use serde::{Deserialize, Serialize};

use crate::shape::polyhedron::Polyhedron;
use crate::state::{Bodies, Forces, Vec3};

/// A polyhedron turned by `rot`, as a support map about its centroid.
struct Turned<'a> {
    shape: &'a Polyhedron,
    rot: Matrix3<f64>,
}

impl SupportMap for Turned<'_> {
    fn local_support_point(&self, dir: Vector) -> Vector {
        let d = self.rot.tr_mul(&Vec3::new(dir.x, dir.y, dir.z));
        let v = self.rot * self.shape.support(&d);
        Vector::new(v.x, v.y, v.z)
    }
}

fn to_vec3(v: Vector) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// The Coulomb-limited tangential spring: updates the elastic displacement `xi` with the
/// tangential relative velocity `vt` over `dt` (after turning it into the plane of normal
/// `n`) and returns the tangential force on the body whose relative velocity `vt` is.
#[inline]
fn tangential_force(xi: &mut Vec3, n: &Vec3, vt: &Vec3, dt: f64, kt: f64, limit: f64) -> Vec3 {
    *xi -= n * n.dot(xi);
    *xi += vt * dt;
    let f = kt * xi.norm();
    if f > limit {
        *xi *= if f > 0.0 { limit / f } else { 0.0 };
    }
    -*xi * kt
}

/// The shape of a [`GroundContact`]'s rigid surface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Surface {
    /// The plane through `point` normal to `normal`.
    Plane,
    /// A concave circular cylinder of `radius` (m) about an `axis` (unit, normal to
    /// `normal`) through `point + radius × normal`: it touches the plane of [`Surface::Plane`]
    /// at `point` and curves towards the elements on either side, as a jaw around a disc. Its
    /// half on the far side of the axis is open.
    Cylinder { radius: f64, axis: Vec3 },
}

/// A rigid surface every element may touch: the ground of a `drop`, a platen or a jaw of a
/// Brazilian test.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct GroundContact {
    pub point: Vec3,
    /// The surface's unit normal at `point`, towards the elements.
    pub normal: Vec3,
    pub surface: Surface,
    /// The surface's velocity (m/s): the elements slide relative to it.
    pub velocity: Vec3,
    /// Normal and tangential stiffness (N/m).
    pub stiffness: f64,
    /// Coulomb coefficient; 0 without the `friction` effect.
    pub friction: f64,
    /// Elastic tangential displacement per element (empty without friction).
    pub history: Vec<Vec3>,
    /// Elements touching and the energy of the springs in the last evaluation.
    pub contacts: usize,
    pub energy: f64,
    /// The sum of the forces it applied to the elements in the last evaluation (N).
    pub total: Vec3,
    /// A cylinder's contact half-width in the last evaluation (m): the largest distance of a
    /// touching vertex from the plane of the normal and the axis (0 for a plane).
    pub reach: f64,
}

impl GroundContact {
    pub fn new(point: Vec3, normal: Vec3, stiffness: f64, friction: f64, elements: usize) -> Self {
        GroundContact {
            point,
            normal: normal.normalize(),
            surface: Surface::Plane,
            velocity: Vec3::zeros(),
            stiffness,
            friction,
            history: if friction > 0.0 {
                vec![Vec3::zeros(); elements]
            } else {
                Vec::new()
            },
            contacts: 0,
            energy: 0.0,
            total: Vec3::zeros(),
            reach: 0.0,
        }
    }

    /// The same contact law against a concave cylinder of `radius` about `axis` (see
    /// [`Surface::Cylinder`]).
    pub fn cylinder(mut self, radius: f64, axis: Vec3) -> Self {
        let axis = axis.normalize();
        self.surface = Surface::Cylinder {
            radius,
            axis: (axis - self.normal * self.normal.dot(&axis)).normalize(),
        };
        self
    }

    /// How far the surface can move along its normal before it reaches `p` (m; infinite where
    /// it never does).
    pub fn clearance(&self, p: &Vec3) -> f64 {
        let n = self.normal;
        match self.surface {
            Surface::Plane => n.dot(&(p - self.point)),
            Surface::Cylinder { radius, axis } => {
                // In the plane normal to the axis: a across, b along the normal, from the
                // axis; the surface moved by s reaches p when a² + (b − s)² = radius² on its
                // solid half (b − s < 0).
                let q = p - (self.point + n * radius);
                let a = axis.cross(&n).dot(&q);
                if a.abs() >= radius {
                    return f64::INFINITY;
                }
                n.dot(&q) + (radius * radius - a * a).sqrt()
            }
        }
    }

    /// Moves the surface along its normal until it touches the nearest of `points` without
    /// overlapping any.
    pub fn place_touching(&mut self, points: impl IntoIterator<Item = Vec3>) {
        let gap = points
            .into_iter()
            .map(|p| self.clearance(&p))
            .fold(f64::INFINITY, f64::min);
        if gap.is_finite() {
            self.point += self.normal * gap;
        }
    }

    /// Where element `i` (at `x`, turned by `r`) overlaps the surface most: the point, the
    /// depth (> 0) and the normal there (towards the element).
    fn overlap(
        &self,
        x: &Vec3,
        bound: f64,
        r: &nalgebra::Rotation3<f64>,
        shape: &Polyhedron,
    ) -> Option<(Vec3, f64, Vec3)> {
        let n = self.normal;
        match self.surface {
            Surface::Plane => {
                if n.dot(&(x - self.point)) > bound {
                    return None;
                }
                let deepest = x + r * shape.support(&r.inverse_transform_vector(&(-n)));
                let depth = -n.dot(&(deepest - self.point));
                (depth > 0.0).then_some((deepest, depth, n))
            }
            Surface::Cylinder { radius, axis } => {
                let centre = self.point + n * radius;
                let off_axis = |p: &Vec3| {
                    let q = p - centre;
                    q - axis * axis.dot(&q)
                };
                let q = off_axis(x);
                if q.norm() + bound <= radius || q.dot(&n) > bound {
                    return None;
                }
                let mut best: Option<(Vec3, f64, Vec3)> = None;
                for v in &shape.vertices {
                    let p = x + r * v;
                    let q = off_axis(&p);
                    let distance = q.norm();
                    let depth = distance - radius;
                    if q.dot(&n) < 0.0 && depth > best.map_or(0.0, |b| b.1) {
                        best = Some((p, depth, -q / distance));
                    }
                }
                best
            }
        }
    }

    pub fn accumulate(
        &mut self,
        bodies: &Bodies,
        shapes: &[Polyhedron],
        forces: &mut Forces,
        dt: f64,
    ) {
        let k = self.stiffness;
        let friction = !self.history.is_empty();
        let across = match self.surface {
            Surface::Plane => None,
            Surface::Cylinder { axis, .. } => Some(axis.cross(&self.normal)),
        };
        self.contacts = 0;
        self.energy = 0.0;
        self.total = Vec3::zeros();
        self.reach = 0.0;
        for (i, shape) in shapes.iter().enumerate().take(bodies.len()) {
            let x = bodies.pos[i];
            let r = bodies.orientation[i].to_rotation_matrix();
            let Some((deepest, depth, n)) = self.overlap(&x, bodies.radius[i], &r, shape) else {
                if friction {
                    self.history[i] = Vec3::zeros();
                }
                continue;
            };
            self.contacts += 1;
            if let Some(t) = across {
                self.reach = self.reach.max(t.dot(&(deepest - self.point)).abs());
            }
            let fn_ = k * depth;
            let mut f = n * fn_;
            self.energy += 0.5 * k * depth * depth;
            if friction {
                let arm = deepest - x;
                let v = bodies.vel[i] + bodies.omega[i].cross(&arm) - self.velocity;
                let vt = v - n * n.dot(&v);
                let xi = &mut self.history[i];
                f += tangential_force(xi, &n, &vt, dt, k, self.friction * fn_);
                self.energy += 0.5 * k * xi.norm_squared();
            }
            forces.force[i] += f;
            forces.torque[i] += (deepest - x).cross(&f);
            self.total += f;
        }
    }
}

/// The contacts that cohesive contacts leave when they break (the `fracture` effect).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BrokenContacts {
    /// The element pairs, in the order they broke, with normal stiffness E S / L0 (the
    /// bond's in normal compression) and tangential stiffness k / (1 + ν) (its shear).
    pub pairs: Vec<[u32; 2]>,
    pub stiffness: Vec<f64>,
    pub history: Vec<Vec3>,
    pub friction: f64,
    pub shear_ratio: f64,
    /// Pairs touching in the last evaluation.
    pub touching: usize,
}

impl BrokenContacts {
    pub fn new(friction: f64, poisson: f64) -> Self {
        BrokenContacts {
            pairs: Vec::new(),
            stiffness: Vec::new(),
            history: Vec::new(),
            friction,
            shear_ratio: 1.0 / (1.0 + poisson),
            touching: 0,
        }
    }

    pub fn add(&mut self, pair: [u32; 2], stiffness: f64) {
        self.pairs.push(pair);
        self.stiffness.push(stiffness);
        self.history.push(Vec3::zeros());
    }

    pub fn accumulate(
        &mut self,
        bodies: &Bodies,
        shapes: &[Polyhedron],
        forces: &mut Forces,
        dt: f64,
    ) {
        self.touching = 0;
        for k in 0..self.pairs.len() {
            let [i, j] = self.pairs[k];
            let (i, j) = (i as usize, j as usize);
            let d = bodies.pos[j] - bodies.pos[i];
            if d.norm() > bodies.radius[i] + bodies.radius[j] {
                self.history[k] = Vec3::zeros();
                continue;
            }
            let a = Turned {
                shape: &shapes[i],
                rot: *bodies.orientation[i].to_rotation_matrix().matrix(),
            };
            let b = Turned {
                shape: &shapes[j],
                rot: *bodies.orientation[j].to_rotation_matrix().matrix(),
            };
            let pose = Pose::from_translation(Vector::new(d.x, d.y, d.z));
            let hit = contact_support_map_support_map(&pose, &a, &b, 0.0);
            let Some(c) = hit.filter(|c| c.dist < 0.0) else {
                self.history[k] = Vec3::zeros();
                continue;
            };
            self.touching += 1;
            let depth = -c.dist;
            let n = to_vec3(c.normal1);
            let point =
                0.5 * ((bodies.pos[i] + to_vec3(c.point1)) + (bodies.pos[j] + to_vec3(c.point2)));
            let kn = self.stiffness[k];
            // Force on j: pushed along n, away from i.
            let mut f = n * (kn * depth);
            if self.friction > 0.0 {
                let vj = bodies.vel[j] + bodies.omega[j].cross(&(point - bodies.pos[j]));
                let vi = bodies.vel[i] + bodies.omega[i].cross(&(point - bodies.pos[i]));
                let v = vj - vi;
                let vt = v - n * n.dot(&v);
                f += tangential_force(
                    &mut self.history[k],
                    &n,
                    &vt,
                    dt,
                    kn * self.shear_ratio,
                    self.friction * kn * depth,
                );
            }
            forces.force[j] += f;
            forces.force[i] -= f;
            forces.torque[j] += (point - bodies.pos[j]).cross(&f);
            forces.torque[i] -= (point - bodies.pos[i]).cross(&f);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    fn two_cubes(gap: f64) -> (Bodies, Vec<Polyhedron>) {
        let cube = Polyhedron::cuboid(Vec3::repeat(-0.5), Vec3::repeat(0.5));
        let mut b = Bodies::default();
        for x in [0.0, 1.0 + gap] {
            b.push_polyhedron(
                Vec3::new(x, 0.0, 0.0),
                1000.0,
                Vec3::repeat(1000.0 / 6.0),
                UnitQuaternion::identity(),
                0.75f64.sqrt(),
            );
        }
        (b, vec![cube.clone(), cube])
    }

    #[test]
    fn overlapping_cubes_push_apart_with_k_times_depth() {
        let (b, shapes) = two_cubes(-1e-3);
        let mut c = BrokenContacts::new(0.0, 0.25);
        c.add([0, 1], 2e9);
        let mut f = Forces::new(2);
        c.accumulate(&b, &shapes, &mut f, 1e-6);
        assert_eq!(c.touching, 1);
        assert!((f.force[1].x - 2e6).abs() < 1e-3, "{}", f.force[1]);
        assert!((f.force[0] + f.force[1]).norm() < 1e-9);
        // Apart: nothing.
        let (b, shapes) = two_cubes(1e-3);
        let mut f = Forces::new(2);
        c.accumulate(&b, &shapes, &mut f, 1e-6);
        assert_eq!(c.touching, 0);
        assert_eq!(f.force[1], Vec3::zeros());
    }

    #[test]
    fn sliding_contact_carries_at_most_mu_times_the_normal_force() {
        let (mut b, shapes) = two_cubes(-1e-3);
        b.vel[1] = Vec3::new(0.0, 0.5, 0.0);
        let mut c = BrokenContacts::new(0.4, 0.25);
        c.add([0, 1], 2e9);
        let mut f = Forces::new(2);
        // The spring reaches the Coulomb limit after μ Fn / (kt v dt) = 1000 steps.
        for step in 0..1500 {
            f.clear();
            c.accumulate(&b, &shapes, &mut f, 1e-6);
            let ft = f.force[1].y;
            assert!(ft <= 0.0, "friction opposes the sliding");
            assert!(-ft <= 0.4 * 2e6 * (1.0 + 1e-12));
            if step > 1100 {
                assert!(
                    (-ft / (0.4 * 2e6) - 1.0).abs() < 1e-9,
                    "sliding at the limit"
                );
            }
        }
    }

    #[test]
    fn a_cube_resting_on_the_ground_is_pushed_up_at_its_lowest_vertex() {
        let (mut b, shapes) = two_cubes(0.0);
        b.pos[0].z = 0.5 - 2e-3;
        b.pos[1].z = 5.0;
        let mut g = GroundContact::new(Vec3::zeros(), Vec3::z(), 1e6, 0.0, 2);
        let mut f = Forces::new(2);
        g.accumulate(&b, &shapes, &mut f, 1e-4);
        assert_eq!(g.contacts, 1);
        assert!((f.force[0].z - 2e3).abs() < 1e-6);
        assert!((g.energy - 0.5 * 1e6 * 4e-6).abs() < 1e-12);
    }

    #[test]
    fn a_cube_in_a_concave_cylinder_is_pushed_at_its_vertex_farthest_from_the_axis() {
        // A cradle of radius 10 about the z axis through (0, 10, 0), its lowest line at the
        // origin; a unit cube whose bottom face lies 2 mm below that line touches at the
        // corners of that face, which lie farthest from the axis.
        let (mut b, shapes) = two_cubes(0.0);
        b.pos[0].y = 0.5 - 2e-3;
        b.pos[1].y = 5.0;
        let k = 1e6;
        let mut g =
            GroundContact::new(Vec3::zeros(), Vec3::y(), k, 0.0, 2).cylinder(10.0, Vec3::z());
        let mut f = Forces::new(2);
        g.accumulate(&b, &shapes, &mut f, 1e-4);
        assert_eq!(g.contacts, 1);
        // Either corner of the face's near edge or far edge (they tie): the one it chose.
        let side = -f.force[0].x.signum();
        let q = Vec3::new(0.5 * side, -2e-3 - 10.0, 0.0);
        let depth = q.norm() - 10.0;
        assert!((depth - 0.0144897).abs() < 1e-6, "{depth}");
        // Radial, towards the axis, k times the depth.
        let expected = -q / q.norm() * (k * depth);
        assert!(
            (f.force[0].xy() - expected.xy()).norm() < 1e-6,
            "{}",
            f.force[0]
        );
        assert_eq!(f.force[0].z, 0.0);
        assert!((g.reach - 0.5).abs() < 1e-12);
        assert!((g.total - f.force[0]).norm() < 1e-12);
        // Placed touching, the same cube meets the cylinder at a corner and no deeper.
        let vertices: Vec<Vec3> = shapes[0].vertices.iter().map(|v| b.pos[0] + v).collect();
        let mut h = GroundContact::new(Vec3::new(0.0, -1.0, 0.0), Vec3::y(), k, 0.0, 2)
            .cylinder(10.0, Vec3::z());
        h.place_touching(vertices.iter().copied());
        let nearest = vertices
            .iter()
            .map(|p| h.clearance(p))
            .fold(f64::INFINITY, f64::min);
        assert!(nearest.abs() < 1e-12, "{nearest}");
        // Its lowest line lies below the corners by 10 − √(10² − 0.5²).
        assert!((h.point.y - (-2e-3 - 10.0 + (100.0f64 - 0.25).sqrt())).abs() < 1e-12);
        let mut f = Forces::new(2);
        h.accumulate(&b, &shapes, &mut f, 1e-4);
        assert!(f.force[0].norm() < 1e-6, "{}", f.force[0]);
        // A plane's clearance is the signed distance.
        let plane = GroundContact::new(Vec3::new(0.0, 1.0, 0.0), -Vec3::y(), k, 0.0, 2);
        assert_eq!(plane.clearance(&Vec3::new(3.0, 0.25, -2.0)), 0.75);
    }

    #[test]
    fn elements_carried_along_by_a_moving_surface_feel_no_friction() {
        // The tangential spring loads with the slip relative to the surface, not with the
        // element's own velocity.
        let (mut b, shapes) = two_cubes(0.0);
        b.pos[0].z = 0.5 - 1e-3;
        b.pos[1].z = 5.0;
        b.vel[0] = Vec3::new(0.3, 0.0, 0.0);
        let mut g = GroundContact::new(Vec3::zeros(), Vec3::z(), 1e6, 0.5, 2);
        g.velocity = Vec3::new(0.3, 0.0, 0.0);
        let mut f = Forces::new(2);
        for _ in 0..100 {
            f.clear();
            g.accumulate(&b, &shapes, &mut f, 1e-4);
        }
        assert_eq!(f.force[0].xy(), nalgebra::Vector2::zeros());
        g.velocity = Vec3::zeros();
        f.clear();
        g.accumulate(&b, &shapes, &mut f, 1e-4);
        assert!(f.force[0].x < 0.0, "a fixed surface resists the slip");
    }
}
