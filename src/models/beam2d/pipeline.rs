//! The force pipeline of the `beam2d` model: polygon contacts (`contact`, with `damping` and
//! `friction` compiled in only when the scene names them) and beams (`beams`, with
//! `beam_breaking` compiled in only when named). An effect the scene does not list is not
//! built.
//!
//! Each effect first computes every pair's or beam's force into its own buffer (in parallel
//! where that pays: the items are independent, and with several threads the contacts and the
//! beams are computed side by side), then one pass sums them per polygon in a fixed order:
//! its pairs as the first body, then as the partner, then its beams. That order does not
//! depend on the number of threads, so one and two threads give bit-identical results, and it
//! does not depend on when the neighbour list was last rebuilt (pairs that do not touch add
//! exact zeros), so a resumed run continues bit for bit. Three parallel regions per step
//! (placing the polygons, the forces, the sums): each costs a wake-up of the workers.

use rayon::prelude::*;

use super::scene::Beam2dScene;
use crate::bond::beam2d::{Beams, BreakingForm, BreakingRule};
use crate::contact::neighbor::PairList;
use crate::contact::overlap_area_2d::{
    ClipBuffers, OverlapLaw, characteristic_length, contact_force, overlap_in,
};
use crate::parallel::threads_here;
use crate::scene::{EffectKind, Scene};
use crate::shape::polygon::{MAX_VERTICES, Vec2, cross, perp};
use crate::state::Vec3;
use crate::state::polygons::Polygons;

/// Below this many polygons (or beams, or pairs) a loop stays on one thread.
const PARALLEL_MIN_ITEMS: usize = 512;
/// Smallest piece of work handed to a thread.
const PARALLEL_GRAIN: usize = 128;

fn parallel(items: usize) -> bool {
    items >= PARALLEL_MIN_ITEMS && threads_here() > 1
}

/// What one evaluation found.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StepCounts {
    /// Polygon pairs that overlap.
    pub contacts: usize,
    /// Beams that broke in this evaluation.
    pub broken: usize,
}

/// The contact effect, whatever sub-models it was compiled with.
trait ContactEffect: Send + Sync {
    fn describe(&self) -> String;
    /// Places the polygons for this step (world vertices, bounding boxes).
    fn place(&mut self, polys: &Polygons);
    /// Every pair's force into the buffer; returns the overlapping pairs.
    fn compute(&mut self, polys: &Polygons) -> usize;
    /// Adds polygon k's pair forces to `fk`.
    fn gather(&self, k: usize, fk: &mut [f64; 3]);
}

/// The beams effect, with or without breaking.
trait BeamEffect: Send + Sync {
    fn describe(&self) -> String;
    /// Every beam's force into the buffer; breaks beams; returns how many broke.
    fn compute(&mut self, polys: &Polygons, beams: &mut Beams, time: f64) -> usize;
    /// Adds polygon k's beam forces to `fk`.
    fn gather(&self, k: usize, fk: &mut [f64; 3]);
}

/// The effects of a beam2d scene, in a fixed order: contact, then beams.
pub struct PolygonPipeline {
    contact: Option<Box<dyn ContactEffect>>,
    beams: Option<Box<dyn BeamEffect>>,
}

impl PolygonPipeline {
    /// Builds exactly the effects the scene lists. `skin` is the neighbour list's skin (m).
    pub fn build(
        scene: &Scene,
        cfg: &Beam2dScene,
        polys: &Polygons,
        beams: &Beams,
        skin: f64,
    ) -> Self {
        let m = &cfg.material;
        let thickness = cfg.sample.thickness;
        let contact = scene.has_effect(EffectKind::Contact).then(|| {
            let law = OverlapLaw {
                young_thickness: m.young * thickness,
                gamma_n: m.normal_damping,
                gamma_t: m.tangential_damping,
                mu: m.friction,
            };
            let damp = scene.has_effect(EffectKind::Damping);
            let fric = scene.has_effect(EffectKind::Friction);
            let c: Box<dyn ContactEffect> = match (damp, fric) {
                (false, false) => Box::new(OverlapContact::<false, false>::new(law, skin)),
                (true, false) => Box::new(OverlapContact::<true, false>::new(law, skin)),
                (false, true) => Box::new(OverlapContact::<false, true>::new(law, skin)),
                (true, true) => Box::new(OverlapContact::<true, true>::new(law, skin)),
            };
            c
        });
        // Present exactly with the `beams` effect, and the rule with `beam_breaking`.
        let beam_effect = m.beams.map(|material| {
            let young = material.young;
            let b: Box<dyn BeamEffect> = if let Some(rule) = material.breaking {
                Box::new(BeamForces::<true>::new(
                    polys.len(),
                    beams,
                    young,
                    Some(rule),
                ))
            } else {
                Box::new(BeamForces::<false>::new(polys.len(), beams, young, None))
            };
            b
        });
        PolygonPipeline {
            contact,
            beams: beam_effect,
        }
    }

    /// Sets `f` to the forces and torques at the current state; breaks beams (at `time`).
    pub fn evaluate(
        &mut self,
        polys: &Polygons,
        beams: &mut Beams,
        time: f64,
        f: &mut [[f64; 3]],
    ) -> StepCounts {
        if let Some(c) = &mut self.contact {
            c.place(polys);
        }
        let (contact, beam) = (&mut self.contact, &mut self.beams);
        let mut contacts = move || contact.as_mut().map_or(0, |c| c.compute(polys));
        let mut broken = move || beam.as_mut().map_or(0, |b| b.compute(polys, beams, time));
        let (contacts, broken) = if threads_here() > 1 {
            rayon::join(contacts, broken)
        } else {
            (contacts(), broken())
        };
        let counts = StepCounts { contacts, broken };
        let (contact, beam) = (self.contact.as_deref(), self.beams.as_deref());
        let gather = |(k, fk): (usize, &mut [f64; 3])| {
            *fk = [0.0; 3];
            if let Some(c) = contact {
                c.gather(k, fk);
            }
            if let Some(b) = beam {
                b.gather(k, fk);
            }
        };
        if parallel(f.len()) {
            f.par_iter_mut()
                .enumerate()
                .with_min_len(PARALLEL_GRAIN)
                .for_each(gather);
        } else {
            f.iter_mut().enumerate().for_each(gather);
        }
        counts
    }

    /// One line per effect, in evaluation order.
    pub fn describe(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some(c) = &self.contact {
            lines.push(c.describe());
        }
        if let Some(b) = &self.beams {
            lines.push(b.describe());
        }
        lines
    }
}

/// One pair's contact: the force on j (i gets the opposite) and the torques on both.
#[derive(Debug, Clone, Copy, Default)]
struct PairForce {
    force_j: Vec2,
    torque_i: f64,
    torque_j: f64,
    touching: bool,
}

/// World vertices and bounding box of a polygon at the current step.
#[derive(Debug, Clone, Copy)]
struct Placed {
    n: usize,
    v: [Vec2; MAX_VERTICES],
    lo: Vec2,
    hi: Vec2,
}

impl Default for Placed {
    fn default() -> Self {
        Placed {
            n: 0,
            v: [Vec2::zeros(); MAX_VERTICES],
            lo: Vec2::zeros(),
            hi: Vec2::zeros(),
        }
    }
}

/// The overlap-area contact (Eq. 2–6) over a Verlet list of polygon pairs.
struct OverlapContact<const DAMP: bool, const FRIC: bool> {
    law: OverlapLaw,
    pairs: PairList,
    /// Centres as 3D points for the shared neighbour list.
    centres: Vec<Vec3>,
    /// The first body (row) of each pair slot.
    slot_row: Vec<u32>,
    out: Vec<PairForce>,
    placed: Vec<Placed>,
}

impl<const DAMP: bool, const FRIC: bool> OverlapContact<DAMP, FRIC> {
    fn new(law: OverlapLaw, skin: f64) -> Self {
        OverlapContact {
            law,
            pairs: PairList::new(skin),
            centres: Vec::new(),
            slot_row: Vec::new(),
            out: Vec::new(),
            placed: Vec::new(),
        }
    }

    fn place_one(polys: &Polygons, i: usize, p: &mut Placed) {
        p.n = polys.world_vertices(i, &mut p.v);
        let (mut lo, mut hi) = (p.v[0], p.v[0]);
        for v in &p.v[1..p.n] {
            lo = lo.inf(v);
            hi = hi.sup(v);
        }
        p.lo = lo;
        p.hi = hi;
    }

    #[inline(always)]
    fn pair(&self, buffers: &mut ClipBuffers, polys: &Polygons, i: usize, j: usize) -> PairForce {
        let (a, b) = (&self.placed[i], &self.placed[j]);
        if a.hi.x < b.lo.x || b.hi.x < a.lo.x || a.hi.y < b.lo.y || b.hi.y < a.lo.y {
            return PairForce::default();
        }
        let (ci, cj) = (polys.centre(i), polys.centre(j));
        let Some(o) = overlap_in(buffers, &a.v[..a.n], &b.v[..b.n], ci, cj) else {
            return PairForce::default();
        };
        let lc = characteristic_length(polys.equivalent_diameter[i], polys.equivalent_diameter[j]);
        let (ri, rj) = (o.point - ci, o.point - cj);
        let v_rel = if DAMP || FRIC {
            (polys.velocity(j) + perp(rj) * polys.v[j][2])
                - (polys.velocity(i) + perp(ri) * polys.v[i][2])
        } else {
            Vec2::zeros()
        };
        let m_eff = if DAMP || FRIC {
            let (mi, mj) = (polys.mass[i], polys.mass[j]);
            mi * mj / (mi + mj)
        } else {
            0.0
        };
        let force_j = contact_force::<DAMP, FRIC>(&self.law, &o, lc, m_eff, v_rel);
        PairForce {
            force_j,
            torque_i: -cross(ri, force_j),
            torque_j: cross(rj, force_j),
            touching: true,
        }
    }
}

impl<const DAMP: bool, const FRIC: bool> ContactEffect for OverlapContact<DAMP, FRIC> {
    fn describe(&self) -> String {
        let mut s = format!(
            "contact: overlap area, F = Y A / Lc normal to the contact line (Eq. 2), Y t = {:e} N/m, 1/Lc = (1/r_i + 1/r_j)/2",
            self.law.young_thickness
        );
        if DAMP {
            s.push_str(&format!(
                "; damping: - m_eff gamma_N v_n, gamma_N = {:e} 1/s (Eq. 3)",
                self.law.gamma_n
            ));
        }
        if FRIC {
            s.push_str(&format!(
                "; friction: min(m_eff gamma_T |v_t|, mu F_N) against sliding, gamma_T = {:e} 1/s, mu = {} (Eq. 4)",
                self.law.gamma_t, self.law.mu
            ));
        }
        s
    }

    fn place(&mut self, polys: &Polygons) {
        let n = polys.len();
        self.centres.resize(n, Vec3::zeros());
        for (c, q) in self.centres.iter_mut().zip(&polys.q) {
            *c = Vec3::new(q[0], q[1], 0.0);
        }
        if self.pairs.needs_rebuild(&self.centres) {
            self.pairs.build(&self.centres, &polys.bound_radius);
            self.slot_row.clear();
            for i in 0..n {
                let row = self.pairs.row(i);
                self.slot_row
                    .extend(std::iter::repeat_n(i as u32, row.len()));
            }
            self.out.resize(self.pairs.len(), PairForce::default());
        }
        self.placed.resize(n, Placed::default());
        if parallel(n) {
            self.placed
                .par_iter_mut()
                .enumerate()
                .with_min_len(PARALLEL_GRAIN)
                .for_each(|(i, p)| Self::place_one(polys, i, p));
        } else {
            for (i, p) in self.placed.iter_mut().enumerate() {
                Self::place_one(polys, i, p);
            }
        }
    }

    fn compute(&mut self, polys: &Polygons) -> usize {
        let mut out = std::mem::take(&mut self.out);
        {
            let this = &*self;
            let kernel = |buffers: &mut ClipBuffers, (s, o): (usize, &mut PairForce)| {
                let i = this.slot_row[s] as usize;
                let j = this.pairs.partners[s] as usize;
                *o = this.pair(buffers, polys, i, j);
            };
            if parallel(out.len()) {
                out.par_iter_mut()
                    .enumerate()
                    .with_min_len(PARALLEL_GRAIN)
                    .for_each_init(ClipBuffers::default, kernel);
            } else {
                let mut buffers = ClipBuffers::default();
                for item in out.iter_mut().enumerate() {
                    kernel(&mut buffers, item);
                }
            }
        }
        self.out = out;
        self.out.iter().filter(|p| p.touching).count()
    }

    #[inline]
    fn gather(&self, k: usize, fk: &mut [f64; 3]) {
        let (pairs, out) = (&self.pairs, &self.out);
        for s in pairs.row(k) {
            let p = &out[s];
            fk[0] -= p.force_j.x;
            fk[1] -= p.force_j.y;
            fk[2] += p.torque_i;
        }
        let t = pairs.t_offsets[k] as usize..pairs.t_offsets[k + 1] as usize;
        for &s in &pairs.t_slots[t] {
            let p = &out[s as usize];
            fk[0] += p.force_j.x;
            fk[1] += p.force_j.y;
            fk[2] += p.torque_j;
        }
    }
}

/// One beam's forces in the last evaluation.
#[derive(Debug, Clone, Copy, Default)]
struct BeamForce {
    force_j: Vec2,
    torque_i: f64,
    torque_j: f64,
    broke: bool,
}

/// The beams (Eq. 7–12), breaking by Eq. 13 when `BREAK`.
struct BeamForces<const BREAK: bool> {
    young: f64,
    rule: Option<BreakingRule>,
    out: Vec<BeamForce>,
    /// Per polygon, its beams as `2 b` (it is end i) or `2 b + 1` (end j), in beam order.
    offsets: Vec<u32>,
    ends: Vec<u32>,
}

impl<const BREAK: bool> BeamForces<BREAK> {
    fn new(n: usize, beams: &Beams, young: f64, rule: Option<BreakingRule>) -> Self {
        let mut counts = vec![0u32; n + 1];
        for b in 0..beams.len() {
            counts[beams.i[b] as usize + 1] += 1;
            counts[beams.j[b] as usize + 1] += 1;
        }
        for k in 0..n {
            counts[k + 1] += counts[k];
        }
        let mut fill = counts.clone();
        let mut ends = vec![0u32; 2 * beams.len()];
        for b in 0..beams.len() {
            for (side, end) in [(0, beams.i[b]), (1, beams.j[b])] {
                let at = &mut fill[end as usize];
                ends[*at as usize] = 2 * b as u32 + side;
                *at += 1;
            }
        }
        BeamForces {
            young,
            rule,
            out: vec![BeamForce::default(); beams.len()],
            offsets: counts,
            ends,
        }
    }
}

impl<const BREAK: bool> BeamEffect for BeamForces<BREAK> {
    fn describe(&self) -> String {
        let mut s = format!(
            "beams: Timoshenko beams between centres of mass, E = {:e} Pa, b = 2a, cross-section the shared side (Eq. 7-12)",
            self.young
        );
        if let Some(r) = self.rule {
            let (what, rule) = match r.form {
                BreakingForm::Eq13 => (
                    "stretched beams",
                    "(eps/{s})^2 + max|Theta|/{b} >= 1 (Eq. 13)",
                ),
                BreakingForm::Squared => (
                    "stretched beams",
                    "(eps/{s})^2 + (max|Theta|/{b})^2 >= 1 (not Eq. 13: both terms squared)",
                ),
                BreakingForm::MeanAngle => (
                    "stretched beams",
                    "(eps/{s})^2 + (|Theta_i| + |Theta_j|)/(2 {b}) >= 1 (not Eq. 13: the ends' mean angle)",
                ),
                BreakingForm::EitherSign => (
                    "beams stretched or compressed",
                    "(eps/{s})^2 + max|Theta|/{b} >= 1 (not Eq. 13: compressed beams break too)",
                ),
            };
            let rule = rule
                .replace("{s}", &r.strain.to_string())
                .replace("{b}", &r.bending.to_string());
            s.push_str(&format!(
                "; beam_breaking: {what} break when {rule}, for good"
            ));
        }
        s
    }

    fn compute(&mut self, polys: &Polygons, beams: &mut Beams, time: f64) -> usize {
        let rule = self.rule;
        {
            let beams_ref = &*beams;
            let kernel = |(b, o): (usize, &mut BeamForce)| {
                if !beams_ref.intact[b] {
                    *o = BeamForce::default();
                    return;
                }
                let (i, j) = (beams_ref.i[b] as usize, beams_ref.j[b] as usize);
                let r = beams_ref.response(
                    b,
                    polys.centre(i),
                    polys.q[i][2],
                    polys.centre(j),
                    polys.q[j][2],
                );
                if BREAK && rule.is_some_and(|rule| rule.breaks(&r)) {
                    *o = BeamForce {
                        broke: true,
                        ..Default::default()
                    };
                    return;
                }
                *o = BeamForce {
                    force_j: r.force_j,
                    torque_i: r.torque_i,
                    torque_j: r.torque_j,
                    broke: false,
                };
            };
            if parallel(self.out.len()) {
                self.out
                    .par_iter_mut()
                    .enumerate()
                    .with_min_len(PARALLEL_GRAIN)
                    .for_each(kernel);
            } else {
                self.out.iter_mut().enumerate().for_each(kernel);
            }
        }
        let mut broken = 0;
        if BREAK {
            for (b, o) in self.out.iter().enumerate() {
                if o.broke {
                    beams.intact[b] = false;
                    beams.broken_time[b] = time;
                    broken += 1;
                }
            }
        }
        broken
    }

    #[inline]
    fn gather(&self, k: usize, fk: &mut [f64; 3]) {
        for &e in &self.ends[self.offsets[k] as usize..self.offsets[k + 1] as usize] {
            let o = &self.out[(e >> 1) as usize];
            if e & 1 == 0 {
                fk[0] -= o.force_j.x;
                fk[1] -= o.force_j.y;
                fk[2] += o.torque_i;
            } else {
                fk[0] += o.force_j.x;
                fk[1] += o.force_j.y;
                fk[2] += o.torque_j;
            }
        }
    }
}
