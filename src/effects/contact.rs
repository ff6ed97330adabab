//! The `contact` effect: Hertz normal force between spheres and against walls, with the
//! `damping` and `friction` effects folded into the same loop when the scene names them.
//!
//! One thread sums each pair's force straight into both bodies, pair slot by pair slot.
//! Several threads each own a fixed range of rows and sum into private accumulators that are
//! added up per body in a fixed order: for a given thread count, runs repeat bit for bit.

use std::ops::Range;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{Effect, StepContext};
use crate::contact::hertz_mindlin::{
    ContactForce, Hertz, KernelConsts, Mindlin, ViscousDamping, hertz_mindlin,
};
use crate::contact::neighbor::{PairList, WallLists, transfer_pair_data, transfer_wall_data};
use crate::error::{Error, Result};
use crate::parallel::threads_here;
use crate::scene::{EffectKind, Scene};
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
    /// Verlet skin (m); `None`: 0.4 × the smallest radius, chosen at the first build.
    pub skin: Option<f64>,
}

impl ContactParams {
    /// The contact model a scene asks for. `friction` overrides the material's coefficient
    /// (sample preparation compacts with its own).
    pub fn from_scene(scene: &Scene, friction: Option<f64>) -> Self {
        let m = &scene.material;
        let damping = scene
            .has_effect(EffectKind::Damping)
            .then(|| ViscousDamping::from_restitution(m.restitution));
        let mindlin = scene
            .has_effect(EffectKind::Friction)
            .then(|| Mindlin::new(m.young, m.poisson, friction.unwrap_or(m.friction)));
        ContactParams {
            hertz: Hertz::new(m.young, m.poisson),
            damping,
            mindlin,
            wall_friction: scene.walls.friction,
            skin: scene.neighbor.skin,
        }
    }
}

/// Builds the contact effect with exactly the sub-models in `params`.
pub fn build_contact(params: ContactParams) -> Box<dyn Effect> {
    match (params.damping.is_some(), params.mindlin.is_some()) {
        (false, false) => Box::new(HertzContact::<false, false>::new(params)),
        (true, false) => Box::new(HertzContact::<true, false>::new(params)),
        (false, true) => Box::new(HertzContact::<false, true>::new(params)),
        (true, true) => Box::new(HertzContact::<true, true>::new(params)),
    }
}

/// Below this many bodies per thread the pair loop runs on one thread: waking a second
/// worker twice per step costs more than it saves (measured on the 2-core CI machine: with
/// 2 threads, 2000 bodies ran at 0.86x and 4000 at 1.16x of one thread).
const PARALLEL_MIN_BODIES_PER_THREAD: usize = 1500;

/// One pair's force on i and the torques on i and j.
#[derive(Debug, Clone, Copy, Default)]
struct PairOut {
    force: Vec3,
    torque_i: Vec3,
    torque_j: Vec3,
}

/// A thread's private sums of forces and torques over the bodies `range`.
#[derive(Debug, Clone, Default)]
struct Accumulator {
    range: Range<usize>,
    force: Vec<Vec3>,
    torque: Vec<Vec3>,
}

impl Accumulator {
    fn new(range: Range<usize>) -> Self {
        let n = range.len();
        Accumulator {
            range,
            force: vec![Vec3::zeros(); n],
            torque: vec![Vec3::zeros(); n],
        }
    }

    fn clear(&mut self) {
        self.force.fill(Vec3::zeros());
        self.torque.fill(Vec3::zeros());
    }
}

/// Contact histories in a form independent of the neighbour list, for checkpoints.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct SavedHistory {
    pairs: Vec<(u32, u32, [f64; 3])>,
    walls: Vec<(u32, u32, [f64; 3])>,
}

pub struct HertzContact<const DAMP: bool, const FRIC: bool> {
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
}

impl<const DAMP: bool, const FRIC: bool> HertzContact<DAMP, FRIC> {
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
        }
    }

    fn rebuild_pairs(&mut self, bodies: &Bodies) {
        if self.pairs.skin <= 0.0 {
            self.pairs.skin = 0.4 * bodies.min_radius();
        }
        let (old_offsets, old_partners) = if FRIC {
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
        self.chunk_threads = 0;
    }

    fn rebuild_walls(&mut self, bodies: &Bodies, walls: &Walls) {
        let old = std::mem::take(&mut self.wall_lists.candidates);
        self.wall_lists
            .build(walls, &bodies.pos, &bodies.radius, self.pairs.skin);
        if FRIC {
            self.wall_hist = transfer_wall_data(&old, &self.wall_hist, &self.wall_lists.candidates);
        }
    }

    /// Puts restored histories into the freshly built lists.
    fn apply_pending(&mut self) {
        let Some(saved) = self.pending.take() else {
            return;
        };
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

    /// The force of the pair (i, j), or None when the spheres do not overlap.
    #[inline(always)]
    fn pair_force(
        &self,
        bodies: &Bodies,
        i: usize,
        j: usize,
        hist: &mut Vec3,
        ctx: &StepContext,
    ) -> Option<PairOut> {
        let d = bodies.pos[i] - bodies.pos[j];
        let (ri, rj) = (bodies.radius[i], bodies.radius[j]);
        let rsum = ri + rj;
        let r2 = d.norm_squared();
        if r2 >= rsum * rsum {
            if FRIC {
                *hist = Vec3::zeros();
            }
            return None;
        }
        let r = r2.sqrt();
        let n = if r > 0.0 { d / r } else { Vec3::z() };
        let delta = rsum - r;
        let r_eff = ri * rj / rsum;
        let m_eff = if DAMP {
            let (mi, mj) = (bodies.mass[i], bodies.mass[j]);
            mi * mj / (mi + mj)
        } else {
            0.0
        };
        let (di, dj) = (ri - 0.5 * delta, rj - 0.5 * delta);
        let mut v = bodies.vel[i] - bodies.vel[j];
        if FRIC {
            v -= (bodies.omega[i] * di + bodies.omega[j] * dj).cross(&n);
        }
        let ContactForce { force, .. } = hertz_mindlin::<DAMP, FRIC>(
            &self.k,
            &n,
            delta,
            r_eff,
            m_eff,
            &v,
            hist,
            ctx.dt,
            ctx.update_history,
        );
        let (torque_i, torque_j) = if FRIC {
            let nxf = n.cross(&force);
            (nxf * (-di), nxf * (-dj))
        } else {
            (Vec3::zeros(), Vec3::zeros())
        };
        Some(PairOut {
            force,
            torque_i,
            torque_j,
        })
    }

    fn pairs_serial(&mut self, bodies: &Bodies, forces: &mut Forces, ctx: &StepContext) {
        let mut count = 0;
        let mut dummy = Vec3::zeros();
        let mut hist = std::mem::take(&mut self.pair_hist);
        for i in 0..bodies.len() {
            for s in self.pairs.row(i) {
                let j = self.pairs.partners[s] as usize;
                let h = if FRIC { &mut hist[s] } else { &mut dummy };
                if let Some(p) = self.pair_force(bodies, i, j, h, ctx) {
                    forces.force[i] += p.force;
                    forces.force[j] -= p.force;
                    if FRIC {
                        forces.torque[i] += p.torque_i;
                        forces.torque[j] += p.torque_j;
                    }
                    count += 1;
                }
            }
        }
        self.pair_hist = hist;
        self.contacts = count;
    }

    /// Several threads: each takes a fixed range of rows (balanced by pair count) and sums its
    /// pairs into its own accumulator over the bodies those rows touch; the accumulators are
    /// then added per body in range order. For a given thread count the order of every sum is
    /// fixed, so runs repeat bit for bit.
    fn pairs_parallel(&mut self, bodies: &Bodies, forces: &mut Forces, ctx: &StepContext) {
        let threads = threads_here();
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
        let mut accs = std::mem::take(&mut self.accumulators);
        {
            let hist_parts: Vec<&mut [Vec3]> = if FRIC {
                split_ranges(&mut hist, &slot_ranges)
            } else {
                slot_ranges.iter().map(|_| &mut [][..]).collect()
            };
            let this = &*self;
            let count: usize = this
                .chunks
                .par_iter()
                .zip(accs.par_iter_mut())
                .zip(hist_parts)
                .map(|((rows, acc), hist)| {
                    acc.clear();
                    let base = this.pairs.offsets[rows.start] as usize;
                    let lo = acc.range.start;
                    let mut dummy = Vec3::zeros();
                    let mut count = 0;
                    for i in rows.clone() {
                        for s in this.pairs.row(i) {
                            let j = this.pairs.partners[s] as usize;
                            let h = if FRIC {
                                &mut hist[s - base]
                            } else {
                                &mut dummy
                            };
                            if let Some(p) = this.pair_force(bodies, i, j, h, ctx) {
                                acc.force[i - lo] += p.force;
                                acc.force[j - lo] -= p.force;
                                if FRIC {
                                    acc.torque[i - lo] += p.torque_i;
                                    acc.torque[j - lo] += p.torque_j;
                                }
                                count += 1;
                            }
                        }
                    }
                    count
                })
                .sum();
            self.contacts = count;
        }
        let accs_ref = &accs;
        forces
            .force
            .par_iter_mut()
            .zip(forces.torque.par_iter_mut())
            .enumerate()
            .with_min_len(1024)
            .for_each(|(i, (f, t))| {
                for acc in accs_ref {
                    if acc.range.contains(&i) {
                        *f += acc.force[i - acc.range.start];
                        if FRIC {
                            *t += acc.torque[i - acc.range.start];
                        }
                    }
                }
            });
        self.pair_hist = hist;
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
        for (w, wall) in walls.walls.iter_mut().enumerate() {
            let cands = &self.wall_lists.candidates[w];
            for (c, &i) in cands.iter().enumerate() {
                let i = i as usize;
                let h = if FRIC {
                    &mut self.wall_hist[w][c]
                } else {
                    &mut dummy
                };
                let r = bodies.radius[i];
                let delta = r - wall.distance(&bodies.pos[i]);
                if delta <= 0.0 {
                    if FRIC {
                        *h = Vec3::zeros();
                    }
                    continue;
                }
                let n = wall.normal;
                let di = r - delta;
                let mut v = bodies.vel[i] - wall.velocity;
                if FRIC {
                    v -= (bodies.omega[i] * di).cross(&n);
                }
                let c = hertz_mindlin::<DAMP, FRIC>(
                    &self.k_wall,
                    &n,
                    delta,
                    r,
                    bodies.mass[i],
                    &v,
                    h,
                    ctx.dt,
                    ctx.update_history,
                );
                forces.force[i] += c.force;
                if FRIC {
                    forces.torque[i] += n.cross(&c.force) * (-di);
                }
                wall.force -= c.force;
                wall.stiffness += c.stiffness;
                wall.contacts += 1;
            }
        }
    }
}

/// Splits `data` into the consecutive sub-slices `ranges` (which start at 0 and touch).
fn split_ranges<'a, T>(mut data: &'a mut [T], ranges: &[Range<usize>]) -> Vec<&'a mut [T]> {
    let mut parts = Vec::with_capacity(ranges.len());
    let mut at = 0;
    for r in ranges {
        debug_assert_eq!(r.start, at);
        let (head, tail) = data.split_at_mut(r.end - r.start);
        parts.push(head);
        data = tail;
        at = r.end;
    }
    parts
}

impl<const DAMP: bool, const FRIC: bool> Effect for HertzContact<DAMP, FRIC> {
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
        let threads = threads_here();
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

    fn history_len(&self) -> usize {
        self.pair_hist.len() + self.wall_hist.iter().map(Vec::len).sum::<usize>()
    }

    /// `max_i sqrt(2 Σ_j k_ij / m_i)` over the normal contact stiffnesses `k = 2 E* a` of
    /// each body's contacts (walls included): a Gershgorin bound on the highest normal-mode
    /// frequency, exact for two equal spheres. Hertz contacts stiffen as they overlap, which
    /// the Rayleigh step does not see.
    fn max_frequency(&self, bodies: &Bodies, walls: &Walls) -> f64 {
        if self.pairs.offsets.len() != bodies.len() + 1 {
            return 0.0;
        }
        let two_e = 2.0 * self.params.hertz.e_eff;
        let mut stiffness = vec![0.0; bodies.len()];
        for i in 0..bodies.len() {
            for s in self.pairs.row(i) {
                let j = self.pairs.partners[s] as usize;
                let (ri, rj) = (bodies.radius[i], bodies.radius[j]);
                let delta = ri + rj - (bodies.pos[i] - bodies.pos[j]).norm();
                if delta > 0.0 {
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
        stiffness
            .iter()
            .zip(&bodies.inv_mass)
            .map(|(k, inv_m)| (2.0 * k * inv_m).sqrt())
            .fold(0.0, f64::max)
    }

    fn save(&self) -> Vec<u8> {
        if !FRIC {
            return Vec::new();
        }
        let mut saved = self.pending.clone().unwrap_or_default();
        if self.pending.is_none() {
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

    fn restore(&mut self, data: &[u8]) -> Result<()> {
        if !FRIC || data.is_empty() {
            return Ok(());
        }
        let saved: SavedHistory = postcard::from_bytes(data).map_err(|e| {
            Error::run(format!("the checkpoint's contact history is damaged ({e})"))
        })?;
        // Lists are rebuilt at the next evaluation; the histories go in then.
        self.pairs = PairList::new(self.pairs.skin);
        self.wall_lists = WallLists::default();
        self.pair_hist.clear();
        self.wall_hist.clear();
        self.pending = Some(saved);
        Ok(())
    }
}
