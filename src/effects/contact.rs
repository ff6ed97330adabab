//! The `contact` effect: Hertz normal force between spheres and against walls, with the
//! `damping` and `friction` effects folded into the same loop when the scene names them.
//!
//! With grains that are not all spheres (poly-ellipsoids, from fracture or from the sample),
//! the `POLY` variant finds the contact of a pair by [`crate::contact::convex`] (overlap,
//! common normal, contact point, Hertz radius from the local curvatures), warm-started from
//! the pair's last normal; sphere pairs still take the sphere formula. That variant also keeps
//! a record of every contact of the evaluation (forces, points, contact radii, stored and
//! dissipated energy) for the fracture criteria and the energy account. Scenes of spheres
//! without fracture build neither.
//!
//! One thread sums each pair's force straight into both bodies, pair slot by pair slot.
//! Several threads each own a fixed range of rows and sum into private accumulators that are
//! added up per body in a fixed order: for a given thread count, runs repeat bit for bit.

use std::ops::Range;

use nalgebra::{Matrix3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use super::{Effect, StepContext};
use crate::contact::convex::{self, Placed};
use crate::contact::hertz_mindlin::{
    ContactForce, Hertz, KernelConsts, Mindlin, ViscousDamping, hertz_mindlin,
};
use crate::contact::neighbor::{PairList, WallLists, transfer_pair_data, transfer_wall_data};
use crate::error::{Error, Result};
use crate::parallel::{on_team, split_ranges, team_blocks, team_size};
use crate::probe::modes::{Dof, MassScale, highest_eigenvalue, largest_motion};
use crate::shape::Shape;
use crate::state::{Bodies, Body, Forces, Vec3, Walls, plane_distance, shape_placement};

/// Parameters of the contact effect.
#[derive(Debug, Clone)]
pub struct ContactParams {
    pub hertz: Hertz,
    /// Present only with the `damping` effect.
    pub damping: Option<ViscousDamping>,
    /// Present only with the `friction` effect.
    pub mindlin: Option<Mindlin>,
    /// Friction coefficient against walls (default: that of `mindlin`).
    pub wall_friction: Option<f64>,
    /// Verlet skin (m); `None`: 0.4 × the smallest radius, chosen at the first build.
    pub skin: Option<f64>,
    /// Bodies other than spheres may take part (poly-ellipsoids): build the `POLY` variant,
    /// which also records every contact.
    pub shapes: bool,
}

/// Builds the contact effect with exactly the sub-models in `params`.
pub fn build_contact(params: ContactParams) -> Box<dyn Effect> {
    match (
        params.damping.is_some(),
        params.mindlin.is_some(),
        params.shapes,
    ) {
        (false, false, false) => Box::new(HertzContact::<false, false, false>::new(params)),
        (true, false, false) => Box::new(HertzContact::<true, false, false>::new(params)),
        (false, true, false) => Box::new(HertzContact::<false, true, false>::new(params)),
        (true, true, false) => Box::new(HertzContact::<true, true, false>::new(params)),
        (false, false, true) => Box::new(HertzContact::<false, false, true>::new(params)),
        (true, false, true) => Box::new(HertzContact::<true, false, true>::new(params)),
        (false, true, true) => Box::new(HertzContact::<false, true, true>::new(params)),
        (true, true, true) => Box::new(HertzContact::<true, true, true>::new(params)),
    }
}

/// `ContactRecord::j` of a contact with wall w: `WALL | w`.
pub const WALL: u32 = 1 << 31;

/// One contact of the last evaluation (POLY variant only), world frame.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
pub struct ContactRecord {
    pub i: u32,
    /// The other body, or `WALL | w` for wall w.
    pub j: u32,
    /// Contact point (m).
    pub point: Vec3,
    /// Unit normal from j to i.
    pub normal: Vec3,
    /// Force on i (N); j receives the opposite.
    pub force: Vec3,
    /// Normal force (N), its elastic (Hertz) part (N), and the Hertz contact radius (m).
    pub normal_force: f64,
    pub hertz_force: f64,
    pub radius: f64,
    /// Normal contact stiffness 2 E* a (N/m).
    pub stiffness: f64,
    /// Elastic energy stored in the contact (J).
    pub energy: f64,
}

impl ContactRecord {
    pub fn wall(&self) -> Option<usize> {
        (self.j & WALL != 0).then_some((self.j & !WALL) as usize)
    }
}

/// The contacts of the last evaluation and the energy damping and sliding dissipated in it.
#[derive(Debug, Clone, Default)]
pub struct ContactRecords {
    pub list: Vec<ContactRecord>,
    /// Energy dissipated by damping and sliding during the last evaluated step (J).
    pub dissipated: f64,
}

/// Below this many bodies per thread the pair loop runs on one thread even with a worker
/// team. Whether a step is worth the team at all (dense spheres below 1500 per thread are
/// not) is the model's decision, [`crate::run::Model::use_team`].
const PARALLEL_MIN_BODIES_PER_THREAD: usize = 100;

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

impl PairOut {
    fn record(&self, i: usize, j: u32) -> ContactRecord {
        ContactRecord {
            i: i as u32,
            j,
            point: self.point,
            normal: self.normal,
            force: self.force,
            normal_force: self.c.normal_force,
            hertz_force: self.c.hertz_force,
            radius: self.c.radius,
            stiffness: self.c.stiffness,
            energy: self.c.energy,
        }
    }
}

/// A thread's private sums of forces and torques over the bodies `range` (and, POLY, its
/// contact records and dissipated energy).
#[derive(Debug, Clone, Default)]
struct Accumulator {
    range: Range<usize>,
    force: Vec<Vec3>,
    torque: Vec<Vec3>,
    records: Vec<ContactRecord>,
    dissipated: f64,
}

impl Accumulator {
    fn new(range: Range<usize>) -> Self {
        let n = range.len();
        Accumulator {
            range,
            force: vec![Vec3::zeros(); n],
            torque: vec![Vec3::zeros(); n],
            records: Vec::new(),
            dissipated: 0.0,
        }
    }

    fn clear(&mut self) {
        self.force.fill(Vec3::zeros());
        self.torque.fill(Vec3::zeros());
        self.records.clear();
        self.dissipated = 0.0;
    }
}

/// Contact histories in a form independent of the neighbour list, for checkpoints: tangential
/// displacements and (POLY) the last contact normals that warm-start the next search.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct SavedHistory {
    pairs: Vec<(u32, u32, [f64; 3])>,
    walls: Vec<(u32, u32, [f64; 3])>,
    /// POLY: per pair, the last normal and the held Hertz radius (0: not in contact).
    normals: Vec<(u32, u32, [f64; 4])>,
    /// POLY: per wall candidate in contact, its held Hertz radius.
    wall_radii: Vec<(u32, u32, f64)>,
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
    /// `body`, placed as the run places its bodies ([`HertzContact`] places every body once
    /// per evaluation by [`Placement::of`]).
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
    if delta <= 0.0 {
        forget(hist, held, FRIC, POLY);
        return None;
    }
    let mut v = a.vel() - wall_velocity;
    if FRIC || POLY {
        v += a.omega().cross(&lever);
    }
    let c = hertz_mindlin::<DAMP, FRIC>(k, &n, delta, r_eff, a.mass(), &v, hist, dt, update);
    Some(PairOut {
        force: c.force,
        torque_i: if FRIC || POLY {
            lever.cross(&c.force)
        } else {
            Vec3::zeros()
        },
        torque_j: Vec3::zeros(),
        point: a.pos() + lever,
        normal: n,
        c: ContactOut::from(&c),
    })
}

pub struct HertzContact<const DAMP: bool, const FRIC: bool, const POLY: bool> {
    params: ContactParams,
    k: KernelConsts,
    /// Constants against walls (their own friction coefficient).
    k_wall: KernelConsts,
    pairs: PairList,
    wall_lists: WallLists,
    /// Tangential displacement per pair slot (empty without friction).
    pair_hist: Vec<Vec3>,
    /// Tangential displacement per wall candidate (empty without friction).
    wall_hist: Vec<Vec<Vec3>>,
    /// Parallel path: rows of each thread and their accumulators.
    chunks: Vec<Range<usize>>,
    accumulators: Vec<Accumulator>,
    chunk_threads: usize,
    pending: Option<SavedHistory>,
    contacts: usize,
    /// POLY: what each pair slot remembers (last normal, held Hertz radius), the placements
    /// of this evaluation and its records.
    pair_memory: Vec<PairMemory>,
    /// POLY: held Hertz radius per wall candidate (0: not in contact).
    wall_radius: Vec<Vec<f64>>,
    placements: Vec<Placement>,
    records: ContactRecords,
    /// POLY: how far each body has moved since the effect was made (m: its centroid's path
    /// plus its bounding radius times the angles it turned through), and its pose at the last
    /// evaluation.
    travel: Vec<f64>,
    last_pose: Vec<(Vec3, UnitQuaternion<f64>)>,
    /// POLY: per pair slot, the sum of the two bodies' travel below which they cannot touch
    /// (the travel when the pair was last found apart plus its gap); 0 when they must be
    /// searched. A pair below it is not searched: the search would find it apart again.
    pair_reach: Vec<f64>,
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

impl<const DAMP: bool, const FRIC: bool, const POLY: bool> HertzContact<DAMP, FRIC, POLY> {
    pub fn new(params: ContactParams) -> Self {
        let k = KernelConsts::new(
            &params.hertz,
            params.damping.as_ref(),
            params.mindlin.as_ref(),
        );
        let wall_mindlin = params.mindlin.map(|m| Mindlin {
            mu: params.wall_friction.unwrap_or(m.mu),
            ..m
        });
        let k_wall = KernelConsts::new(
            &params.hertz,
            params.damping.as_ref(),
            wall_mindlin.as_ref(),
        );
        HertzContact {
            k,
            k_wall,
            pairs: PairList::new(params.skin.unwrap_or(0.0)),
            params,
            wall_lists: WallLists::default(),
            pair_hist: Vec::new(),
            wall_hist: Vec::new(),
            chunks: Vec::new(),
            accumulators: Vec::new(),
            chunk_threads: 0,
            pending: None,
            contacts: 0,
            pair_memory: Vec::new(),
            wall_radius: Vec::new(),
            placements: Vec::new(),
            records: ContactRecords::default(),
            travel: Vec::new(),
            last_pose: Vec::new(),
            pair_reach: Vec::new(),
        }
    }

    /// Places every poly-ellipsoid in the world for this evaluation, and adds each body's
    /// motion since the last one to its travel (a body new since then starts from here).
    fn place(&mut self, bodies: &Bodies) {
        let n = bodies.len();
        self.placements.clear();
        self.placements.extend(
            (0..n).map(|i| Placement::of(&bodies.pos[i], &bodies.orientation[i], &bodies.shape[i])),
        );
        self.travel.resize(n, 0.0);
        self.last_pose.truncate(n);
        let known = self.last_pose.len();
        self.last_pose
            .extend((known..n).map(|i| (bodies.pos[i], bodies.orientation[i])));
        for (i, (x, q)) in self.last_pose.iter_mut().enumerate().take(known) {
            let (pos, orientation) = (&bodies.pos[i], &bodies.orientation[i]);
            self.travel[i] += travel_step(x, q, pos, orientation, bodies.radius[i]);
            *x = *pos;
            *q = *orientation;
        }
    }

    /// POLY: what a pair slot `s` of bodies `i`, `j` found apart by `gap` (m) may skip: the
    /// travel it must reach before it is searched again, less a margin for round-off.
    #[inline(always)]
    fn reach(&self, i: usize, j: usize, gap: f64, bodies: &Bodies) -> f64 {
        pair_reach(
            self.travel[i],
            self.travel[j],
            gap,
            bodies.radius[i],
            bodies.radius[j],
        )
    }

    fn rebuild_pairs(&mut self, bodies: &Bodies) {
        if self.pairs.skin <= 0.0 {
            self.pairs.skin = default_skin(bodies);
        }
        let (old_offsets, old_partners) = if FRIC || POLY {
            (
                std::mem::take(&mut self.pairs.offsets),
                std::mem::take(&mut self.pairs.partners),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        self.pairs.build(&bodies.pos, &bodies.radius);
        if FRIC {
            self.pair_hist =
                transfer_pair_data(&old_offsets, &old_partners, &self.pair_hist, &self.pairs);
        }
        if POLY {
            self.pair_memory =
                transfer_pair_data(&old_offsets, &old_partners, &self.pair_memory, &self.pairs);
            self.pair_reach =
                transfer_pair_data(&old_offsets, &old_partners, &self.pair_reach, &self.pairs);
        }
        self.chunk_threads = 0;
    }

    fn rebuild_walls(&mut self, bodies: &Bodies, walls: &Walls) {
        let old = std::mem::take(&mut self.wall_lists.candidates);
        self.wall_lists
            .build(walls, &bodies.pos, &bodies.radius, self.pairs.skin);
        if FRIC {
            self.wall_hist = transfer_wall_data(&old, &self.wall_hist, &self.wall_lists.candidates);
        }
        if POLY {
            self.wall_radius =
                transfer_wall_data(&old, &self.wall_radius, &self.wall_lists.candidates);
        }
    }

    /// Puts restored histories into the freshly built lists.
    fn apply_pending(&mut self) {
        let Some(saved) = self.pending.take() else {
            return;
        };
        if POLY {
            for (i, j, [x, y, z, radius]) in &saved.normals {
                let row = self.pairs.row(*i as usize);
                if let Ok(p) = self.pairs.partners[row.clone()].binary_search(j) {
                    self.pair_memory[row.start + p] = PairMemory {
                        normal: Vec3::new(*x, *y, *z),
                        radius: *radius,
                    };
                }
            }
            for &(w, i, radius) in &saved.wall_radii {
                if let Some(list) = self.wall_lists.candidates.get(w as usize) {
                    if let Ok(p) = list.binary_search(&i) {
                        self.wall_radius[w as usize][p] = radius;
                    }
                }
            }
        }
        if !FRIC {
            return;
        }
        for (i, j, h) in saved.pairs {
            let row = self.pairs.row(i as usize);
            if let Ok(p) = self.pairs.partners[row.clone()].binary_search(&j) {
                self.pair_hist[row.start + p] = Vec3::from(h);
            }
        }
        for (w, i, h) in saved.walls {
            if let Some(list) = self.wall_lists.candidates.get(w as usize) {
                if let Ok(p) = list.binary_search(&i) {
                    self.wall_hist[w as usize][p] = Vec3::from(h);
                }
            }
        }
    }

    /// The force of the pair (i, j) in slot `s`, or None when the bodies do not overlap.
    /// `memory` is what the pair remembers (POLY): its last normal warm-starts the contact
    /// search. POLY: a pair whose bodies have not travelled far enough since it was last found
    /// apart is not searched (`reach`, the slot's [`HertzContact::pair_reach`], is updated).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn pair_force(
        &self,
        bodies: &Bodies,
        i: usize,
        j: usize,
        hist: &mut Vec3,
        memory: &mut PairMemory,
        reach: &mut f64,
        ctx: &StepContext,
    ) -> Option<PairOut> {
        if POLY && skips(*reach, self.travel[i], self.travel[j]) {
            return None;
        }
        let at = |i| BodyAt {
            bodies,
            placements: &self.placements,
            i,
        };
        match pair_contact_or_gap::<DAMP, FRIC, POLY>(
            &self.k,
            &at(i),
            &at(j),
            hist,
            memory,
            ctx.dt,
            ctx.update_history,
        ) {
            Ok(p) => {
                *reach = 0.0;
                Some(p)
            }
            Err(gap) => {
                if POLY {
                    *reach = self.reach(i, j, gap, bodies);
                }
                None
            }
        }
    }

    fn pairs_serial(&mut self, bodies: &Bodies, forces: &mut Forces, ctx: &StepContext) {
        let mut count = 0;
        let mut dummy = Vec3::zeros();
        let mut dummy_n = PairMemory::default();
        let mut dummy_reach = 0.0;
        let mut hist = std::mem::take(&mut self.pair_hist);
        let mut normals = std::mem::take(&mut self.pair_memory);
        let mut reach = std::mem::take(&mut self.pair_reach);
        let mut records = std::mem::take(&mut self.records);
        for i in 0..bodies.len() {
            for s in self.pairs.row(i) {
                let j = self.pairs.partners[s] as usize;
                let h = if FRIC { &mut hist[s] } else { &mut dummy };
                let nrm = if POLY { &mut normals[s] } else { &mut dummy_n };
                let r = if POLY {
                    &mut reach[s]
                } else {
                    &mut dummy_reach
                };
                if let Some(p) = self.pair_force(bodies, i, j, h, nrm, r, ctx) {
                    forces.force[i] += p.force;
                    forces.force[j] -= p.force;
                    if FRIC || POLY {
                        forces.torque[i] += p.torque_i;
                        forces.torque[j] += p.torque_j;
                    }
                    if POLY {
                        records.list.push(p.record(i, j as u32));
                        records.dissipated += p.c.dissipated;
                    }
                    count += 1;
                }
            }
        }
        self.pair_hist = hist;
        self.pair_memory = normals;
        self.pair_reach = reach;
        self.records = records;
        self.contacts = count;
    }

    /// Several threads: each takes a fixed range of rows (balanced by pair count) and sums its
    /// pairs into its own accumulator over the bodies those rows touch; the accumulators are
    /// then added per body in range order. For a given thread count the order of every sum is
    /// fixed, so runs repeat bit for bit.
    fn pairs_parallel(&mut self, bodies: &Bodies, forces: &mut Forces, ctx: &StepContext) {
        let threads = team_size();
        if self.chunk_threads != threads || self.chunks.len() != self.accumulators.len() {
            self.chunks = self.pairs.row_chunks(threads);
            self.accumulators = self
                .chunks
                .iter()
                .map(|rows| {
                    let mut hi = rows.end;
                    for i in rows.clone() {
                        if let Some(&j) = self.pairs.partners[self.pairs.row(i)].last() {
                            hi = hi.max(j as usize + 1);
                        }
                    }
                    Accumulator::new(rows.start..hi)
                })
                .collect();
            self.chunk_threads = threads;
        }
        let slot_ranges: Vec<Range<usize>> = self
            .chunks
            .iter()
            .map(|rows| {
                self.pairs.offsets[rows.start] as usize..self.pairs.offsets[rows.end] as usize
            })
            .collect();
        let mut hist = std::mem::take(&mut self.pair_hist);
        let mut normals = std::mem::take(&mut self.pair_memory);
        let mut reach = std::mem::take(&mut self.pair_reach);
        let mut accs = std::mem::take(&mut self.accumulators);
        {
            fn parts<'a, T>(
                data: &'a mut [T],
                on: bool,
                ranges: &[Range<usize>],
            ) -> Vec<&'a mut [T]> {
                if on {
                    split_ranges(data, ranges)
                } else {
                    ranges.iter().map(|_| &mut [][..]).collect()
                }
            }
            let work: Vec<_> = self
                .chunks
                .iter()
                .zip(accs.iter_mut())
                .zip(parts(&mut hist, FRIC, &slot_ranges))
                .zip(parts(&mut normals, POLY, &slot_ranges))
                .zip(parts(&mut reach, POLY, &slot_ranges))
                .collect();
            let this = &*self;
            let counts = on_team(work, |_, ((((rows, acc), hist), normals), reach)| {
                acc.clear();
                let base = this.pairs.offsets[rows.start] as usize;
                let lo = acc.range.start;
                let mut dummy = Vec3::zeros();
                let mut dummy_n = PairMemory::default();
                let mut dummy_reach = 0.0;
                let mut count = 0;
                for i in rows.clone() {
                    for s in this.pairs.row(i) {
                        let j = this.pairs.partners[s] as usize;
                        let h = if FRIC {
                            &mut hist[s - base]
                        } else {
                            &mut dummy
                        };
                        let nrm = if POLY {
                            &mut normals[s - base]
                        } else {
                            &mut dummy_n
                        };
                        let r = if POLY {
                            &mut reach[s - base]
                        } else {
                            &mut dummy_reach
                        };
                        if let Some(p) = this.pair_force(bodies, i, j, h, nrm, r, ctx) {
                            acc.force[i - lo] += p.force;
                            acc.force[j - lo] -= p.force;
                            if FRIC || POLY {
                                acc.torque[i - lo] += p.torque_i;
                                acc.torque[j - lo] += p.torque_j;
                            }
                            if POLY {
                                acc.records.push(p.record(i, j as u32));
                                acc.dissipated += p.c.dissipated;
                            }
                            count += 1;
                        }
                    }
                }
                count
            });
            self.contacts = counts.iter().sum();
        }
        if POLY {
            // Chunk order is row order: the same records as one thread, in the same order.
            for acc in &accs {
                self.records.list.extend_from_slice(&acc.records);
                self.records.dissipated += acc.dissipated;
            }
        }
        // Each body adds the accumulators that hold it, in chunk order.
        let n = forces.force.len();
        #[allow(clippy::single_range_in_vec_init)] // one part: every body
        let ranges = team_blocks(n).unwrap_or_else(|| vec![0..n]);
        let merge: Vec<_> = ranges
            .iter()
            .zip(split_ranges(&mut forces.force, &ranges))
            .zip(split_ranges(&mut forces.torque, &ranges))
            .collect();
        let accs_ref = &accs;
        on_team(merge, |_, ((range, f), t)| {
            for (k, i) in range.clone().enumerate() {
                for acc in accs_ref {
                    if acc.range.contains(&i) {
                        f[k] += acc.force[i - acc.range.start];
                        if FRIC || POLY {
                            t[k] += acc.torque[i - acc.range.start];
                        }
                    }
                }
            }
        });
        self.pair_hist = hist;
        self.pair_memory = normals;
        self.pair_reach = reach;
        self.accumulators = accs;
    }

    fn walls_serial(
        &mut self,
        bodies: &Bodies,
        walls: &mut Walls,
        forces: &mut Forces,
        ctx: &StepContext,
    ) {
        let mut dummy = Vec3::zeros();
        let mut dummy_radius = 0.0;
        let mut wall_hist = std::mem::take(&mut self.wall_hist);
        let mut wall_radius = std::mem::take(&mut self.wall_radius);
        let mut records = std::mem::take(&mut self.records);
        let this = &*self;
        for (w, wall) in walls.walls.iter_mut().enumerate() {
            let cands = &this.wall_lists.candidates[w];
            for (c, &i) in cands.iter().enumerate() {
                let i = i as usize;
                let h = if FRIC {
                    &mut wall_hist[w][c]
                } else {
                    &mut dummy
                };
                let held = if POLY {
                    &mut wall_radius[w][c]
                } else {
                    &mut dummy_radius
                };
                let body = BodyAt {
                    bodies,
                    placements: &this.placements,
                    i,
                };
                let Some(p) = wall_contact::<DAMP, FRIC, POLY>(
                    &this.k_wall,
                    &body,
                    &wall.normal,
                    &wall.point,
                    &wall.velocity,
                    h,
                    held,
                    ctx.dt,
                    ctx.update_history,
                ) else {
                    continue;
                };
                forces.force[i] += p.force;
                if FRIC || POLY {
                    forces.torque[i] += p.torque_i;
                }
                if POLY {
                    records.list.push(p.record(i, WALL | w as u32));
                    records.dissipated += p.c.dissipated;
                }
                wall.force -= p.force;
                wall.stiffness += p.c.stiffness;
                wall.contacts += 1;
            }
        }
        self.wall_hist = wall_hist;
        self.wall_radius = wall_radius;
        self.records = records;
    }
}

impl<const DAMP: bool, const FRIC: bool, const POLY: bool> Effect
    for HertzContact<DAMP, FRIC, POLY>
{
    fn name(&self) -> &'static str {
        "contact"
    }

    fn describe(&self) -> String {
        let mut s = format!(
            "Hertz normal force, E* = {:.4e} Pa, between spheres and against walls",
            self.params.hertz.e_eff
        );
        if let Some(d) = &self.params.damping {
            s.push_str(&format!(
                "; + damping: viscous, restitution {} -> coefficient c = {:.6}",
                d.restitution, d.coefficient
            ));
        }
        if let Some(m) = &self.params.mindlin {
            s.push_str(&format!(
                "; + friction: Mindlin tangential with history, G* = {:.4e} Pa, Coulomb limit mu = {} (walls {})",
                m.g_eff,
                m.mu,
                self.params.wall_friction.unwrap_or(m.mu)
            ));
        }
        match self.params.skin {
            Some(skin) => s.push_str(&format!("; Verlet skin {skin:e} m")),
            None => s.push_str("; Verlet skin 0.4 x the smallest radius"),
        }
        if POLY {
            s.push_str("; poly-ellipsoid contacts (support-function Newton, Hertz radius from the local curvatures), every contact recorded for fracture and energy");
        }
        s
    }

    fn accumulate(
        &mut self,
        ctx: &StepContext,
        bodies: &Bodies,
        walls: &mut Walls,
        forces: &mut Forces,
    ) {
        if self.pairs.needs_rebuild(&bodies.pos) {
            self.rebuild_pairs(bodies);
            self.rebuild_walls(bodies, walls);
            self.apply_pending();
        } else if self.wall_lists.needs_rebuild(walls, self.pairs.skin) {
            self.rebuild_walls(bodies, walls);
        }
        if FRIC && self.pair_hist.len() != self.pairs.len() {
            self.pair_hist.resize(self.pairs.len(), Vec3::zeros());
        }
        if POLY {
            if self.pair_memory.len() != self.pairs.len() {
                self.pair_memory
                    .resize(self.pairs.len(), PairMemory::default());
            }
            if self.pair_reach.len() != self.pairs.len() {
                self.pair_reach.resize(self.pairs.len(), 0.0);
            }
            if self.wall_radius.len() != self.wall_lists.candidates.len() {
                self.wall_radius = self
                    .wall_lists
                    .candidates
                    .iter()
                    .map(|c| vec![0.0; c.len()])
                    .collect();
            }
            self.place(bodies);
            self.records.list.clear();
            self.records.dissipated = 0.0;
        }
        let threads = team_size();
        if threads > 1 && bodies.len() >= PARALLEL_MIN_BODIES_PER_THREAD * threads {
            self.pairs_parallel(bodies, forces, ctx);
        } else {
            self.pairs_serial(bodies, forces, ctx);
        }
        self.walls_serial(bodies, walls, forces, ctx);
    }

    fn contacts(&self) -> usize {
        self.contacts
    }

    fn records(&self) -> Option<&ContactRecords> {
        POLY.then_some(&self.records)
    }

    fn reshaped(&mut self, changed: &[usize]) {
        if !POLY || changed.is_empty() {
            return;
        }
        let rows = self.pairs.offsets.len().saturating_sub(1);
        for i in 0..rows {
            for s in self.pairs.row(i) {
                if changed.contains(&i) || changed.contains(&(self.pairs.partners[s] as usize)) {
                    if let Some(m) = self.pair_memory.get_mut(s) {
                        m.radius = 0.0;
                    }
                    // A new shape: its old gaps tell nothing.
                    if let Some(r) = self.pair_reach.get_mut(s) {
                        *r = 0.0;
                    }
                }
            }
        }
        for (list, radii) in self.wall_lists.candidates.iter().zip(&mut self.wall_radius) {
            for (&i, r) in list.iter().zip(radii.iter_mut()) {
                if changed.contains(&(i as usize)) {
                    *r = 0.0;
                }
            }
        }
    }

    fn history_len(&self) -> usize {
        self.pair_hist.len() + self.wall_hist.iter().map(Vec::len).sum::<usize>()
    }

    /// `max_i sqrt(2 Σ_j k_ij / m_i)` over the normal contact stiffnesses `k = 2 E* a` of
    /// each body's contacts (walls included): a Gershgorin bound on the highest normal-mode
    /// frequency, exact for two equal spheres. Hertz contacts stiffen as they overlap, which
    /// the Rayleigh step does not see.
    fn max_frequency(&self, bodies: &Bodies, walls: &Walls) -> f64 {
        if POLY {
            let tangential = self.params.mindlin.map_or(0.0, |m| {
                tangential_ratio(m.g_eff * 8.0, 2.0 * self.params.hertz.e_eff)
            });
            return records_max_frequency(&self.records.list, bodies, tangential);
        }
        if self.pairs.offsets.len() != bodies.len() + 1 {
            return 0.0;
        }
        let two_e = 2.0 * self.params.hertz.e_eff;
        let mut stiffness = take_rows(bodies.len());
        for i in 0..bodies.len() {
            for s in self.pairs.row(i) {
                let j = self.pairs.partners[s] as usize;
                let (ri, rj) = (bodies.radius[i], bodies.radius[j]);
                // Most listed pairs are apart (the list holds a skin): no root for them, as
                // this runs after every step.
                let d2 = (bodies.pos[i] - bodies.pos[j]).norm_squared();
                if d2 < (ri + rj) * (ri + rj) {
                    let delta = ri + rj - d2.sqrt();
                    let k = two_e * (ri * rj / (ri + rj) * delta).sqrt();
                    stiffness[i] += k;
                    stiffness[j] += k;
                }
            }
        }
        for (w, wall) in walls.walls.iter().enumerate() {
            for &i in self
                .wall_lists
                .candidates
                .get(w)
                .map_or(&[][..], |c| &c[..])
            {
                let i = i as usize;
                let delta = bodies.radius[i] - wall.distance(&bodies.pos[i]);
                if delta > 0.0 {
                    stiffness[i] += two_e * (bodies.radius[i] * delta).sqrt();
                }
            }
        }
        let highest = stiffness
            .iter()
            .zip(&bodies.inv_mass)
            .map(|(k, inv_m)| (2.0 * k * inv_m).sqrt())
            .fold(0.0, f64::max);
        give_rows(stiffness);
        highest
    }

    fn save(&self) -> Vec<u8> {
        if !(FRIC || POLY) {
            return Vec::new();
        }
        let mut saved = self.pending.clone().unwrap_or_default();
        if self.pending.is_none() && POLY {
            for i in 0..self.pairs.offsets.len().saturating_sub(1) {
                for s in self.pairs.row(i) {
                    let m = self.pair_memory[s];
                    if m != PairMemory::default() {
                        let n = m.normal;
                        saved.normals.push((
                            i as u32,
                            self.pairs.partners[s],
                            [n.x, n.y, n.z, m.radius],
                        ));
                    }
                }
            }
        }
        if self.pending.is_none() && POLY {
            for (w, list) in self.wall_lists.candidates.iter().enumerate() {
                for (c, &i) in list.iter().enumerate() {
                    let r = self.wall_radius.get(w).map_or(0.0, |v| v[c]);
                    if r > 0.0 {
                        saved.wall_radii.push((w as u32, i, r));
                    }
                }
            }
        }
        if self.pending.is_none() && FRIC {
            for i in 0..self.pairs.offsets.len().saturating_sub(1) {
                for s in self.pairs.row(i) {
                    let h = self.pair_hist[s];
                    if h != Vec3::zeros() {
                        saved
                            .pairs
                            .push((i as u32, self.pairs.partners[s], h.into()));
                    }
                }
            }
            for (w, list) in self.wall_lists.candidates.iter().enumerate() {
                for (c, &i) in list.iter().enumerate() {
                    let h = self.wall_hist[w][c];
                    if h != Vec3::zeros() {
                        saved.walls.push((w as u32, i, h.into()));
                    }
                }
            }
        }
        postcard::to_stdvec(&saved).expect("contact history serialises")
    }

    fn restore(&mut self, data: &[u8], bodies: usize) -> Result<()> {
        if !(FRIC || POLY) || data.is_empty() {
            return Ok(());
        }
        let saved: SavedHistory = postcard::from_bytes(data).map_err(|e| {
            Error::run(format!("the checkpoint's contact history is damaged ({e})"))
        })?;
        // The histories go into the lists by body index: one past the bodies indexed a row
        // that does not exist (a panic at the first step after a forged restore).
        let n = bodies as u32;
        let pairs = saved.pairs.iter().map(|&(i, j, _)| (i, j));
        let normals = saved.normals.iter().map(|&(i, j, _)| (i, j));
        let walls = saved.walls.iter().map(|&(_, i, _)| (i, 0));
        let radii = saved.wall_radii.iter().map(|&(_, i, _)| (i, 0));
        if let Some((i, j)) = pairs
            .chain(normals)
            .chain(walls)
            .chain(radii)
            .find(|&(i, j)| i >= n || j >= n)
        {
            return Err(Error::run(format!(
                "the checkpoint's contact history names body {} of a state of {bodies} bodies",
                i.max(j)
            )));
        }
        // Lists are rebuilt at the next evaluation; the histories go in then.
        self.pairs = PairList::new(self.pairs.skin);
        self.wall_lists = WallLists::default();
        self.pair_hist.clear();
        self.wall_hist.clear();
        self.pair_memory.clear();
        self.wall_radius.clear();
        self.pending = Some(saved);
        Ok(())
    }
}

thread_local! {
    /// The per-body sums of the frequency estimates, kept between calls: the estimate runs
    /// after every step, and a step allocates nothing (tests/step_allocations.rs).
    static ROWS: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The kept per-body sums, `n` zeros (hand them back with [`give_rows`]).
fn take_rows(n: usize) -> Vec<f64> {
    let mut rows = ROWS.with(|r| std::mem::take(&mut *r.borrow_mut()));
    rows.clear();
    rows.resize(n, 0.0);
    rows
}

/// Keeps `rows` for the next estimate.
fn give_rows(rows: Vec<f64>) {
    ROWS.with(|r| *r.borrow_mut() = rows);
}

/// A bound on the highest frequency (rad/s) of the recorded contacts' linearised springs,
/// translation and rotation (block Gershgorin over the bodies, docs/performance.md): each
/// contact loads each of its bodies by [`contact_load`], a body's row sums its contacts'
/// [`frequency_share`]s, and the bound is [`frequency_bound`] of the largest row. Exact for two
/// equal spheres (`sqrt(2 k / m)`); within 1.3-1.5x of the computed highest frequency
/// ([`records_highest_frequency`]) in the main job.
pub fn records_max_frequency(records: &[ContactRecord], bodies: &Bodies, tangential: f64) -> f64 {
    let mut rows = take_rows(bodies.len());
    let load = |i: usize, r: &ContactRecord| {
        contact_load(
            &r.point,
            &r.normal,
            r.stiffness,
            &bodies.pos[i],
            &bodies.orientation[i],
            bodies.inv_mass[i],
            &bodies.inv_inertia[i],
            tangential,
        )
    };
    for r in records {
        let i = r.i as usize;
        let own = load(i, r);
        match r.wall() {
            Some(_) => rows[i] += frequency_share(own, None),
            None => {
                let j = r.j as usize;
                let other = load(j, r);
                rows[i] += frequency_share(own, Some(other));
                rows[j] += frequency_share(other, Some(own));
            }
        }
    }
    let highest = rows.iter().map(|&x| frequency_bound(x)).fold(0.0, f64::max);
    give_rows(rows);
    highest
}

/// The highest frequency (rad/s) of the recorded contacts' linearised springs, computed rather
/// than bounded: the largest eigenvalue of `M^-1/2 K M^-1/2` by power iteration, with K the
/// normal springs `stiffness n n^T` and (with friction, `tangential` > 0) the Mindlin springs
/// `tangential stiffness (1 - n n^T)` acting at the contact points on every body's three
/// translations and three rotations (principal moments turned to the world), walls fixed.
/// Returns that frequency and the body that moves most in its mode (the translational share
/// of that body's motion as the third value). It is never above [`records_max_frequency`],
/// the bound the run adapts its step to; `iterations` (a few hundred) sets how closely it
/// approaches from below. For diagnosis (what sets a run's step), not for the step loop.
pub fn records_highest_frequency(
    records: &[ContactRecord],
    bodies: &Bodies,
    tangential: f64,
    iterations: usize,
) -> (f64, usize, f64) {
    let n = bodies.len();
    if n == 0 || records.is_empty() {
        return (0.0, 0, 0.0);
    }
    let scale = MassScale::of(bodies);
    let apply = |w: &[Dof], out: &mut [Dof]| {
        for o in out.iter_mut() {
            *o = [Vec3::zeros(); 2];
        }
        let disp = |i: usize, c: &Vec3| {
            let (u, th) = scale.motion(i, &w[i]);
            u + th.cross(&(c - bodies.pos[i]))
        };
        for r in records {
            let i = r.i as usize;
            let mut d = disp(i, &r.point);
            let wall = r.wall().is_some();
            if !wall {
                d -= disp(r.j as usize, &r.point);
            }
            let dn = r.normal * r.normal.dot(&d);
            let f = (dn + (d - dn) * tangential) * r.stiffness;
            let mut push = |b: usize, f: Vec3| {
                let l = scale.load(b, &f, &(r.point - bodies.pos[b]).cross(&f));
                out[b][0] += l[0];
                out[b][1] += l[1];
            };
            push(i, f);
            if !wall {
                push(r.j as usize, -f);
            }
        }
    };
    let (lambda, mode) = highest_eigenvalue(n, iterations, apply);
    let (at, lin) = largest_motion(&mode);
    (lambda.sqrt(), at, lin)
}

/// The neighbour-list skin (m) without a scene's `neighbor.skin`: 0.4 of the smallest radius.
pub fn default_skin(bodies: &Bodies) -> f64 {
    0.4 * bodies.min_radius()
}

/// How hard one contact's springs load one of its bodies (rad²/s²): the largest eigenvalue of
/// `S^½ G S^½`, with `S = k (n nᵀ + t (1 − n nᵀ))` the contact's normal (stiffness `k`, N/m,
/// along the unit `normal`) and Mindlin tangential (`t k`) springs and
/// `G = 1/m + [c]× I⁻¹ [c]×ᵀ` the body's compliance at `point` (c the lever from the centre
/// `pos`, I⁻¹ the inverse inertia tensor: the inverse principal moments `inv_inertia` turned
/// to the world by `orientation`). Without friction (`tangential` 0) it is
/// `k (1/m + (c × n)ᵀ I⁻¹ (c × n))`. `tangential` is [`tangential_ratio`].
#[allow(clippy::too_many_arguments)]
pub fn contact_load(
    point: &Vec3,
    normal: &Vec3,
    stiffness: f64,
    pos: &Vec3,
    orientation: &UnitQuaternion<f64>,
    inv_mass: f64,
    inv_inertia: &Vec3,
    tangential: f64,
) -> f64 {
    let lever = point - pos;
    if tangential == 0.0 {
        let arm = orientation.inverse_transform_vector(&lever.cross(normal));
        return stiffness * (inv_mass + arm.component_mul(&arm).dot(inv_inertia));
    }
    // Y = [c]× R: the rotation (in the principal frame) that moves the contact point.
    let y = lever.cross_matrix() * orientation.to_rotation_matrix().into_inner();
    let g = Matrix3::from_diagonal_element(inv_mass)
        + y * Matrix3::from_diagonal(inv_inertia) * y.transpose();
    let root_t = tangential.sqrt();
    let q = Matrix3::from_diagonal_element(root_t) + normal * normal.transpose() * (1.0 - root_t);
    let h = q * g * q * stiffness;
    let h = (h + h.transpose()) * 0.5;
    crate::fracture::criteria::symmetric3_largest_eigenvalue(&h)
}

/// One contact's share of a body's row (rad²/s²): its load on the body, `own`, plus its
/// coupling to the partner, `sqrt(own other)` (`other` the load on the partner; none for a
/// wall, which does not move).
pub fn frequency_share(own: f64, other: Option<f64>) -> f64 {
    match other {
        Some(o) => own + (own * o).sqrt(),
        None => own,
    }
}

/// The frequency bound (rad/s) of a body whose contacts' [`frequency_share`]s sum to `sum`.
pub fn frequency_bound(sum: f64) -> f64 {
    sum.sqrt()
}

/// The Mindlin tangential stiffness over the Hertz normal stiffness, `8 G* / (2 E*)` (0
/// without friction), for [`frequency_share`].
pub fn tangential_ratio(eight_g: f64, two_e: f64) -> f64 {
    eight_g / two_e
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A saved contact history names its bodies by index; restored into a state of fewer
    /// bodies (a forged or mismatched checkpoint) it is refused naming the body, where the
    /// first step after it indexed a row that does not exist; within the bodies it is taken.
    #[test]
    fn a_history_naming_a_body_past_the_state_is_refused() {
        for shapes in [false, true] {
            let params = ContactParams {
                hertz: Hertz::new(60e9, 0.17),
                damping: None,
                mindlin: Some(Mindlin::new(60e9, 0.17, 0.5)),
                wall_friction: None,
                skin: None,
                shapes,
            };
            let saved = SavedHistory {
                pairs: vec![(0, 5, [1e-9, 0.0, 0.0])],
                walls: vec![(0, 2, [0.0; 3])],
                normals: Vec::new(),
                wall_radii: Vec::new(),
            };
            let data = postcard::to_stdvec(&saved).unwrap();
            let mut effect = build_contact(params);
            let err = effect.restore(&data, 5).unwrap_err().to_string();
            assert!(err.contains("names body 5 of a state of 5 bodies"), "{err}");
            effect.restore(&data, 6).unwrap();
        }
    }

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
