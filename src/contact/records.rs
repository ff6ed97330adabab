//! The contacts of an evaluation as records ([`ContactRecords`], kept by the contact effect
//! with poly-ellipsoids or fracture, read by the fracture criteria and the energy account),
//! and the bound on the highest frequency of their linearised springs that a run's step
//! check and step adaptation read ([`records_max_frequency`], from the per-contact
//! [`contact_load`], [`frequency_share`] and [`frequency_bound`]).

use nalgebra::{Matrix3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use super::pair::PairOut;
use crate::parallel::{on_team, team_parts};
use crate::probe::modes::{Dof, MassScale, highest_eigenvalue, largest_motion};
use crate::state::{Bodies, Vec3};
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

impl PairOut {
    /// The record of this contact of body `i` with `j` (a body, or `WALL | w`).
    pub(crate) fn record(&self, i: usize, j: u32) -> ContactRecord {
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

thread_local! {
    /// The per-body sums of the frequency estimates, kept between calls: the estimate runs
    /// after every step, and a step allocates nothing (tests/step_allocations.rs).
    static ROWS: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The kept per-body sums, `n` zeros (hand them back with [`give_rows`]).
pub(crate) fn take_rows(n: usize) -> Vec<f64> {
    let mut rows = ROWS.with(|r| std::mem::take(&mut *r.borrow_mut()));
    rows.clear();
    rows.resize(n, 0.0);
    rows
}

/// Keeps `rows` for the next estimate.
pub(crate) fn give_rows(rows: Vec<f64>) {
    ROWS.with(|r| *r.borrow_mut() = rows);
}

/// The contact records of each body, in record order: body `i`'s are `records[k]` for `k` in
/// [`RecordsByBody::of`]`(i)` (a record of two bodies is listed under both; one of a wall
/// under its body). Built by counting, kept between steps so that a step allocates nothing
/// once it has grown.
#[derive(Debug, Clone, Default)]
pub struct RecordsByBody {
    offsets: Vec<u32>,
    entries: Vec<u32>,
}

impl RecordsByBody {
    /// Indexes `records` over `n` bodies.
    pub fn build(&mut self, n: usize, records: &[ContactRecord]) {
        let offsets = &mut self.offsets;
        offsets.clear();
        offsets.resize(n + 1, 0);
        for r in records {
            offsets[r.i as usize + 1] += 1;
            if r.wall().is_none() {
                offsets[r.j as usize + 1] += 1;
            }
        }
        for k in 0..n {
            offsets[k + 1] += offsets[k];
        }
        self.entries.clear();
        self.entries.resize(offsets[n] as usize, 0);
        // Filled at each body's next free place: offsets[i] walks to offsets[i + 1] and is
        // moved back after.
        for (k, r) in records.iter().enumerate() {
            let i = r.i as usize;
            self.entries[offsets[i] as usize] = k as u32;
            offsets[i] += 1;
            if r.wall().is_none() {
                let j = r.j as usize;
                self.entries[offsets[j] as usize] = k as u32;
                offsets[j] += 1;
            }
        }
        for k in (1..=n).rev() {
            offsets[k] = offsets[k - 1];
        }
        offsets[0] = 0;
    }

    /// The indices of body `i`'s records, in record order.
    pub fn of(&self, i: usize) -> &[u32] {
        &self.entries[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }
}

/// A bound on the highest frequency (rad/s) of the recorded contacts' linearised springs,
/// translation and rotation (block Gershgorin over the bodies, docs/performance.md): each
/// contact loads each of its bodies by [`contact_load`], a body's row sums its contacts'
/// [`frequency_share`]s, and the bound is [`frequency_bound`] of the largest row. Exact for two
/// equal spheres (`sqrt(2 k / m)`); within 1.3-1.5x of the computed highest frequency
/// ([`records_highest_frequency`]) in the main job.
pub fn records_max_frequency(records: &[ContactRecord], bodies: &Bodies, tangential: f64) -> f64 {
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
    // A contact's shares of its two bodies' rows (the second 0 for a wall).
    let shares = |r: &ContactRecord| -> [f64; 2] {
        let own = load(r.i as usize, r);
        match r.wall() {
            Some(_) => [frequency_share(own, None), 0.0],
            None => {
                let other = load(r.j as usize, r);
                [
                    frequency_share(own, Some(other)),
                    frequency_share(other, Some(own)),
                ]
            }
        }
    };
    let mut rows = take_rows(bodies.len());
    let mut add = |r: &ContactRecord, [own, other]: [f64; 2]| {
        rows[r.i as usize] += own;
        if r.wall().is_none() {
            rows[r.j as usize] += other;
        }
    };
    // The loads (an eigenvalue each) are the cost: with a team they are computed in blocks
    // of records across its members, and the rows summed here in record order as on one
    // thread, so the bound has the same bits whatever the thread count. (Serial, this pass
    // was a sixth of the caller's time in the main job on two threads, the member waiting.)
    match team_parts(records.len(), RECORDS_PER_PART) {
        Some(parts) => {
            let computed = on_team(parts, |_, part| {
                records[part].iter().map(shares).collect::<Vec<_>>()
            });
            for (r, s) in records.iter().zip(computed.into_iter().flatten()) {
                add(r, s);
            }
        }
        None => {
            for r in records {
                add(r, shares(r));
            }
        }
    }
    let highest = rows.iter().map(|&x| frequency_bound(x)).fold(0.0, f64::max);
    give_rows(rows);
    highest
}

/// Contact records per part of [`records_max_frequency`] on a team.
const RECORDS_PER_PART: usize = 256;

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
    crate::linalg::symmetric3_largest_eigenvalue(&h)
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
