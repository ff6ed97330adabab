//! One pair's contact: the per-contact core of the granular contact effect (which the run,
//! compaction and fracture evaluate forces with) and of the C ABI's kernels, so that both
//! compute the same bits. [`pair_contact`] between two bodies and
//! [`wall_contact`] against a wall evaluate the Hertz–Mindlin law ([`super::hertz_mindlin`])
//! on the geometry the convex narrow phase finds ([`super::convex`]; spheres by the sphere
//! formula), with what a pair remembers between evaluations ([`PairMemory`]); the bodies come
//! as [`ContactBody`]s, the run's arrays in place ([`BodyAt`]) or one [`Body`] ([`BodyView`]).
//! The separated pairs' skip ([`travel_step`], [`pair_reach`], [`skips`]) lets a pair found
//! apart go unsearched until its bodies could have met.

use nalgebra::{Matrix3, UnitQuaternion};

use super::convex::{self, Placed};
use super::hertz_mindlin::{ContactForce, KernelConsts, hertz_mindlin};
use crate::shape::Shape;
use crate::state::{Bodies, Body, Sleeve, Vec3, plane_distance, radial, shape_placement};
/// One contact's force on body i (the first body of a pair; the body against a wall) and the
/// torques on i and j, and what a record keeps of it. j receives the opposite force.
#[derive(Debug, Clone, Copy, Default)]
pub struct PairOut {
    /// Force on i (N).
    pub force: Vec3,
    /// Torques on i and j about their centres of mass (N·m); zero without friction on
    /// spheres. Against a wall `torque_j` is zero.
    pub torque_i: Vec3,
    pub torque_j: Vec3,
    /// Contact point (m) and unit normal from j (or the wall) to i.
    pub point: Vec3,
    pub normal: Vec3,
    pub c: ContactOut,
}

/// The scalar results of the kernel a record keeps.
#[derive(Debug, Clone, Copy, Default)]
pub struct ContactOut {
    /// Normal force (N), its elastic (Hertz) part (N), Hertz contact radius (m), normal
    /// stiffness 2 E* a (N/m), stored elastic energy (J) and the energy damping and sliding
    /// dissipated in the step (J).
    pub normal_force: f64,
    pub hertz_force: f64,
    pub radius: f64,
    pub stiffness: f64,
    pub energy: f64,
    pub dissipated: f64,
}

impl From<&ContactForce> for ContactOut {
    #[inline(always)]
    fn from(c: &ContactForce) -> Self {
        ContactOut {
            normal_force: c.normal_force,
            hertz_force: c.hertz_force,
            radius: c.radius,
            stiffness: c.stiffness,
            energy: c.elastic_energy,
            dissipated: c.dissipated,
        }
    }
}

/// What a pair slot remembers between evaluations (POLY): the last contact normal, which
/// warm-starts the search, and the Hertz radius held since the contact formed (0 while the
/// bodies do not touch).
///
/// The radius is the local one (principal curvatures at the contact point) when the contact
/// forms, and is held until the bodies part. Re-reading it at every step would make the force
/// non-conservative: a poly-ellipsoid's curvature jumps where octants meet (its surface is
/// C¹, not C²), and a contact resting on such a seam (a grain tip on a platen) gained energy
/// at every crossing (0.41 J against 2.4 mJ of platen work in the crushing scene); with the
/// radius held, `F = 4/3 E* √R δ^{3/2}` derives from a potential for the contact's life.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairMemory {
    /// The last contact normal (zero before the first contact).
    pub normal: Vec3,
    /// The held Hertz radius (m), 0 while the bodies do not touch.
    pub radius: f64,
}

/// The held Hertz radius: the current local one when the contact forms.
#[inline(always)]
fn held_radius(memory: &mut f64, local: f64) -> f64 {
    if *memory <= 0.0 {
        *memory = local;
    }
    *memory
}

/// A body's shape placed in the world for one evaluation (POLY variant): the world octant
/// origin (m) and the shape-to-world rotation.
#[derive(Debug, Clone, Copy)]
pub struct Placement {
    pub origin: Vec3,
    pub rot: Matrix3<f64>,
}

impl Placement {
    /// The placement of a body of shape `shape` at `pos` turned by `orientation` (body to
    /// world), as [`Bodies::shape_placement`] places it.
    #[inline]
    pub fn of(pos: &Vec3, orientation: &UnitQuaternion<f64>, shape: &Shape) -> Self {
        let (origin, q) = shape_placement(pos, orientation, shape);
        Placement {
            origin,
            rot: q.to_rotation_matrix().into_inner(),
        }
    }
}

/// A body as the contact kernels ([`pair_contact`], [`wall_contact`]) read it. The run reads
/// its arrays in place ([`BodyAt`]); the C ABI hands over one [`Body`] ([`BodyView`]).
pub trait ContactBody {
    /// Centre of mass (m).
    fn pos(&self) -> Vec3;
    /// Velocity (m/s).
    fn vel(&self) -> Vec3;
    /// Angular velocity, world frame (rad/s).
    fn omega(&self) -> Vec3;
    /// Mass (kg).
    fn mass(&self) -> f64;
    /// Bounding radius (m); a sphere's radius.
    fn radius(&self) -> f64;
    fn is_sphere(&self) -> bool;
    /// The body as a convex shape in the world (needs its placement: POLY only).
    fn placed(&self) -> Placed<'_>;
}

/// A body of shape `shape` as a convex shape in the world: a sphere (and a dlsm polyhedron,
/// which never reaches the granular contact) by its bounding radius about `pos`, a
/// poly-ellipsoid by its `placement` (asked for only then).
#[inline(always)]
fn placed_shape(
    shape: &Shape,
    radius: f64,
    pos: Vec3,
    placement: impl FnOnce() -> Placement,
) -> Placed<'_> {
    match shape {
        // Polyhedra are dlsm elements, which never reach the granular contact.
        Shape::Sphere | Shape::Polyhedron => Placed::sphere(radius, pos),
        Shape::PolyEllipsoid { pe, .. } => {
            let p = placement();
            Placed::poly_ellipsoid(pe, p.origin, p.rot)
        }
    }
}

/// Body `i` of `bodies`, placed by `placements` (this evaluation's, one per body; empty
/// without POLY): how the run feeds the contact kernels.
#[derive(Debug, Clone, Copy)]
pub struct BodyAt<'a> {
    pub bodies: &'a Bodies,
    pub placements: &'a [Placement],
    pub i: usize,
}

impl ContactBody for BodyAt<'_> {
    #[inline(always)]
    fn pos(&self) -> Vec3 {
        self.bodies.pos[self.i]
    }
    #[inline(always)]
    fn vel(&self) -> Vec3 {
        self.bodies.vel[self.i]
    }
    #[inline(always)]
    fn omega(&self) -> Vec3 {
        self.bodies.omega[self.i]
    }
    #[inline(always)]
    fn mass(&self) -> f64 {
        self.bodies.mass[self.i]
    }
    #[inline(always)]
    fn radius(&self) -> f64 {
        self.bodies.radius[self.i]
    }
    #[inline(always)]
    fn is_sphere(&self) -> bool {
        self.bodies.shape[self.i].is_sphere()
    }
    #[inline(always)]
    fn placed(&self) -> Placed<'_> {
        let i = self.i;
        placed_shape(
            &self.bodies.shape[i],
            self.bodies.radius[i],
            self.bodies.pos[i],
            || self.placements[i],
        )
    }
}

/// One [`Body`] with its placement: how the C ABI feeds the contact kernels.
#[derive(Debug, Clone, Copy)]
pub struct BodyView<'a> {
    pub body: &'a Body,
    pub placement: Placement,
}

impl<'a> BodyView<'a> {
    /// `body`, placed as the run places its bodies (the contact effect,
    /// [`HertzContact`](crate::effects::contact::HertzContact), places every body once per
    /// evaluation by [`Placement::of`]).
    pub fn new(body: &'a Body) -> Self {
        BodyView {
            body,
            placement: Placement::of(&body.pos, &body.orientation, &body.shape),
        }
    }
}

impl ContactBody for BodyView<'_> {
    #[inline(always)]
    fn pos(&self) -> Vec3 {
        self.body.pos
    }
    #[inline(always)]
    fn vel(&self) -> Vec3 {
        self.body.vel
    }
    #[inline(always)]
    fn omega(&self) -> Vec3 {
        self.body.omega
    }
    #[inline(always)]
    fn mass(&self) -> f64 {
        self.body.mass
    }
    #[inline(always)]
    fn radius(&self) -> f64 {
        self.body.radius
    }
    #[inline(always)]
    fn is_sphere(&self) -> bool {
        self.body.shape.is_sphere()
    }
    #[inline(always)]
    fn placed(&self) -> Placed<'_> {
        placed_shape(&self.body.shape, self.body.radius, self.body.pos, || {
            self.placement
        })
    }
}

/// The force of the pair (a, b) on a, or None when the bodies do not overlap: the whole
/// per-pair kernel of the contact effect (bounding-sphere rejection; the sphere formula, or
/// with `POLY` for a pair that is not two spheres the convex contact warm-started from the
/// pair's last normal in `memory`, with the Hertz radius held there; Hertz–Mindlin; torques,
/// point and normal). `hist` is the pair's tangential displacement (FRIC), `memory` what the
/// pair remembers (POLY); `update` is false only for the force evaluation before the first
/// step. m* is `m_a m_b / (m_a + m_b)` (read only with DAMP).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn pair_contact<const DAMP: bool, const FRIC: bool, const POLY: bool>(
    k: &KernelConsts,
    a: &impl ContactBody,
    b: &impl ContactBody,
    hist: &mut Vec3,
    memory: &mut PairMemory,
    dt: f64,
    update: bool,
) -> Option<PairOut> {
    pair_contact_or_gap::<DAMP, FRIC, POLY>(k, a, b, hist, memory, dt, update).ok()
}

/// [`pair_contact`], with the gap of a separated pair: `Err(gap)` (m, >= 0) where the bodies do
/// not touch and stay apart while their centroids' translations plus their bounding radii
/// times their rotation angles add up to less than `gap` ([`convex::contact_or_gap`]; the
/// bounding spheres' clearance for a pair whose bounding spheres are apart; 0 for two spheres
/// in reach, whose test is cheap anyway).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn pair_contact_or_gap<const DAMP: bool, const FRIC: bool, const POLY: bool>(
    k: &KernelConsts,
    a: &impl ContactBody,
    b: &impl ContactBody,
    hist: &mut Vec3,
    memory: &mut PairMemory,
    dt: f64,
    update: bool,
) -> std::result::Result<PairOut, f64> {
    let (ri, rj) = (a.radius(), b.radius());
    if bounds_apart(&a.pos(), ri, &b.pos(), rj) {
        forget(hist, &mut memory.radius, FRIC, POLY);
        return Err((a.pos() - b.pos()).norm() - (ri + rj));
    }
    let d = a.pos() - b.pos();
    let rsum = ri + rj;
    let r2 = d.norm_squared();
    let m_eff = if DAMP {
        let (mi, mj) = (a.mass(), b.mass());
        mi * mj / (mi + mj)
    } else {
        0.0
    };
    if POLY && !(a.is_sphere() && b.is_sphere()) {
        let guess = if memory.normal == Vec3::zeros() {
            d
        } else {
            memory.normal
        };
        let g = match convex::contact_or_gap(&a.placed(), &b.placed(), &guess) {
            Ok(g) => g,
            Err(gap) => {
                forget(hist, &mut memory.radius, FRIC, POLY);
                return Err(gap);
            }
        };
        memory.normal = g.normal;
        let r_eff = held_radius(&mut memory.radius, g.r_eff);
        let (ci, cj) = (g.point - a.pos(), g.point - b.pos());
        let v = a.vel() + a.omega().cross(&ci) - b.vel() - b.omega().cross(&cj);
        let c =
            hertz_mindlin::<DAMP, FRIC>(k, &g.normal, g.depth, r_eff, m_eff, &v, hist, dt, update);
        return Ok(PairOut {
            force: c.force,
            torque_i: ci.cross(&c.force),
            torque_j: -cj.cross(&c.force),
            point: g.point,
            normal: g.normal,
            c: ContactOut::from(&c),
        });
    }
    let r = r2.sqrt();
    let n = if r > 0.0 { d / r } else { Vec3::z() };
    let delta = rsum - r;
    let r_eff = ri * rj / rsum;
    let (di, dj) = (ri - 0.5 * delta, rj - 0.5 * delta);
    let mut v = a.vel() - b.vel();
    if FRIC {
        v -= (a.omega() * di + b.omega() * dj).cross(&n);
    }
    let c = hertz_mindlin::<DAMP, FRIC>(k, &n, delta, r_eff, m_eff, &v, hist, dt, update);
    let (torque_i, torque_j) = if FRIC {
        let nxf = n.cross(&c.force);
        (nxf * (-di), nxf * (-dj))
    } else {
        (Vec3::zeros(), Vec3::zeros())
    };
    Ok(PairOut {
        force: c.force,
        torque_i,
        torque_j,
        point: a.pos() - n * di,
        normal: n,
        c: ContactOut::from(&c),
    })
}

/// True when the bounding spheres of bodies at `pa` and `pb` (radii `ra`, `rb`, m) do not
/// overlap: then [`pair_contact`] finds no contact and only [`forget`]s. Hosts that call the
/// kernels per candidate (the C ABI) test this first and skip the rest.
#[inline(always)]
pub fn bounds_apart(pa: &Vec3, ra: f64, pb: &Vec3, rb: f64) -> bool {
    let rsum = ra + rb;
    (pa - pb).norm_squared() >= rsum * rsum
}

/// True when the bounding sphere of a body at `pos` (radius `r`, m) does not reach the wall
/// through `wall_point` of unit normal `wall_normal`: then [`wall_contact`] finds no contact
/// and only [`forget`]s (a poly-ellipsoid lies inside its bounding sphere; for a sphere it is
/// the overlap test itself).
#[inline(always)]
pub fn bound_off_wall(pos: &Vec3, r: f64, wall_normal: &Vec3, wall_point: &Vec3) -> bool {
    plane_distance(wall_point, wall_normal, pos) >= r
}

/// What a pair (or a body and a wall) forgets when they do not touch: the tangential
/// displacement `hist` (with friction) and the held Hertz radius (with poly-ellipsoids). The
/// last normal is kept: it warm-starts the next contact search.
#[inline(always)]
pub fn forget(hist: &mut Vec3, held_radius: &mut f64, friction: bool, poly: bool) {
    if friction {
        *hist = Vec3::zeros();
    }
    if poly {
        *held_radius = 0.0;
    }
}

/// The force of the wall through `wall_point` (unit normal `wall_normal` into the bodies'
/// side, moving at `wall_velocity`) on body a, or None when they do not touch: the
/// per-candidate kernel of the contact effect's wall loop (with `POLY` a poly-ellipsoid's
/// closed-form wall contact, with the Hertz radius held in `held`; else the sphere's).
/// `hist` is the candidate's tangential displacement (FRIC). The wall receives the opposite
/// force; `torque_j` is zero.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn wall_contact<const DAMP: bool, const FRIC: bool, const POLY: bool>(
    k: &KernelConsts,
    a: &impl ContactBody,
    wall_normal: &Vec3,
    wall_point: &Vec3,
    wall_velocity: &Vec3,
    hist: &mut Vec3,
    held: &mut f64,
    dt: f64,
    update: bool,
) -> Option<PairOut> {
    let r = a.radius();
    let n = *wall_normal;
    // Lever from the centre to the contact point, overlap, Hertz radius.
    let (lever, delta, r_eff) = if POLY && !a.is_sphere() {
        match convex::wall_contact(&a.placed(), &n, wall_point) {
            Some(g) => (g.point - a.pos(), g.depth, held_radius(held, g.r_eff)),
            None => (Vec3::zeros(), 0.0, 0.0),
        }
    } else {
        let delta = r - plane_distance(wall_point, &n, &a.pos());
        (n * (delta - r), delta, r)
    };
    surface_force::<DAMP, FRIC, POLY>(
        k,
        a,
        &n,
        lever,
        delta,
        r_eff,
        wall_velocity,
        hist,
        held,
        dt,
        update,
    )
}

/// The force of a rigid surface (a wall, the sleeve) moving at `surface_velocity` on body a,
/// touching it at `lever` from its centre with overlap `delta` along the unit normal `n` (out
/// of the surface) and Hertz radius `r_eff`, or None (the memory forgotten) when `delta <= 0`:
/// the Hertz–Mindlin law and the torque, shared by [`wall_contact`] and [`sleeve_contact`].
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn surface_force<const DAMP: bool, const FRIC: bool, const POLY: bool>(
    k: &KernelConsts,
    a: &impl ContactBody,
    n: &Vec3,
    lever: Vec3,
    delta: f64,
    r_eff: f64,
    surface_velocity: &Vec3,
    hist: &mut Vec3,
    held: &mut f64,
    dt: f64,
    update: bool,
) -> Option<PairOut> {
    if delta <= 0.0 {
        forget(hist, held, FRIC, POLY);
        return None;
    }
    let mut v = a.vel() - surface_velocity;
    if FRIC || POLY {
        v += a.omega().cross(&lever);
    }
    let c = hertz_mindlin::<DAMP, FRIC>(k, n, delta, r_eff, a.mass(), &v, hist, dt, update);
    Some(PairOut {
        force: c.force,
        torque_i: if FRIC || POLY {
            lever.cross(&c.force)
        } else {
            Vec3::zeros()
        },
        torque_j: Vec3::zeros(),
        point: a.pos() + lever,
        normal: *n,
        c: ContactOut::from(&c),
    })
}

/// True when the bounding sphere of a body at `pos` (radius `r`, m) does not reach the
/// sleeve: then [`sleeve_contact`] finds no contact and only [`forget`]s.
#[inline(always)]
pub fn bound_off_sleeve(pos: &Vec3, r: f64, sleeve: &Sleeve) -> bool {
    sleeve.distance(pos) >= r
}

/// The force of the sleeve (fixed, its axis along z) on body a, or None when they do not
/// touch: the per-candidate kernel of the contact effect's sleeve loop (with `POLY` a
/// poly-ellipsoid's contact by [`convex::sleeve_contact`], the Hertz radius held in `held`;
/// else the sphere's closed form, its Hertz radius that of a sphere in a concave cylinder,
/// [`convex::sleeve_hertz_radius`]). `hist` is the candidate's tangential displacement (FRIC).
/// The sleeve receives the opposite force.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn sleeve_contact<const DAMP: bool, const FRIC: bool, const POLY: bool>(
    k: &KernelConsts,
    a: &impl ContactBody,
    sleeve: &Sleeve,
    hist: &mut Vec3,
    held: &mut f64,
    dt: f64,
    update: bool,
) -> Option<PairOut> {
    let r = a.radius();
    let (n, lever, delta, r_eff) = if POLY && !a.is_sphere() {
        match convex::sleeve_contact(&a.placed(), &sleeve.centre, sleeve.radius) {
            Some(g) => (
                g.normal,
                g.point - a.pos(),
                g.depth,
                held_radius(held, g.r_eff),
            ),
            None => (Vec3::zeros(), Vec3::zeros(), 0.0, 0.0),
        }
    } else {
        let d = radial(&sleeve.centre, &a.pos());
        let rho = d.norm();
        let e = if rho > 0.0 { d / rho } else { Vec3::x() };
        let delta = rho + r - sleeve.radius;
        let r_eff = convex::sleeve_hertz_radius(r * r, r, sleeve.radius);
        (-e, e * (r - delta), delta, r_eff)
    };
    surface_force::<DAMP, FRIC, POLY>(
        k,
        a,
        &n,
        lever,
        delta,
        r_eff,
        &Vec3::zeros(),
        hist,
        held,
        dt,
        update,
    )
}

/// How far a body of bounding radius `radius` (m) may have moved, at most, from pose
/// (`from_pos`, `from_q`) to (`to_pos`, `to_q`): its centroid's path plus its bounding radius
/// (taken a millionth larger: it is an ascent's maximum) times a bound on the angle it turned
/// (m). The separated pairs' skip adds these up per body ("travel").
#[inline(always)]
pub fn travel_step(
    from_pos: &Vec3,
    from_q: &UnitQuaternion<f64>,
    to_pos: &Vec3,
    to_q: &UnitQuaternion<f64>,
    radius: f64,
) -> f64 {
    (to_pos - from_pos).norm() + radius * (1.0 + 1e-6) * turn_bound(from_q, to_q)
}

/// What a pair of bodies (bounding radii `ri`, `rj`, m) found apart by `gap` (m) when their
/// travels were `travel_i`, `travel_j` may skip: the sum of their travels must pass it before
/// they can touch, less a margin for round-off (m). A pair whose travels sum to no more than
/// its reach is not searched: the search would find it apart again ([`skips`]).
#[inline(always)]
pub fn pair_reach(travel_i: f64, travel_j: f64, gap: f64, ri: f64, rj: f64) -> f64 {
    travel_i + travel_j + gap * (1.0 - 1e-9) - 1e-12 * (ri + rj)
}

/// True when a pair of `reach` ([`pair_reach`]; 0: never found apart) need not be searched
/// with its bodies' travels now `travel_i`, `travel_j`.
#[inline(always)]
pub fn skips(reach: f64, travel_i: f64, travel_j: f64) -> bool {
    reach > travel_i + travel_j
}

/// A bound on the angle (rad) of the rotation from `from` to `to`: `2 asin(s)` with `s` the
/// length of the vector part of `to from⁻¹`, bounded by `2.0944 s` while `s <= 1/2`
/// (`asin(s)/s` grows from 1 to π/3 / (1/2) there), else π.
#[inline(always)]
fn turn_bound(from: &UnitQuaternion<f64>, to: &UnitQuaternion<f64>) -> f64 {
    let s = (to * from.inverse()).imag().norm();
    if s <= 0.5 {
        2.0944 * s
    } else {
        std::f64::consts::PI
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rotation bound behind the separated pairs' skip: never below the angle of the
    /// rotation from one orientation to the other, and close to it for small turns.
    #[test]
    fn turn_bound_bounds_the_angle_between_orientations() {
        let from = UnitQuaternion::from_euler_angles(0.3, -1.1, 2.0);
        for k in 0..=400 {
            let angle = std::f64::consts::PI * k as f64 / 400.0;
            let axis = Vec3::new((k as f64).sin(), 0.5, (0.3 * k as f64).cos()).normalize();
            let to = UnitQuaternion::from_scaled_axis(axis * angle) * from;
            let bound = turn_bound(&from, &to);
            assert!(bound >= angle * (1.0 - 1e-12), "{bound} below {angle}");
            if angle < 0.1 {
                assert!(bound <= 1.05 * angle + 1e-15, "{bound} far above {angle}");
            }
        }
    }
}
