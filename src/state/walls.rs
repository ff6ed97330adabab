//! Rigid planar walls and moving platens, and the sleeve: a rigid cylinder around the sample.

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

/// Axial slices of the sleeve over which its radial stress is resolved along the axis.
pub const SLEEVE_SLICES: usize = 10;

/// A rigid, fixed circular cylinder whose inside holds the bodies: the steel sleeve that
/// confines an SHPB specimen laterally. Its axis runs along z through `centre`; a box's two z
/// faces close it at either end (the bars' faces).
#[derive(Debug, Clone, PartialEq)]
pub struct Sleeve {
    /// A point of the axis (m); its z is not used.
    pub centre: Vec3,
    /// Inner radius (m).
    pub radius: f64,
    /// Force exerted by the bodies on the sleeve during the last step (N): the radial parts
    /// cancel round the axis; the axial part is what the sleeve's friction holds.
    pub force: Vec3,
    /// Sum of the contacts' normal (radial) forces on the sleeve during the last step (N),
    /// compression positive.
    pub load: f64,
    /// `load` by axial slice: [`SLEEVE_SLICES`] equal slices of the span between the box's
    /// two z faces, from z- up; a contact counts in the slice of its contact point (N).
    pub slices: [f64; SLEEVE_SLICES],
    /// Sum of the normal contact stiffnesses on the sleeve during the last step (N/m).
    pub stiffness: f64,
    /// Number of bodies touching the sleeve during the last step.
    pub contacts: usize,
}

impl Sleeve {
    /// The sleeve inscribed in the x–y section of the box `[lo, hi]` (whose x and y edges are
    /// equal): the diameter its x edge, the axis through the section's centre.
    pub fn inscribed(lo: Vec3, hi: Vec3) -> Self {
        Sleeve {
            centre: 0.5 * (lo + hi),
            radius: 0.5 * (hi.x - lo.x),
            force: Vec3::zeros(),
            load: 0.0,
            slices: [0.0; SLEEVE_SLICES],
            stiffness: 0.0,
            contacts: 0,
        }
    }

    /// Distance from `x` to the sleeve's surface (m), positive inside.
    #[inline]
    pub fn distance(&self, x: &Vec3) -> f64 {
        self.radius - radial(&self.centre, x).norm()
    }

    /// Mean radial (normal) stress on the sleeve (Pa) over its wetted length `height` (m):
    /// the summed normal forces over the inner area `2 π R h`.
    pub fn radial_stress(&self, height: f64) -> f64 {
        self.load / (2.0 * std::f64::consts::PI * self.radius * height)
    }

    /// The radial stress of each axial slice (Pa), from z- up, over the span `height` (m).
    pub fn radial_profile(&self, height: f64) -> [f64; SLEEVE_SLICES] {
        let area = 2.0 * std::f64::consts::PI * self.radius * height / SLEEVE_SLICES as f64;
        self.slices.map(|f| f / area)
    }

    fn clear_forces(&mut self) {
        self.force = Vec3::zeros();
        self.load = 0.0;
        self.slices = [0.0; SLEEVE_SLICES];
        self.stiffness = 0.0;
        self.contacts = 0;
    }
}

/// The part of `x - centre` across the z axis (m): from the sleeve's axis to `x`.
#[inline(always)]
pub fn radial(centre: &Vec3, x: &Vec3) -> Vec3 {
    Vec3::new(x.x - centre.x, x.y - centre.y, 0.0)
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Walls {
    pub walls: Vec<Wall>,
    /// True when `walls` are the six faces of a box, in [`BoxFace`] order.
    pub is_box: bool,
    /// The sleeve, when the scene asks for one (`walls.sleeve`): it confines the sample
    /// laterally in place of the box's four side faces, which then touch nothing (they stay,
    /// tangent to it, as the box's extent). Not saved with a sample or a state: it is the
    /// scene's, made from it at every build and restore ([`Walls::add_sleeve`]).
    #[serde(skip)]
    pub sleeve: Option<Sleeve>,
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
            sleeve: None,
        }
    }

    /// Puts the sleeve inscribed in the box's x–y section around the sample (the box's x and y
    /// edges are equal: the scene's checks see to it).
    pub fn add_sleeve(&mut self) {
        debug_assert!(self.is_box);
        let lo = Vec3::new(
            self.face(BoxFace::XMin).point.x,
            self.face(BoxFace::YMin).point.y,
            self.face(BoxFace::ZMin).point.z,
        );
        self.sleeve = Some(Sleeve::inscribed(lo, lo + self.box_size()));
    }

    /// Whether wall `w` can touch a body: with a sleeve, the box's four side faces cannot.
    #[inline]
    pub fn touches(&self, w: usize) -> bool {
        self.sleeve.is_none() || w >= BoxFace::ZMin as usize
    }

    /// The volume (m³) a box of edges `size` holds: with a sleeve, the cylinder inscribed in
    /// its x–y section.
    pub fn volume_of(&self, size: Vec3) -> f64 {
        match self.sleeve {
            Some(_) => 0.25 * std::f64::consts::PI * size.x * size.y * size.z,
            None => size.x * size.y * size.z,
        }
    }

    /// Bodies touching a wall or the sleeve during the last step (a body counts once per
    /// wall it touches).
    pub fn contacts(&self) -> usize {
        self.walls.iter().map(|w| w.contacts).sum::<usize>()
            + self.sleeve.as_ref().map_or(0, |s| s.contacts)
    }

    /// The size of a box of edges `size` (m) changed to hold `ratio` times its volume: alike
    /// in all directions, or with a sleeve along its axis only (the sleeve stays).
    pub fn resized(&self, size: Vec3, ratio: f64) -> Vec3 {
        match self.sleeve {
            Some(_) => Vec3::new(size.x, size.y, size.z * ratio),
            None => size * ratio.cbrt(),
        }
    }

    /// The volume (m³) the walls hold now ([`Walls::volume_of`] the box).
    pub fn volume(&self) -> f64 {
        self.volume_of(self.box_size())
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
    /// With a sleeve, a z face's area is the sleeve's section, and the side faces read the
    /// sleeve's mean radial stress (the lateral stress of the sample).
    pub fn face_stress(&self, f: BoxFace) -> f64 {
        let l = self.box_size();
        if let Some(s) = &self.sleeve {
            return match f {
                BoxFace::ZMin | BoxFace::ZMax => {
                    self.face(f).normal_force() / (std::f64::consts::PI * s.radius * s.radius)
                }
                _ => s.radial_stress(l.z),
            };
        }
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
        if let Some(s) = &mut self.sleeve {
            s.clear_forces();
        }
    }
}
