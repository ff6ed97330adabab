//! The `contact` effect of the beam2d model: the overlap-area contact (Eq. 2–6) over a Verlet
//! list of polygon pairs, with `damping` and `friction` compiled in only when the scene names
//! them. Every pair's force goes into a buffer; [`ContactEffect::gather`] sums a polygon's.

use rayon::prelude::*;

use super::super::scene::Beam2dScene;
use super::{PARALLEL_GRAIN, parallel};
use crate::contact::neighbor::PairList;
use crate::contact::overlap_area_2d::{
    ClipBuffers, OverlapLaw, characteristic_length, contact_force, overlap_in,
};
use crate::scene::{EffectKind, Scene};
use crate::shape::polygon::{MAX_VERTICES, Vec2, cross, perp};
use crate::state::Vec3;
use crate::state::polygons::Polygons;

/// The contact effect, whatever sub-models it was compiled with.
pub(super) trait ContactEffect: Send + Sync {
    fn describe(&self) -> String;
    /// Places the polygons for this step (world vertices, bounding boxes).
    fn place(&mut self, polys: &Polygons);
    /// Every pair's force into the buffer; returns the overlapping pairs.
    fn compute(&mut self, polys: &Polygons) -> usize;
    /// Adds polygon k's pair forces to `fk`.
    fn gather(&self, k: usize, fk: &mut [f64; 3]);
}

/// The contact effect with exactly the sub-models the scene names; none without `contact`.
/// `skin` is the neighbour list's skin (m).
pub(super) fn build(scene: &Scene, cfg: &Beam2dScene, skin: f64) -> Option<Box<dyn ContactEffect>> {
    let m = &cfg.material;
    let thickness = cfg.sample.thickness;
    scene.has_effect(EffectKind::Contact).then(|| {
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
    })
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
