//! The wall loop: each body's contacts with the walls, and the walls' forces.

use super::*;
use crate::contact::pair::sleeve_contact;
use crate::state::{BoxFace, SLEEVE_SLICES};

impl<const DAMP: bool, const FRIC: bool, const POLY: bool> HertzContact<DAMP, FRIC, POLY> {
    pub(super) fn walls_serial(
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
        let mut stiffness = std::mem::take(&mut self.body_stiffness);
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
                } else {
                    stiffness[i] += p.c.stiffness;
                }
                wall.force -= p.force;
                wall.stiffness += p.c.stiffness;
                wall.contacts += 1;
            }
        }
        if let Some(sleeve) = &mut walls.sleeve {
            // The slices of the span between the box's z faces (the bars' faces).
            let z0 = walls.walls[BoxFace::ZMin as usize].point.z;
            let height = walls.walls[BoxFace::ZMax as usize].point.z - z0;
            let w = walls.walls.len();
            for (c, &i) in this.wall_lists.candidates[w].iter().enumerate() {
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
                let Some(p) = sleeve_contact::<DAMP, FRIC, POLY>(
                    &this.k_sleeve,
                    &body,
                    sleeve,
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
                } else {
                    stiffness[i] += p.c.stiffness;
                }
                let load = p.force.dot(&p.normal);
                let slice = ((p.point.z - z0) / height * SLEEVE_SLICES as f64).floor();
                // A point beyond either face (a grain pressed into it) counts in the end slice.
                let slice = if slice.is_nan() {
                    0
                } else {
                    (slice.max(0.0) as usize).min(SLEEVE_SLICES - 1)
                };
                sleeve.force -= p.force;
                sleeve.load += load;
                sleeve.slices[slice] += load;
                sleeve.stiffness += p.c.stiffness;
                sleeve.contacts += 1;
            }
        }
        self.wall_hist = wall_hist;
        self.wall_radius = wall_radius;
        self.records = records;
        self.body_stiffness = stiffness;
    }
}
