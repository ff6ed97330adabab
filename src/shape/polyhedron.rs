//! Convex polyhedra: the Voronoi cells of the `dlsm` model. Geometry of the faces, mass
//! properties (volume, centroid, inertia tensor) by decomposition into tetrahedra, principal
//! axes, and the support map that GJK/EPA needs.

use nalgebra::{Matrix3, Rotation3, SymmetricEigen, UnitQuaternion};
use serde::{Deserialize, Serialize};

use crate::state::Vec3;

/// A convex polyhedron: vertices and faces, each face a loop of vertex indices that runs
/// counter-clockwise seen from outside.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Polyhedron {
    /// Vertices (m).
    pub vertices: Vec<Vec3>,
    /// Face k is `face_vertices[face_start[k]..face_start[k + 1]]`.
    pub face_start: Vec<u32>,
    pub face_vertices: Vec<u32>,
}

/// Area, outward unit normal and centroid of one face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceGeometry {
    pub area: f64,
    pub normal: Vec3,
    pub centroid: Vec3,
}

/// Volume, centroid and the inertia tensor about the centroid per unit density
/// (`∫ (|r|² I − r rᵀ) dV`, m⁵): multiply by the density for kg·m².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    pub volume: f64,
    pub centroid: Vec3,
    pub inertia: Matrix3<f64>,
}

impl Polyhedron {
    /// A polyhedron from its vertices and face loops. `inside` is a point strictly inside it
    /// (a Voronoi seed); faces are turned so that they run counter-clockwise from outside.
    pub fn from_faces(vertices: Vec<Vec3>, faces: &[Vec<u32>], inside: &Vec3) -> Polyhedron {
        let mut face_start = Vec::with_capacity(faces.len() + 1);
        let mut face_vertices = Vec::new();
        face_start.push(0);
        for f in faces {
            let n = newell_normal(&vertices, f);
            let c = f.iter().map(|&k| vertices[k as usize]).sum::<Vec3>() / f.len() as f64;
            if n.dot(&(c - inside)) < 0.0 {
                face_vertices.extend(f.iter().rev());
            } else {
                face_vertices.extend(f.iter());
            }
            face_start.push(face_vertices.len() as u32);
        }
        Polyhedron {
            vertices,
            face_start,
            face_vertices,
        }
    }

    /// An axis-aligned box [lo, hi].
    pub fn cuboid(lo: Vec3, hi: Vec3) -> Polyhedron {
        let corner = |k: u32| {
            Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            )
        };
        let vertices = (0..8).map(corner).collect();
        let faces = [
            vec![0, 2, 6, 4],
            vec![1, 3, 7, 5],
            vec![0, 1, 5, 4],
            vec![2, 3, 7, 6],
            vec![0, 1, 3, 2],
            vec![4, 5, 7, 6],
        ];
        Polyhedron::from_faces(vertices, &faces, &(0.5 * (lo + hi)))
    }

    pub fn face_count(&self) -> usize {
        self.face_start.len().saturating_sub(1)
    }

    /// The vertex indices of face `k`.
    pub fn face(&self, k: usize) -> &[u32] {
        &self.face_vertices[self.face_start[k] as usize..self.face_start[k + 1] as usize]
    }

    /// Area, outward normal and centroid of face `k` (a fan of triangles from its first
    /// vertex; exact for planar faces).
    pub fn face_geometry(&self, k: usize) -> FaceGeometry {
        let f = self.face(k);
        let v0 = self.vertices[f[0] as usize];
        let mut twice_area = Vec3::zeros();
        let mut moment = Vec3::zeros();
        let mut weight = 0.0;
        for w in f[1..].windows(2) {
            let (a, b) = (self.vertices[w[0] as usize], self.vertices[w[1] as usize]);
            let t = (a - v0).cross(&(b - v0));
            let wt = t.norm();
            twice_area += t;
            moment += (v0 + a + b) * (wt / 3.0);
            weight += wt;
        }
        let area = 0.5 * twice_area.norm();
        FaceGeometry {
            area,
            normal: if area > 0.0 {
                twice_area / (2.0 * area)
            } else {
                Vec3::zeros()
            },
            centroid: if weight > 0.0 { moment / weight } else { v0 },
        }
    }

    /// Volume, centroid and inertia tensor (per unit density, about the centroid), from the
    /// tetrahedra that join a reference vertex to every face triangle:
    /// `∫ r rᵀ dV = V/20 (Σ vᵢvᵢᵀ + (Σ vᵢ)(Σ vᵢ)ᵀ)` over the four corners of each.
    pub fn mass_properties(&self) -> MassProperties {
        let o = self.vertices.first().copied().unwrap_or_else(Vec3::zeros);
        let mut volume = 0.0;
        let mut first = Vec3::zeros();
        let mut second = Matrix3::zeros();
        for k in 0..self.face_count() {
            let f = self.face(k);
            let a = self.vertices[f[0] as usize] - o;
            for w in f[1..].windows(2) {
                let b = self.vertices[w[0] as usize] - o;
                let c = self.vertices[w[1] as usize] - o;
                let v = a.dot(&b.cross(&c)) / 6.0;
                let s = a + b + c;
                volume += v;
                first += s * (v / 4.0);
                second +=
                    (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose())
                        * (v / 20.0);
            }
        }
        let g = first / volume;
        let about_centroid = second - g * g.transpose() * volume;
        let inertia = Matrix3::identity() * about_centroid.trace() - about_centroid;
        MassProperties {
            volume,
            centroid: g + o,
            inertia,
        }
    }

    /// The vertex farthest along `dir` (the support point).
    #[inline]
    pub fn support(&self, dir: &Vec3) -> Vec3 {
        let mut best = self.vertices[0];
        let mut d = best.dot(dir);
        for v in &self.vertices[1..] {
            let e = v.dot(dir);
            if e > d {
                d = e;
                best = *v;
            }
        }
        best
    }

    /// The largest distance from `point` to a vertex.
    pub fn bounding_radius(&self, point: &Vec3) -> f64 {
        self.vertices
            .iter()
            .map(|v| (v - point).norm())
            .fold(0.0, f64::max)
    }

    /// The same polyhedron with every vertex mapped by `f` (a rigid motion keeps it valid).
    pub fn mapped(&self, f: impl Fn(&Vec3) -> Vec3) -> Polyhedron {
        Polyhedron {
            vertices: self.vertices.iter().map(f).collect(),
            face_start: self.face_start.clone(),
            face_vertices: self.face_vertices.clone(),
        }
    }
}

/// Newell's normal of a polygon (twice its vector area).
fn newell_normal(vertices: &[Vec3], f: &[u32]) -> Vec3 {
    let mut n = Vec3::zeros();
    for k in 0..f.len() {
        let a = vertices[f[k] as usize];
        let b = vertices[f[(k + 1) % f.len()] as usize];
        n += a.cross(&b);
    }
    n
}

/// Principal moments (ascending) and the rotation from the principal frame to the frame of
/// `inertia` (a proper rotation).
pub fn principal_axes(inertia: &Matrix3<f64>) -> (Vec3, UnitQuaternion<f64>) {
    let eig = SymmetricEigen::new(*inertia);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let mut axes = Matrix3::zeros();
    let mut moments = Vec3::zeros();
    for (col, &k) in order.iter().enumerate() {
        axes.set_column(col, &eig.eigenvectors.column(k));
        moments[col] = eig.eigenvalues[k];
    }
    if axes.determinant() < 0.0 {
        let c = -axes.column(2);
        axes.set_column(2, &c);
    }
    let rotation = Rotation3::from_matrix_unchecked(axes);
    (moments, UnitQuaternion::from_rotation_matrix(&rotation))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_mass_properties_match_closed_form() {
        let (a, b, c) = (2.0, 3.0, 5.0);
        let p = Polyhedron::cuboid(Vec3::new(1.0, -1.0, 0.5), Vec3::new(1.0 + a, 2.0, 5.5));
        let m = p.mass_properties();
        let v = a * b * c;
        assert!((m.volume - v).abs() < 1e-12);
        assert!((m.centroid - Vec3::new(2.0, 0.5, 3.0)).norm() < 1e-12);
        let want = Matrix3::from_diagonal(&Vec3::new(
            v * (b * b + c * c) / 12.0,
            v * (a * a + c * c) / 12.0,
            v * (a * a + b * b) / 12.0,
        ));
        assert!(
            (m.inertia - want).norm() < 1e-10 * want.norm(),
            "{}",
            m.inertia
        );
        for k in 0..6 {
            let g = p.face_geometry(k);
            // Outward: the normal points away from the box centre.
            assert!(g.normal.dot(&(g.centroid - m.centroid)) > 0.0);
        }
        let total: f64 = (0..6).map(|k| p.face_geometry(k).area).sum();
        assert!((total - 2.0 * (a * b + b * c + a * c)).abs() < 1e-12);
    }

    #[test]
    fn tetrahedron_inertia_about_centroid() {
        // Unit right tetrahedron: V = 1/6, centroid (1/4, 1/4, 1/4); products of inertia
        // about the origin are V/20 per pair, so about the centroid
        // Ixx = 2 (V/10 - V/16) = 3V/40 and Ixy = V/16 - V/20 = V/80.
        let verts = vec![Vec3::zeros(), Vec3::x(), Vec3::y(), Vec3::z()];
        let faces = vec![vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]];
        let p = Polyhedron::from_faces(verts, &faces, &Vec3::repeat(0.2));
        let m = p.mass_properties();
        let v = 1.0 / 6.0;
        assert!((m.volume - v).abs() < 1e-15);
        assert!((m.centroid - Vec3::repeat(0.25)).norm() < 1e-15);
        assert!((m.inertia[(0, 0)] - 3.0 * v / 40.0).abs() < 1e-15);
        assert!((m.inertia[(0, 1)] - v / 80.0).abs() < 1e-15);
        let (moments, q) = principal_axes(&m.inertia);
        let r = q.to_rotation_matrix();
        let diag = r.matrix().transpose() * m.inertia * r.matrix();
        assert!((diag - Matrix3::from_diagonal(&moments)).norm() < 1e-15);
        assert!(moments[0] <= moments[1] && moments[1] <= moments[2]);
    }

    #[test]
    fn support_point_is_the_farthest_vertex() {
        let p = Polyhedron::cuboid(Vec3::zeros(), Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(
            p.support(&Vec3::new(1.0, -1.0, 0.1)),
            Vec3::new(1.0, 0.0, 3.0)
        );
        assert!((p.bounding_radius(&Vec3::new(0.5, 1.0, 1.5)) - 14f64.sqrt() / 2.0).abs() < 1e-15);
    }
}
