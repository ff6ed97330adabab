//! The `beams` effect of the beam2d model: Timoshenko beams between the polygons' centres
//! (Eq. 7–12), breaking by Eq. 13 compiled in only with `beam_breaking`. Every beam's force
//! goes into a buffer; [`BeamEffect::gather`] sums a polygon's.

use rayon::prelude::*;

use super::super::scene::Beam2dScene;
use super::{PARALLEL_GRAIN, parallel};
use crate::bond::beam2d::{Beams, BreakingForm, BreakingRule};
use crate::shape::polygon::Vec2;
use crate::state::polygons::Polygons;

/// The beams effect, with or without breaking.
pub(super) trait BeamEffect: Send + Sync {
    fn describe(&self) -> String;
    /// Every beam's force into the buffer; breaks beams; returns how many broke.
    fn compute(&mut self, polys: &Polygons, beams: &mut Beams, time: f64) -> usize;
    /// Adds polygon k's beam forces to `fk`.
    fn gather(&self, k: usize, fk: &mut [f64; 3]);
}

/// The beams effect over `beams` of the `polys`' polygons: present exactly with the `beams`
/// effect, and the rule with `beam_breaking`.
pub(super) fn build(
    cfg: &Beam2dScene,
    polys: &Polygons,
    beams: &Beams,
) -> Option<Box<dyn BeamEffect>> {
    cfg.material.beams.map(|material| {
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
    })
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
