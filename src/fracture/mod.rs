//! Particle fracture of the granular model (granular paper, Section 3):
//! the `fracture`, `weibull` and `cohesion` effects.
//!
//! After every step, each free grain (one not held by cohesive springs) is checked against
//! Hoek–Brown on its average stress and against the tensile stress of its contacts
//! ([`criteria`]); one that fails splits along a principal plane ([`break_plane`]) into two
//! sub-poly-ellipsoids that carry on its motion ([`subdivision`]). With `cohesion`, springs on
//! the break plane hold the halves with the forces that keep both accelerating as the parent
//! did, and soften until they break ([`cohesion`]). With `weibull`, every grain's strengths
//! are scaled by its own Weibull factor (Eq. 18). [`GrainFracture`] holds the per-grain state
//! and the springs; the run calls it in this order within a step:
//!
//! ```text
//! forces = pipeline(state)               # contacts (recorded), gravity
//! fracture.add_spring_forces(forces)     # cohesion
//! kick                                   # v(t+dt)
//! breaking = fracture.check(...)         # free grains that fail at t+dt
//! fracture.split(breaking)               # bodies change shape; new bodies appended
//! forces = pipeline(state)               # the halves' contacts (history not advanced)
//! fracture.bond(...)                     # springs with the initial forces of Eq. 40–43
//! ```

pub mod break_plane;
pub mod cohesion;
pub mod criteria;
mod grain;
mod params;
mod spec;
pub mod subdivision;

pub use grain::{
    GrainSplit, MadeSpring, angular_acceleration, bond_split, grain_average_stress, grain_fails,
    split_grain,
};
pub use params::{
    CRITICAL_CONTACTS, FractureParams, SPRINGS, equivalent_radius, grain_jitter, grain_strength,
    grain_strength_sized, key_range, platen_contact_strength,
};
pub use spec::{FractureSpec, WeibullOn};

use nalgebra::{Matrix3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use crate::contact::records::RecordsByBody;
use crate::effects::{ContactRecord, ContactRecords};
use crate::parallel::{on_team, split_ranges, team_blocks, team_parts};
use crate::probe::fragments;
use crate::state::{Bodies, Body, Forces, Vec3};
use break_plane::Trigger;
use cohesion::{Demand, Spring, SpringAction};
use subdivision::Parent;

/// Cohesive springs per part of [`GrainFracture::add_spring_forces`] on a team.
const SPRINGS_PER_PART: usize = 512;

/// Which criterion broke a grain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Criterion {
    HoekBrown,
    Contacts,
}

/// One split, for the summary and the tests.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SplitEvent {
    pub step: u64,
    pub time: f64,
    /// The parent's index, which the + half keeps, and the − half's new index.
    pub body: u32,
    pub new_body: u32,
    pub criterion: Criterion,
    /// The largest principal compression (Hoek–Brown) or the largest contact tensile stress
    /// (contacts) at the split (Pa).
    pub stress: f64,
    /// The springs made (0 without cohesion).
    pub springs: u32,
    /// The parent's shape axis normal to the break plane (0 a, 1 b, 2 c), and the halves'
    /// semi-axes a+ a- b+ b- c+ c- (m): the + half's, which the parent keeps, then the − half's.
    pub axis: u8,
    pub semi: [[f64; 6]; 2],
}

/// A grain that fails: its index, what decides its break plane, the criterion and the stress
/// that broke it (Pa: the largest principal compression, or the largest contact tensile
/// stress).
pub type Breaking = (usize, Trigger, Criterion, f64);

/// A split made this step, waiting for the halves' forces to set its springs.
#[derive(Debug, Clone, Copy)]
pub struct PendingSplit {
    pub a: usize,
    pub b: usize,
    /// The parent's centre of mass, acceleration, angular acceleration and velocity: the
    /// rigid-body field the halves must follow.
    pub centroid: Vec3,
    pub accel: Vec3,
    pub alpha: Vec3,
    pub omega: Vec3,
    /// The spring points (world) and the area each stands for (m²).
    pub points: [Vec3; 16],
    pub count: usize,
    pub area: f64,
}

/// The per-grain fracture state and the cohesive springs.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct GrainFracture {
    pub params: FractureParams,
    /// Per body: the Weibull factor of its strengths (1 without `weibull`), the grain of the
    /// sample it comes from, its splits so far and its intact springs.
    pub strength: Vec<f64>,
    pub origin: Vec<u32>,
    pub generation: Vec<u8>,
    pub bonds: Vec<u16>,
    pub springs: Vec<Spring>,
    /// Grains of the sample, and which of them have broken.
    pub broken: Vec<bool>,
    pub events: Vec<SplitEvent>,
    /// Work the springs have done on the bodies (J; negative: energy taken out, spent in
    /// fracture) and the change of kinetic plus elastic energy at the splits (J).
    pub spring_work: f64,
    pub split_energy: f64,
    /// The scene's seed: each grain's draws come from keyed streams of it ([`grain_strength`],
    /// [`grain_jitter`]).
    seed: u64,
    /// The check's per-step loads, kept between steps (not state).
    #[serde(skip)]
    loads: Vec<GrainLoad>,
    /// The check's index of the contact records by grain (with a team; not state).
    #[serde(skip)]
    by_grain: RecordsByBody,
}

/// What a grain's contacts load it with, summed contact by contact as the fracture check
/// reads it: the moment of the contact forces about its centre, `Σ f ⊗ (p − x)`, and its
/// critical contacts (contact tensile stress above σ_f times its Weibull factor): how many,
/// and the three largest (stress, point), largest first, an equal stress after those kept.
/// Fractum's check and a host's kernel calls (`fractum_kernel_grain_load_add`) sum it alike.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GrainLoad {
    pub moment: Matrix3<f64>,
    pub count: usize,
    pub stress: [f64; 3],
    pub point: [Vec3; 3],
}

impl GrainLoad {
    /// Adds one contact: `force` on the grain (centre `centre`) at `point`, with the Hertz
    /// force and radius of its contact tensile stress (Eq. 23, `poisson`), critical above
    /// `threshold` (σ_f times the grain's Weibull factor).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn add(
        &mut self,
        centre: &Vec3,
        force: &Vec3,
        point: &Vec3,
        hertz_force: f64,
        radius: f64,
        poisson: f64,
        threshold: f64,
    ) {
        self.moment += force * (point - centre).transpose();
        let st = criteria::contact_tensile_stress(hertz_force, radius, poisson);
        // Not critical unless above (NaN is never critical).
        if st.partial_cmp(&threshold) != Some(std::cmp::Ordering::Greater) {
            return;
        }
        let mut at = self.count.min(3);
        while at > 0 && self.stress[at - 1] < st {
            at -= 1;
        }
        if at < 3 {
            let mut k = self.count.min(2);
            while k > at {
                self.stress[k] = self.stress[k - 1];
                self.point[k] = self.point[k - 1];
                k -= 1;
            }
            self.stress[at] = st;
            self.point[at] = *point;
        }
        self.count += 1;
    }

    /// The points of the (at most three) largest critical contacts.
    pub fn points(&self) -> &[Vec3] {
        &self.point[..self.count.min(3)]
    }

    /// The largest critical contact tensile stress (0 without one).
    pub fn top(&self) -> f64 {
        if self.count > 0 { self.stress[0] } else { 0.0 }
    }
}

impl GrainFracture {
    /// Whether the per-body arrays fit `n` bodies and every spring and piece points at a body
    /// and grain that exist (a restored state is checked before it is stepped).
    pub fn check_lengths(&self, n: usize) -> Result<(), String> {
        crate::state::check_lengths(
            n,
            &[
                ("strength", self.strength.len()),
                ("origin", self.origin.len()),
                ("generation", self.generation.len()),
                ("bonds", self.bonds.len()),
            ],
        )?;
        if let Some(s) = self
            .springs
            .iter()
            .find(|s| s.a as usize >= n || s.b as usize >= n)
        {
            return Err(format!("a spring joins bodies {} and {} of {n}", s.a, s.b));
        }
        let grains = self.broken.len();
        if let Some(o) = self.origin.iter().find(|&&o| o as usize >= grains) {
            return Err(format!("a piece comes from grain {o} of {grains}"));
        }
        Ok(())
    }

    pub fn new(params: FractureParams, seed: u64, bodies: &Bodies) -> Self {
        let n = bodies.len();
        let mut f = GrainFracture {
            params,
            strength: Vec::with_capacity(n),
            origin: (0..n as u32).collect(),
            generation: vec![0; n],
            bonds: vec![0; n],
            springs: Vec::new(),
            broken: vec![false; n],
            events: Vec::new(),
            spring_work: 0.0,
            split_energy: 0.0,
            seed,
            loads: Vec::new(),
            by_grain: RecordsByBody::default(),
        };
        for i in 0..n {
            let s = f.draw_strength(bodies, i);
            f.strength.push(s);
        }
        f
    }

    /// Body i's Weibull factor (1 without `weibull`), by [`grain_strength`] with the body's
    /// identity and generation.
    fn draw_strength(&self, bodies: &Bodies, i: usize) -> f64 {
        let Some((w, x_m)) = self.params.weibull else {
            return 1.0;
        };
        let generation = u32::from(self.generation[i]);
        grain_strength_sized(
            self.seed,
            i as u64 + 1,
            generation,
            bodies.volume(i),
            w,
            self.params.size_exponent,
            x_m,
        )
    }

    /// Each grain's load from the last check (the force evaluation of the step before it),
    /// by grain index: zero for grains held by intact springs (not checked) and for grains
    /// made by that check's splits; empty before the first check, and after a restore until
    /// the next one (the loads are not state).
    pub fn loads(&self) -> &[GrainLoad] {
        &self.loads
    }

    /// Grains of the sample that have broken.
    pub fn broken_particles(&self) -> usize {
        self.broken.iter().filter(|&&b| b).count()
    }

    pub fn intact_springs(&self) -> usize {
        self.springs.iter().filter(|s| !s.broken).count()
    }

    /// Pieces held together by intact springs: a label per body and the number of pieces.
    pub fn pieces(&self, n: usize) -> (Vec<u32>, usize) {
        fragments::components(
            n,
            self.springs
                .iter()
                .filter(|s| !s.broken)
                .map(|s| (s.a as usize, s.b as usize)),
        )
    }

    /// Fragments: the pieces that come from broken grains.
    pub fn fragments(&self, n: usize) -> usize {
        let (labels, count) = self.pieces(n);
        let mut from_broken = vec![false; count];
        for (i, &l) in labels.iter().enumerate() {
            if self.broken[self.origin[i] as usize] {
                from_broken[l as usize] = true;
            }
        }
        from_broken.iter().filter(|&&b| b).count()
    }

    /// The cohesive spring forces at the current positions (Eq. 35), added to `forces`; springs
    /// whose force has fallen to zero break.
    pub fn add_spring_forces(&mut self, bodies: &Bodies, forces: &mut Forces) {
        let act = |s: &mut Spring| {
            (!s.broken).then(|| {
                let (a, b) = (s.a as usize, s.b as usize);
                s.act(
                    &bodies.pos[a],
                    &bodies.orientation[a],
                    &bodies.pos[b],
                    &bodies.orientation[b],
                )
            })
        };
        let mut work = 0.0;
        let bonds = &mut self.bonds;
        let mut apply = |s: &Spring, f: SpringAction| {
            let (a, b) = (s.a as usize, s.b as usize);
            work += f.work;
            if f.broke {
                bonds[a] -= 1;
                bonds[b] -= 1;
                return;
            }
            forces.force[a] += f.force;
            forces.force[b] -= f.force;
            forces.torque[a] += f.torque_a;
            forces.torque[b] += f.torque_b;
        };
        // With a team the springs act in parts across its members (each spring's own state
        // only) and their forces are added here in spring order as on one thread: the same
        // bits whatever the thread count.
        match team_parts(self.springs.len(), SPRINGS_PER_PART) {
            Some(parts) => {
                let pieces = split_ranges(&mut self.springs, &parts);
                let acted = on_team(pieces, |_, springs| {
                    springs.iter_mut().map(act).collect::<Vec<_>>()
                });
                for (s, f) in self.springs.iter().zip(acted.into_iter().flatten()) {
                    if let Some(f) = f {
                        apply(s, f);
                    }
                }
            }
            None => {
                for s in self.springs.iter_mut() {
                    if let Some(f) = act(s) {
                        apply(s, f);
                    }
                }
            }
        }
        self.spring_work += work;
    }

    /// The free grains that fail at the current state, in index order, with what broke them.
    /// `records` are the contacts of the force evaluation that gave `forces`.
    pub fn check(
        &mut self,
        bodies: &Bodies,
        forces: &Forces,
        records: &ContactRecords,
    ) -> Vec<Breaking> {
        let n = bodies.len();
        let p = &self.params;
        let bonds = &self.bonds;
        let strength = &self.strength;
        let add = |load: &mut GrainLoad, i: usize, force: Vec3, r: &ContactRecord| {
            load.add(
                &bodies.pos[i],
                &force,
                &r.point,
                r.hertz_force,
                r.radius,
                p.poisson,
                p.contact_strength(strength[i]),
            );
        };
        let list = &records.list;
        let loads = &mut self.loads;
        match team_blocks(n) {
            // With a team each grain sums its own contacts, found through an index of the
            // records by grain (in record order, so in the order one thread adds them: the
            // same bits), in blocks across the members. Summed record by record on the
            // caller, this was a third of the main job's serial time on two threads.
            Some(blocks) => {
                let index = &mut self.by_grain;
                index.build(n, list);
                let index = &*index;
                // Set to zero in the blocks, not here: a serial pass over every grain's load.
                loads.resize(n, GrainLoad::default());
                let parts = split_ranges(loads, &blocks);
                on_team(
                    blocks.into_iter().zip(parts).collect(),
                    |_, (grains, loads)| {
                        for (i, load) in grains.zip(loads.iter_mut()) {
                            *load = GrainLoad::default();
                            if bonds[i] != 0 {
                                continue;
                            }
                            for &k in index.of(i) {
                                let r = &list[k as usize];
                                let force = if r.i as usize == i { r.force } else { -r.force };
                                add(load, i, force, r);
                            }
                        }
                    },
                );
            }
            None => {
                loads.clear();
                loads.resize(n, GrainLoad::default());
                for r in list {
                    let (i, j) = (r.i as usize, r.j as usize);
                    if bonds[i] == 0 {
                        add(&mut loads[i], i, r.force, r);
                    }
                    if r.wall().is_none() && bonds[j] == 0 {
                        add(&mut loads[j], j, -r.force, r);
                    }
                }
            }
        }
        // Each grain's criteria read only its own sums: grains are checked in blocks dealt
        // across the run's team, and the blocks' verdicts joined in grain order.
        let loads = &*loads;
        let verdicts = |grains: std::ops::Range<usize>| {
            let mut out = Vec::new();
            for i in grains {
                let load = &loads[i];
                let m = &load.moment;
                if bonds[i] != 0
                    || *m == Matrix3::zeros()
                    || p.below_comminution_limit(bodies.volume(i))
                {
                    continue;
                }
                if let Some((trigger, criterion, stress)) = grain_fails(
                    p,
                    &bodies.body(i),
                    strength[i],
                    m,
                    &forces.torque[i],
                    load.count,
                    load.points(),
                    load.top(),
                ) {
                    out.push((i, trigger, criterion, stress));
                }
            }
            out
        };
        match team_blocks(n) {
            Some(blocks) => on_team(blocks, |_, grains| verdicts(grains))
                .into_iter()
                .flatten()
                .collect(),
            None => verdicts(0..n),
        }
    }

    /// Splits the breaking grains: each parent becomes its + half in place and its − half is
    /// appended. Returns what [`GrainFracture::bond`] needs once the halves' forces are known.
    pub fn split(
        &mut self,
        bodies: &mut Bodies,
        forces: &Forces,
        breaking: &[Breaking],
        step: u64,
        time: f64,
    ) -> Vec<PendingSplit> {
        let mut pending = Vec::new();
        for &(i, trigger, criterion, stress) in breaking {
            // A sphere's slight random rotation, keyed by the parent and its generation.
            let jitter = (bodies.shape[i].is_sphere() && self.params.plane_jitter)
                .then(|| grain_jitter(self.seed, i as u64 + 1, u32::from(self.generation[i])));
            let Some(made) = split_grain(
                &self.params,
                &bodies.body(i),
                &forces.force[i],
                &forces.torque[i],
                &trigger,
                jitter,
            ) else {
                continue;
            };
            bodies.set(i, &made.plus);
            let b = bodies.push(made.minus);
            self.origin.push(self.origin[i]);
            let generation = self.generation[i].saturating_add(1);
            self.generation[i] = generation;
            self.generation.push(generation);
            self.bonds.push(0);
            self.strength.push(0.0);
            self.strength[i] = self.draw_strength(bodies, i);
            self.strength[b] = self.draw_strength(bodies, b);
            self.broken[self.origin[i] as usize] = true;
            self.events.push(SplitEvent {
                step,
                time,
                body: i as u32,
                new_body: b as u32,
                criterion,
                stress,
                springs: 0,
                axis: made.axis as u8,
                semi: [
                    made.plus.shape.semi_axes(made.plus.radius),
                    made.minus.shape.semi_axes(made.minus.radius),
                ],
            });
            pending.push(PendingSplit {
                a: i,
                b,
                ..made.pending
            });
        }
        pending
    }

    /// Makes the springs of this step's splits (with `cohesion`) from the halves' forces at
    /// their new shapes (`forces`, evaluated after the split): their initial forces make each
    /// half accelerate and turn as the parent did (Eq. 39–43), and they are added to `forces`.
    pub fn bond(&mut self, bodies: &Bodies, forces: &mut Forces, pending: &[PendingSplit]) {
        let Some((gc, _)) = self.params.cohesion else {
            return;
        };
        for (split, event) in pending
            .iter()
            .zip(self.events.iter_mut().rev().take(pending.len()).rev())
        {
            let (a, b) = (split.a, split.b);
            let mut made = 0;
            let (force_a, torque_a) = (forces.force[a], forces.torque[a]);
            let (force_b, torque_b) = (forces.force[b], forces.torque[b]);
            bond_split(
                gc,
                &bodies.body(a),
                &bodies.body(b),
                [&force_a, &torque_a, &force_b, &torque_b],
                split,
                |m| {
                    self.springs.push(Spring {
                        a: a as u32,
                        b: b as u32,
                        ..m.spring
                    });
                    forces.force[a] += m.force;
                    forces.force[b] -= m.force;
                    forces.torque[a] += m.torque_a;
                    forces.torque[b] += m.torque_b;
                    made += 1;
                },
            );
            self.bonds[a] += made;
            self.bonds[b] += made;
            event.springs = made as u32;
        }
    }
}

#[cfg(test)]
mod tests;
