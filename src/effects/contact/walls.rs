//! The wall loop: each body's contacts with the walls and the sleeve, and their forces.

use super::*;
use crate::contact::pair::sleeve_contact;
use crate::state::{BoxFace, SLEEVE_SLICES};

/// What one surface's loop needs besides its kernel: the bodies, this evaluation's placements,
/// and what each candidate remembers (tangential displacement with FRIC, held Hertz radius with
/// POLY), with the sums every contact adds to (the bodies' forces, the records or the
/// stiffness sums).
struct SurfaceLoop<'a> {
    bodies: &'a Bodies,
    placements: &'a [Placement],
    hist: &'a mut Vec<Vec<Vec3>>,
    radius: &'a mut Vec<Vec<f64>>,
    forces: &'a mut Forces,
    records: &'a mut ContactRecords,
    stiffness: &'a mut Vec<f64>,
}

impl SurfaceLoop<'_> {
    /// Evaluates `kernel` (a body, its tangential displacement and held radius) on each of
    /// `candidates`, the candidate list `w`, adds each contact's force and torque to its body
    /// and its record (or stiffness), and hands it to `surface`. With a team (POLY) the kernel
    /// runs in parts of the list across its members (each candidate's own memory only) and the
    /// contacts are added here in candidate order, as on one thread: the same bits.
    fn run<const FRIC: bool, const POLY: bool>(
        &mut self,
        w: usize,
        candidates: &[u32],
        kernel: impl Fn(&BodyAt, &mut Vec3, &mut f64) -> Option<PairOut> + Sync,
        mut surface: impl FnMut(&PairOut),
    ) {
        let (bodies, placements) = (self.bodies, self.placements);
        let evaluate = |i: u32, h: &mut Vec3, held: &mut f64| {
            let body = BodyAt {
                bodies,
                placements,
                i: i as usize,
            };
            kernel(&body, h, held)
        };
        // Spheres' wall contacts cost a few tens of nanoseconds: parts would not pay.
        let parts = if POLY {
            team_parts(candidates.len(), CANDIDATES_PER_PART)
        } else {
            None
        };
        let Some(parts) = parts else {
            let (mut dummy, mut dummy_radius) = (Vec3::zeros(), 0.0);
            for (c, &i) in candidates.iter().enumerate() {
                let h = if FRIC {
                    &mut self.hist[w][c]
                } else {
                    &mut dummy
                };
                let held = if POLY {
                    &mut self.radius[w][c]
                } else {
                    &mut dummy_radius
                };
                if let Some(p) = evaluate(i, h, held) {
                    self.add::<FRIC, POLY>(i as usize, w, &p);
                    surface(&p);
                }
            }
            return;
        };
        // A candidate's memory of what the variant keeps (the other lists are empty).
        fn pieces<'a, T>(
            data: &'a mut [Vec<T>],
            w: usize,
            on: bool,
            parts: &[Range<usize>],
        ) -> Vec<&'a mut [T]> {
            match data.get_mut(w) {
                Some(list) if on => split_ranges(list, parts),
                _ => parts.iter().map(|_| &mut [][..]).collect(),
            }
        }
        let work: Vec<_> = parts
            .iter()
            .cloned()
            .zip(pieces(self.hist, w, FRIC, &parts))
            .zip(pieces(self.radius, w, POLY, &parts))
            .collect();
        let found = on_team(work, |_, ((range, hist), radius)| {
            let (mut dummy, mut dummy_radius) = (Vec3::zeros(), 0.0);
            range
                .enumerate()
                .map(|(k, c)| {
                    let h = if FRIC { &mut hist[k] } else { &mut dummy };
                    let held = if POLY {
                        &mut radius[k]
                    } else {
                        &mut dummy_radius
                    };
                    evaluate(candidates[c], h, held)
                })
                .collect::<Vec<_>>()
        });
        for (&i, p) in candidates.iter().zip(found.into_iter().flatten()) {
            if let Some(p) = p {
                self.add::<FRIC, POLY>(i as usize, w, &p);
                surface(&p);
            }
        }
    }

    /// Adds the contact `p` of body `i` with surface `w` to the body's sums and the records.
    #[inline(always)]
    fn add<const FRIC: bool, const POLY: bool>(&mut self, i: usize, w: usize, p: &PairOut) {
        self.forces.force[i] += p.force;
        if FRIC || POLY {
            self.forces.torque[i] += p.torque_i;
        }
        if POLY {
            self.records.list.push(p.record(i, WALL | w as u32));
            self.records.dissipated += p.c.dissipated;
        } else {
            self.stiffness[i] += p.c.stiffness;
        }
    }
}

/// Wall candidates per part of [`SurfaceLoop::run`] on a team.
const CANDIDATES_PER_PART: usize = 32;

impl<const DAMP: bool, const FRIC: bool, const POLY: bool> HertzContact<DAMP, FRIC, POLY> {
    pub(super) fn walls_serial(
        &mut self,
        bodies: &Bodies,
        walls: &mut Walls,
        forces: &mut Forces,
        ctx: &StepContext,
    ) {
        let mut wall_hist = std::mem::take(&mut self.wall_hist);
        let mut wall_radius = std::mem::take(&mut self.wall_radius);
        let mut records = std::mem::take(&mut self.records);
        let mut stiffness = std::mem::take(&mut self.body_stiffness);
        let this = &*self;
        let mut each = SurfaceLoop {
            bodies,
            placements: &this.placements,
            hist: &mut wall_hist,
            radius: &mut wall_radius,
            forces,
            records: &mut records,
            stiffness: &mut stiffness,
        };
        let (dt, update) = (ctx.dt, ctx.update_history);
        let sleeve_list = walls.walls.len();
        for (w, wall) in walls.walls.iter_mut().enumerate() {
            let (normal, point, velocity) = (wall.normal, wall.point, wall.velocity);
            each.run::<FRIC, POLY>(
                w,
                &this.wall_lists.candidates[w],
                |body, h, held| {
                    wall_contact::<DAMP, FRIC, POLY>(
                        &this.k_wall,
                        body,
                        &normal,
                        &point,
                        &velocity,
                        h,
                        held,
                        dt,
                        update,
                    )
                },
                |p| {
                    wall.force -= p.force;
                    wall.stiffness += p.c.stiffness;
                    wall.contacts += 1;
                },
            );
        }
        if let Some(sleeve) = &mut walls.sleeve {
            // The slices of the span between the box's z faces (the bars' faces).
            let z0 = walls.walls[BoxFace::ZMin as usize].point.z;
            let height = walls.walls[BoxFace::ZMax as usize].point.z - z0;
            let geometry = sleeve.clone();
            each.run::<FRIC, POLY>(
                sleeve_list,
                &this.wall_lists.candidates[sleeve_list],
                |body, h, held| {
                    sleeve_contact::<DAMP, FRIC, POLY>(
                        &this.k_sleeve,
                        body,
                        &geometry,
                        h,
                        held,
                        dt,
                        update,
                    )
                },
                |p| {
                    let load = p.force.dot(&p.normal);
                    let slice = ((p.point.z - z0) / height * SLEEVE_SLICES as f64).floor();
                    // A point beyond either face (a grain pressed into it) counts in the end
                    // slice.
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
                },
            );
        }
        self.wall_hist = wall_hist;
        self.wall_radius = wall_radius;
        self.records = records;
        self.body_stiffness = stiffness;
    }
}
