//! Rigid planar walls and moving platens.

use serde::{Deserialize, Serialize};

use super::Vec3;

/// An infinite rigid plane. `normal` is a unit vector pointing into the region the bodies
/// occupy; `velocity` moves the plane rigidly.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Wall {
    pub label: String,
    pub point: Vec3,
    pub normal: Vec3,
    pub velocity: Vec3,
    /// Force exerted by the bodies on the wall during the last step (N).
    pub force: Vec3,
    /// Sum of the normal contact stiffnesses on the wall during the last step (N/m); servo
    /// controllers use it to choose a stable wall speed.
    pub stiffness: f64,
    /// Number of bodies touching the wall during the last step.
    pub contacts: usize,
}

impl Wall {
    pub fn new(label: &str, point: Vec3, normal: Vec3) -> Self {
        Wall {
            label: label.to_string(),
            point,
            normal: normal.normalize(),
            velocity: Vec3::zeros(),
            force: Vec3::zeros(),
            stiffness: 0.0,
            contacts: 0,
        }
    }

    /// Signed distance from the plane to `x`, positive on the bodies' side.
    #[inline]
    pub fn distance(&self, x: &Vec3) -> f64 {
        plane_distance(&self.point, &self.normal, x)
    }

    /// Compressive normal force on the wall (N): positive when the bodies push it outwards.
    pub fn normal_force(&self) -> f64 {
        -self.force.dot(&self.normal)
    }
}

/// Signed distance from the plane through `point` with unit normal `normal` to `x` (m),
/// positive on the side the normal points to.
#[inline(always)]
pub fn plane_distance(point: &Vec3, normal: &Vec3, x: &Vec3) -> f64 {
    (x - point).dot(normal)
}

/// Faces of a rectangular box, in the order the box walls are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoxFace {
    XMin = 0,
    XMax = 1,
    YMin = 2,
    YMax = 3,
    ZMin = 4,
    ZMax = 5,
}

impl BoxFace {
    /// The six faces, in their order.
    pub const ALL: [BoxFace; 6] = [
        BoxFace::XMin,
        BoxFace::XMax,
        BoxFace::YMin,
        BoxFace::YMax,
        BoxFace::ZMin,
        BoxFace::ZMax,
    ];
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Walls {
    pub walls: Vec<Wall>,
    /// True when `walls` are the six faces of a box, in [`BoxFace`] order.
    pub is_box: bool,
}

impl Walls {
    /// The six walls of the box [lo, hi], normals pointing inwards.
    pub fn new_box(lo: Vec3, hi: Vec3) -> Self {
        let walls = vec![
            Wall::new("x-", lo, Vec3::x()),
            Wall::new("x+", hi, -Vec3::x()),
            Wall::new("y-", lo, Vec3::y()),
            Wall::new("y+", hi, -Vec3::y()),
            Wall::new("z-", lo, Vec3::z()),
            Wall::new("z+", hi, -Vec3::z()),
        ];
        Walls {
            walls,
            is_box: true,
        }
    }

    pub fn len(&self) -> usize {
        self.walls.len()
    }

    /// Whether every wall's point, normal, velocity and force are finite (a restored state
    /// is checked before it is stepped); the first that is not, named.
    pub fn check_values(&self) -> std::result::Result<(), String> {
        for w in &self.walls {
            let finite = [w.point, w.normal, w.velocity, w.force]
                .iter()
                .all(|v| v.iter().all(|x| x.is_finite()))
                && w.stiffness.is_finite();
            if !finite {
                return Err(format!("wall {} has a non-finite value", w.label));
            }
        }
        Ok(())
    }

    pub fn is_empty(&self) -> bool {
        self.walls.is_empty()
    }

    pub fn face(&self, f: BoxFace) -> &Wall {
        debug_assert!(self.is_box);
        &self.walls[f as usize]
    }

    pub fn face_mut(&mut self, f: BoxFace) -> &mut Wall {
        debug_assert!(self.is_box);
        &mut self.walls[f as usize]
    }

    /// Edge lengths of the box (m).
    pub fn box_size(&self) -> Vec3 {
        Vec3::new(
            self.face(BoxFace::XMax).point.x - self.face(BoxFace::XMin).point.x,
            self.face(BoxFace::YMax).point.y - self.face(BoxFace::YMin).point.y,
            self.face(BoxFace::ZMax).point.z - self.face(BoxFace::ZMin).point.z,
        )
    }

    /// Compressive normal stress on a box face (Pa): normal force over the face's current area.
    pub fn face_stress(&self, f: BoxFace) -> f64 {
        let l = self.box_size();
        let area = match f {
            BoxFace::XMin | BoxFace::XMax => l.y * l.z,
            BoxFace::YMin | BoxFace::YMax => l.x * l.z,
            BoxFace::ZMin | BoxFace::ZMax => l.x * l.y,
        };
        self.face(f).normal_force() / area
    }

    /// Moves every wall by its velocity over `dt`.
    pub fn advance(&mut self, dt: f64) {
        for w in &mut self.walls {
            w.point += w.velocity * dt;
        }
    }

    pub fn clear_forces(&mut self) {
        for w in &mut self.walls {
            w.force = Vec3::zeros();
            w.stiffness = 0.0;
            w.contacts = 0;
        }
    }
}
