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
//! Sample preparation cuts the rows by their count instead ([`PairParts::PerRows`]), so that
//! its sample is the same on any number of threads.

use std::ops::Range;

use nalgebra::UnitQuaternion;
use serde::{Deserialize, Serialize};

use super::{Effect, StepContext};
use crate::contact::hertz_mindlin::{Hertz, KernelConsts, Mindlin, ViscousDamping};
use crate::contact::neighbor::{PairList, WallLists, transfer_pair_data, transfer_wall_data};
use crate::contact::pair::{
    BodyAt, PairMemory, PairOut, Placement, pair_contact_or_gap, pair_reach, skips, travel_step,
    wall_contact,
};
use crate::contact::records::{
    ContactRecord, ContactRecords, WALL, records_max_frequency, tangential_ratio,
};
use crate::error::{Error, Result};
use crate::parallel::{on_team, split_ranges, team_blocks, team_parts, team_size};
use crate::state::{Bodies, Forces, Vec3, Walls};

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
    /// Friction coefficient against the sleeve (default: `wall_friction`, else that of
    /// `mindlin`).
    pub sleeve_friction: Option<f64>,
    /// Verlet skin (m); `None`: 0.4 × the smallest radius, chosen at the first build.
    pub skin: Option<f64>,
    /// Bodies other than spheres may take part (poly-ellipsoids): build the `POLY` variant,
    /// which also records every contact.
    pub shapes: bool,
    /// How the pair loop is cut into parts with private sums.
    pub parts: PairParts,
}

/// How the pair loop is cut into parts, each summing its pairs' forces in its own
/// accumulator, the accumulators then added body by body in part order. The parts fix the
/// order of every sum, and with it the result's last bits.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum PairParts {
    /// One part per member of the team advancing the run (one, a plain loop, without one):
    /// the fastest cut, its bits those of the thread count.
    #[default]
    PerThread,
    /// One part per this many rows (bodies) whatever the thread count, one part (the plain
    /// loop) below twice that: the same bits on any number of threads, for sample
    /// preparation, whose sample must not depend on the machine that made it.
    PerRows(usize),
}

impl PairParts {
    /// How many parts the pair loop of `bodies` bodies takes; one: the plain loop.
    pub fn count(self, bodies: usize) -> usize {
        match self {
            PairParts::PerThread => {
                let threads = team_size();
                if bodies >= PARALLEL_MIN_BODIES_PER_THREAD * threads {
                    threads
                } else {
                    1
                }
            }
            PairParts::PerRows(rows) => (bodies / rows.max(1)).max(1),
        }
    }
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

/// Below this many bodies per thread the pair loop runs on one thread even with a worker
/// team. Whether a step is worth the team at all (dense spheres below 1500 per thread are
/// not) is the model's decision, [`crate::run::Physics::team_members`].
const PARALLEL_MIN_BODIES_PER_THREAD: usize = 100;

/// A thread's private sums of forces and torques over the bodies `range` (and, POLY, its
/// contact records and dissipated energy; spheres, the bodies' summed contact stiffness).
#[derive(Debug, Clone, Default)]
struct Accumulator {
    range: Range<usize>,
    force: Vec<Vec3>,
    torque: Vec<Vec3>,
    stiffness: Vec<f64>,
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
            stiffness: vec![0.0; n],
            records: Vec::new(),
            dissipated: 0.0,
        }
    }

    fn clear(&mut self) {
        self.force.fill(Vec3::zeros());
        self.torque.fill(Vec3::zeros());
        self.stiffness.fill(0.0);
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

pub struct HertzContact<const DAMP: bool, const FRIC: bool, const POLY: bool> {
    params: ContactParams,
    k: KernelConsts,
    /// Constants against walls (their own friction coefficient).
    k_wall: KernelConsts,
    /// Constants against the sleeve (its own friction coefficient).
    k_sleeve: KernelConsts,
    pairs: PairList,
    wall_lists: WallLists,
    /// Tangential displacement per pair slot (empty without friction).
    pair_hist: Vec<Vec3>,
    /// Tangential displacement per wall candidate (empty without friction).
    wall_hist: Vec<Vec<Vec3>>,
    /// Parallel path: rows of each part and their accumulators.
    chunks: Vec<Range<usize>>,
    accumulators: Vec<Accumulator>,
    chunk_parts: usize,
    pending: Option<SavedHistory>,
    contacts: usize,
    /// Spheres: each body's summed normal contact stiffness (N/m, walls included) at the last
    /// evaluation, gathered in the force pass for [`Effect::max_frequency`] (a second walk
    /// over the neighbour list after every step cost a quarter of a sphere run's time).
    body_stiffness: Vec<f64>,
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
        let sleeve_mindlin = params.mindlin.map(|m| Mindlin {
            mu: params
                .sleeve_friction
                .or(params.wall_friction)
                .unwrap_or(m.mu),
            ..m
        });
        let k_sleeve = KernelConsts::new(
            &params.hertz,
            params.damping.as_ref(),
            sleeve_mindlin.as_ref(),
        );
        HertzContact {
            k,
            k_wall,
            k_sleeve,
            pairs: PairList::new(params.skin.unwrap_or(0.0)),
            params,
            wall_lists: WallLists::default(),
            pair_hist: Vec::new(),
            wall_hist: Vec::new(),
            chunks: Vec::new(),
            accumulators: Vec::new(),
            chunk_parts: 0,
            pending: None,
            contacts: 0,
            body_stiffness: Vec::new(),
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
        let placed =
            |i: usize| Placement::of(&bodies.pos[i], &bodies.orientation[i], &bodies.shape[i]);
        self.travel.resize(n, 0.0);
        self.last_pose.truncate(n);
        let known = self.last_pose.len();
        self.last_pose
            .extend((known..n).map(|i| (bodies.pos[i], bodies.orientation[i])));
        // Each body's own placement, travel and pose: with a team in blocks across it.
        let moved = |i: usize, travel: &mut f64, (x, q): &mut (Vec3, UnitQuaternion<f64>)| {
            if i < known {
                let (pos, orientation) = (&bodies.pos[i], &bodies.orientation[i]);
                *travel += travel_step(x, q, pos, orientation, bodies.radius[i]);
                *x = *pos;
                *q = *orientation;
            }
        };
        match team_blocks(n) {
            Some(blocks) => {
                self.placements.resize(n, placed(0));
                let work: Vec<_> = split_ranges(&mut self.placements, &blocks)
                    .into_iter()
                    .zip(split_ranges(&mut self.travel, &blocks))
                    .zip(split_ranges(&mut self.last_pose, &blocks))
                    .zip(blocks.iter().cloned())
                    .collect();
                on_team(work, |_, (((placements, travel), poses), range)| {
                    for (k, i) in range.enumerate() {
                        placements[k] = placed(i);
                        moved(i, &mut travel[k], &mut poses[k]);
                    }
                });
            }
            None => {
                self.placements.clear();
                self.placements.extend((0..n).map(placed));
                for (i, (travel, pose)) in
                    self.travel.iter_mut().zip(&mut self.last_pose).enumerate()
                {
                    moved(i, travel, pose);
                }
            }
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
        self.chunk_parts = 0;
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
        if !POLY {
            self.body_stiffness.clear();
            self.body_stiffness.resize(bodies.len(), 0.0);
        }
        let parts = self.params.parts.count(bodies.len());
        if parts > 1 {
            self.pairs_parallel(parts, bodies, forces, ctx);
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
    /// each body's contacts (walls included) at the last evaluation: a Gershgorin bound on the
    /// highest normal-mode frequency, exact for two equal spheres. Hertz contacts stiffen as
    /// they overlap, which the Rayleigh step does not see. The sums are the force pass's
    /// (`body_stiffness`): the step evaluates its forces at the positions it ends at, so the
    /// bound after a step is the bound of the state the step left.
    fn max_frequency(&self, bodies: &Bodies, _walls: &Walls) -> f64 {
        if POLY {
            let tangential = self.params.mindlin.map_or(0.0, |m| {
                tangential_ratio(m.g_eff * 8.0, 2.0 * self.params.hertz.e_eff)
            });
            return records_max_frequency(&self.records.list, bodies, tangential);
        }
        if self.body_stiffness.len() != bodies.len() {
            return 0.0;
        }
        // One root for the largest: the root is monotone, so the same bits as the largest root.
        let largest = self
            .body_stiffness
            .iter()
            .zip(&bodies.inv_mass)
            .map(|(k, inv_m)| 2.0 * k * inv_m)
            .fold(0.0, f64::max);
        largest.sqrt()
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

/// The neighbour-list skin (m) without a scene's `neighbor.skin`: 0.4 of the smallest radius.
pub fn default_skin(bodies: &Bodies) -> f64 {
    0.4 * bodies.min_radius()
}

mod pairs;
mod walls;

#[cfg(test)]
mod tests;
