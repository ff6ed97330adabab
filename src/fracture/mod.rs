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
mod spec;
pub mod subdivision;

pub use spec::{FractureSpec, WeibullOn};

use nalgebra::{Matrix3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use crate::effects::ContactRecords;
use crate::parallel::{on_team, team_blocks};
use crate::probe::fragments;
use crate::state::{Bodies, Body, Forces, Vec3};
use break_plane::Trigger;
use cohesion::{Demand, Spring};
use subdivision::Parent;

/// The scene's fracture constants, resolved.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FractureParams {
    pub mi: f64,
    pub sigma_c: f64,
    /// Contact tensile strength σ_fM (Pa).
    pub sigma_f: f64,
    /// Weibull modulus and reference radius, with `weibull`.
    pub weibull: Option<(f64, f64)>,
    /// Size exponent β of the Weibull factor: strengths ∝ (x/x_M)^(−β) (`size_exponent`,
    /// default 2/w).
    pub size_exponent: f64,
    /// The Weibull factor scales σc of Hoek–Brown too (`weibull_on = "both"` or
    /// `"particle"`); it always scales the contact tensile strength.
    pub weibull_sigma_c: bool,
    /// The Weibull factor is the grain's particle strength (`weibull_on = "particle"`): σc
    /// scales with it and the contact tensile strength with its cube root.
    pub particle_strength: bool,
    /// Equivalent radius (m) below which a piece no longer splits (`comminution_limit`);
    /// 0: every piece may split.
    pub comminution_limit: f64,
    pub critical_contacts: usize,
    /// Cohesive energy G_c (J/m²) and springs per plane, with `cohesion`.
    pub cohesion: Option<(f64, usize)>,
    pub ideal_plane: bool,
    pub plane_jitter: bool,
    pub poisson: f64,
}

impl FractureParams {
    /// The constants of `spec` for grains of Young's modulus `young` (Pa) and Poisson's ratio
    /// `poisson`, with Weibull statistics and cohesion as asked.
    pub fn new(
        spec: &FractureSpec,
        young: f64,
        poisson: f64,
        weibull: bool,
        cohesion: bool,
    ) -> Self {
        let f = spec;
        let particle = weibull && f.weibull_on == WeibullOn::Particle;
        let sigma_f = match (f.reference_strength, f.reference_radius) {
            (Some(s), _) => s,
            (None, Some(x_m)) if particle => {
                platen_contact_strength(f.sigma_c, x_m, young, poisson)
            }
            _ => f64::NAN,
        };
        FractureParams {
            mi: f.mi,
            sigma_c: f.sigma_c,
            sigma_f,
            weibull: weibull.then(|| (f.weibull_modulus, f.reference_radius.unwrap_or(f64::NAN))),
            size_exponent: f.size_exponent.unwrap_or(2.0 / f.weibull_modulus),
            weibull_sigma_c: weibull && f.weibull_on != WeibullOn::Contact,
            particle_strength: particle,
            comminution_limit: f.comminution_limit.unwrap_or(0.0),
            critical_contacts: f.critical_contacts,
            cohesion: cohesion.then(|| {
                (
                    cohesion::cohesive_energy(f.toughness, young, poisson),
                    f.springs,
                )
            }),
            ideal_plane: f.ideal_plane,
            plane_jitter: f.plane_jitter,
            poisson,
        }
    }
}

impl FractureParams {
    /// The contact tensile strength (Pa) of a grain of Weibull factor `factor`: σ_fM times
    /// the factor, or times its cube root when the factor is the particle strength (at a
    /// given contact force the Hertz edge stress grows as the force's cube root, so a grain
    /// whose crushing force is `factor` times the reference grain's fails at its contacts at
    /// `factor^(1/3)` times the stress).
    pub fn contact_strength(&self, factor: f64) -> f64 {
        if self.particle_strength {
            self.sigma_f * factor.cbrt()
        } else {
            self.sigma_f * factor
        }
    }

    /// Hoek–Brown's σc (Pa) for a grain of Weibull factor `factor`.
    pub fn compressive_strength(&self, factor: f64) -> f64 {
        if self.weibull_sigma_c {
            self.sigma_c * factor
        } else {
            self.sigma_c
        }
    }

    /// Whether a piece of volume `volume` (m³) is below the comminution limit: it no longer
    /// splits.
    pub fn below_comminution_limit(&self, volume: f64) -> bool {
        self.comminution_limit > 0.0 && equivalent_radius(volume) < self.comminution_limit
    }
}

/// The contact tensile strength (Pa) that goes with Hoek–Brown's `sigma_c` for a grain of
/// radius `x_m` (m) between flat platens: the Hertz edge stress (Eq. 17) at its platen
/// contacts when it fails by Hoek–Brown. A sphere under two opposite forces F has the
/// average stress 3F/(2π x_m²) along them and none across (Eq. 8), so it fails at
/// F = (2π/3) σc x_m²; each platen contact then has the radius a = (3 F x_m / (4 E*))^⅓ with
/// E* = E / (2 (1 − ν²)) (the wall as the contact law takes it) and the edge stress
/// (1 − 2ν)/3 · 3F/(2π a²). With `weibull_on = "particle"` this is the default
/// `reference_strength`: one particle strength sets both criteria, as a crushing test
/// between platens measures it.
pub fn platen_contact_strength(sigma_c: f64, x_m: f64, young: f64, poisson: f64) -> f64 {
    let e_star = young / (2.0 * (1.0 - poisson * poisson));
    let force = 2.0 * std::f64::consts::PI / 3.0 * sigma_c * x_m * x_m;
    let a = (3.0 * force * x_m / (4.0 * e_star)).cbrt();
    criteria::contact_tensile_stress(force, a, poisson)
}

/// The equivalent radius (3V/4π)^⅓ (m) of a volume `volume` (m³): the size of Eq. 18.
pub fn equivalent_radius(volume: f64) -> f64 {
    (3.0 * volume / (4.0 * std::f64::consts::PI)).cbrt()
}

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

/// The allowed ranges (inclusive) of the fracture keys that count things, the one place that
/// the scene's checks, the kernels and the LAMMPS plugin's arguments take them from: the
/// critical contacts that break a grain (three points span a break plane; Section 3.3.2 uses
/// three) and the cohesive springs on a break plane (at least three hold the plane, the
/// kernels and the plugin keep 16 slots per plane).
pub const CRITICAL_CONTACTS: (usize, usize) = (3, 64);
pub const SPRINGS: (usize, usize) = (3, 16);

/// The range of fracture key `key` (`"critical_contacts"` or `"springs"`), `None` for another.
pub fn key_range(key: &str) -> Option<(usize, usize)> {
    match key {
        "critical_contacts" => Some(CRITICAL_CONTACTS),
        "springs" => Some(SPRINGS),
        _ => None,
    }
}

/// The keys of a grain's draws on the scene seed's keyed streams
/// ([`crate::sample::uniforms`]): the kind of draw times 2⁴⁰ plus the grain's identity.
const KEY_STRENGTH: u64 = 1 << 40;
const KEY_JITTER: u64 = 2 << 40;

/// The Weibull factor of the strengths of grain `grain` after `generation` splits (Eq. 20-22:
/// a fresh probability for each grain and each half, the size effect through the equivalent
/// radius of its volume `volume`, m³), with modulus `w` and reference size `x_m` (m). `grain`
/// is the grain's identity: 1 + its index among the bodies when it was made (a sample's grain
/// at its place, a split's − half where it is appended), which is the atom ID of the same
/// grain in a LAMMPS run of `fractum export lammps --plugin`. The draw depends on the seed,
/// the grain and the generation only, not on the order grains are drawn in: the same in
/// Fractum's run and in the plugin's, on any rank count.
pub fn grain_strength(
    seed: u64,
    grain: u64,
    generation: u32,
    volume: f64,
    w: f64,
    x_m: f64,
) -> f64 {
    grain_strength_sized(seed, grain, generation, volume, w, 2.0 / w, x_m)
}

/// [`grain_strength`] with the size exponent `beta` given ((x/x_M)^(−β) instead of Eq. 18's
/// (x/x_M)^(−2/w)); the same draw.
pub fn grain_strength_sized(
    seed: u64,
    grain: u64,
    generation: u32,
    volume: f64,
    w: f64,
    beta: f64,
    x_m: f64,
) -> f64 {
    let mut p = [0.0];
    crate::sample::uniforms(seed, KEY_STRENGTH + grain, u64::from(generation), &mut p);
    criteria::weibull_factor_sized(p[0], w, beta, equivalent_radius(volume), x_m)
}

/// The angles (rad) of the slight random rotation of sphere `grain`'s ideal break plane at
/// its split after `generation` splits (`break_plane::jitter_angles`), drawn as
/// [`grain_strength`] draws: keyed by seed, grain and generation.
pub fn grain_jitter(seed: u64, grain: u64, generation: u32) -> [f64; 3] {
    let mut u = [0.0; 6];
    crate::sample::uniforms(seed, KEY_JITTER + grain, u64::from(generation), &mut u);
    break_plane::jitter_angles(&u)
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
        let mut work = 0.0;
        for s in self.springs.iter_mut().filter(|s| !s.broken) {
            let (a, b) = (s.a as usize, s.b as usize);
            let f = s.act(
                &bodies.pos[a],
                &bodies.orientation[a],
                &bodies.pos[b],
                &bodies.orientation[b],
            );
            work += f.work;
            if f.broke {
                self.bonds[a] -= 1;
                self.bonds[b] -= 1;
                continue;
            }
            forces.force[a] += f.force;
            forces.force[b] -= f.force;
            forces.torque[a] += f.torque_a;
            forces.torque[b] += f.torque_b;
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
        let loads = &mut self.loads;
        loads.clear();
        loads.resize(n, GrainLoad::default());
        let bonds = &self.bonds;
        let strength = &self.strength;
        let mut touch = |i: usize, force: Vec3, r: &crate::effects::ContactRecord| {
            if bonds[i] != 0 {
                return;
            }
            let threshold = p.contact_strength(strength[i]);
            loads[i].add(
                &bodies.pos[i],
                &force,
                &r.point,
                r.hertz_force,
                r.radius,
                p.poisson,
                threshold,
            );
        };
        for r in &records.list {
            touch(r.i as usize, r.force, r);
            if r.wall().is_none() {
                touch(r.j as usize, -r.force, r);
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

/// The average stress of a grain (Pa, tension positive, world frame; Eq. 8–13) from its
/// contact moment `Σ f ⊗ x` (N·m, x from its centre of mass) and its motion: the angular
/// acceleration from `torque` (N·m, world) and its angular velocity.
pub fn grain_average_stress(body: &Body, moment: &Matrix3<f64>, torque: &Vec3) -> Matrix3<f64> {
    let rot = body.orientation.to_rotation_matrix().into_inner();
    let mass_moment = criteria::mass_moment(&body.inertia, &rot);
    let alpha = angular_acceleration(body, torque);
    let v = body.volume();
    criteria::average_stress_from_moment(v, moment, &mass_moment, &alpha, &body.omega)
}

/// Whether a free grain fails, and why: the per-grain decision of [`GrainFracture::check`].
/// Hoek–Brown first, on the average stress ([`grain_average_stress`] of the contact moment
/// `moment` and the torque `torque`) with σc, scaled by the grain's Weibull factor `strength`
/// where `p.weibull_sigma_c` says so;
/// then the contacts: `critical` contacts whose tensile stress exceeds σ_fM × `strength`, at
/// least `critical_contacts` of them, with `points` the first (at most 3) of their points
/// (largest stress first; world, m) spanning a plane, `top_stress` (Pa) the largest stress.
/// Returns the trigger, the criterion and the stress that broke the grain (Pa).
#[allow(clippy::too_many_arguments)]
pub fn grain_fails(
    p: &FractureParams,
    body: &Body,
    strength: f64,
    moment: &Matrix3<f64>,
    torque: &Vec3,
    critical: usize,
    points: &[Vec3],
    top_stress: f64,
) -> Option<(Trigger, Criterion, f64)> {
    let stress = grain_average_stress(body, moment, torque);
    let sigma_c = p.compressive_strength(strength);
    // Most grains are far from failing: a bound on the principal values first.
    if criteria::hoek_brown_may_fail(&stress, sigma_c, p.mi) {
        let [s1, _, s3] = criteria::principal_compression_values(&stress);
        if criteria::hoek_brown_fails(s1, s3, sigma_c, p.mi) {
            return Some((Trigger::HoekBrown { stress }, Criterion::HoekBrown, s1));
        }
    }
    if critical >= p.critical_contacts {
        let points = &points[..points.len().min(3)];
        if let Some(normal) = break_plane::contacts_plane_normal(points) {
            return Some((
                Trigger::Contacts { normal },
                Criterion::Contacts,
                top_stress,
            ));
        }
    }
    None
}

/// One split of a grain ([`split_grain`]): the axis of the parent's shape frame it split
/// normal to, the + half (which the parent becomes), the − half (a new body) and what
/// bonding them needs (its body indices `a`, `b` are the caller's to set).
#[derive(Debug, Clone, Copy)]
pub struct GrainSplit {
    pub axis: usize,
    pub plus: Body,
    pub minus: Body,
    pub pending: PendingSplit,
}

/// Splits `body` under the force and torque `force`, `torque` (N, N·m, world) that it carries,
/// for the reason `trigger`: the break plane (a sphere first turns to the ideal plane and by
/// the slight rotation `jitter`, the angles of [`grain_jitter`], when
/// the scene asks), the two halves with the parent's motion, and the pending bond with its
/// spring points (with cohesion). `None` when the grain's shape forbids breaking.
pub fn split_grain(
    p: &FractureParams,
    body: &Body,
    force: &Vec3,
    torque: &Vec3,
    trigger: &Trigger,
    jitter: Option<[f64; 3]>,
) -> Option<GrainSplit> {
    let mut body = *body;
    let (parent, axis) = break_geometry(p, &mut body, trigger, jitter)?;
    let [plus, minus] = subdivision::split(&parent, axis);
    let accel = force * body.inv_mass;
    let alpha = angular_acceleration(&body, torque);
    let half = |h: &subdivision::Half| Body {
        vel: h.velocity,
        omega: parent.omega,
        ..Body::poly_ellipsoid(h.pe, h.mass, h.centroid, parent.frame)
    };
    let mut pending = PendingSplit {
        a: 0,
        b: 0,
        centroid: parent.centroid,
        accel,
        alpha,
        omega: parent.omega,
        points: [Vec3::zeros(); 16],
        count: 0,
        area: 0.0,
    };
    if let Some((_, ns)) = p.cohesion {
        let (local, area) = cohesion::spring_layout(&parent.semi, axis, ns);
        for (k, q) in local.iter().enumerate() {
            pending.points[k] = parent.origin + parent.frame * q;
        }
        pending.count = local.len();
        pending.area = area;
    }
    Some(GrainSplit {
        axis,
        plus: half(&plus),
        minus: half(&minus),
        pending,
    })
}

/// The parent of a split as the subdivision sees it and the axis to split along; `None`
/// when the grain's shape forbids breaking (Section 3.3.3). A sphere first turns its
/// principal directions (`body.orientation`) to the ideal plane and by the random slight
/// rotation `jitter`, when the scene asks.
fn break_geometry(
    p: &FractureParams,
    body: &mut Body,
    trigger: &Trigger,
    jitter: Option<[f64; 3]>,
) -> Option<(Parent, usize)> {
    let semi = body.shape.semi_axes(body.radius);
    let sphere = body.shape.is_sphere();
    let axis = if sphere && p.ideal_plane {
        body.orientation = break_plane::turn_to_ideal(&body.orientation, &trigger.ideal_normal());
        0
    } else {
        let (_, q) = body.shape_placement();
        let axes = [q * Vec3::x(), q * Vec3::y(), q * Vec3::z()];
        break_plane::break_axis(&semi, &axes, trigger)?
    };
    if sphere && p.plane_jitter {
        if let Some(angles) = jitter {
            body.orientation = break_plane::jittered(&body.orientation, angles);
        }
    }
    let (origin, frame) = body.shape_placement();
    Some((
        Parent {
            semi,
            origin,
            frame,
            mass: body.mass,
            centroid: body.pos,
            velocity: body.vel,
            omega: body.omega,
        },
        axis,
    ))
}

/// A spring [`bond_split`] made: the spring (body indices 0, the caller's to set) and what it
/// adds at once: `force` on A (N; B gets the opposite) and the torques on A and on B about
/// their centres of mass (N·m).
#[derive(Debug, Clone)]
pub struct MadeSpring {
    pub spring: Spring,
    pub force: Vec3,
    pub torque_a: Vec3,
    pub torque_b: Vec3,
}

/// The springs of one split (Eq. 39–43), handed to `made` in the order of the split's points:
/// their initial forces make each half accelerate and turn as the parent did, given the
/// halves `a` (the + half) and `b` and the forces and torques on them after the split,
/// `[force_a, torque_a, force_b, torque_b]` (N, N·m, world). A spring that would carry no
/// force (|f| <= 1e-12 of the demand) is not made. `gc` is the cohesive energy (J/m²).
pub fn bond_split(
    gc: f64,
    a: &Body,
    b: &Body,
    loads: [&Vec3; 4],
    split: &PendingSplit,
    mut made: impl FnMut(MadeSpring),
) {
    let [force_a, torque_a, force_b, torque_b] = loads;
    let demand_of = |k: &Body, force: &Vec3, torque: &Vec3| {
        let r = k.pos - split.centroid;
        let accel = split.accel + split.alpha.cross(&r) + split.omega.cross(&split.omega.cross(&r));
        let force = accel * k.mass - force;
        let iw = world_inertia(k);
        let torque = iw * split.alpha + split.omega.cross(&(iw * split.omega)) - torque;
        (force, torque)
    };
    let (force_a, torque_a) = demand_of(a, force_a, torque_a);
    let (force_b, torque_b) = demand_of(b, force_b, torque_b);
    let mut points = [Vec3::zeros(); 16];
    for (p, q) in points.iter_mut().zip(&split.points[..split.count]) {
        *p = q - a.pos;
    }
    let points = &points[..split.count];
    let demand = Demand {
        force_a,
        torque_a,
        force_b,
        torque_b,
        b_offset: b.pos - a.pos,
    };
    let f = cohesion::initial_forces(points, &demand);
    let (qa, qb) = (a.orientation, b.orientation);
    let scale = demand.force_a.norm() + demand.force_b.norm();
    for (p, fk) in points.iter().zip(&f) {
        let f0 = fk.norm();
        // A spring with no force would break at once: it is not made.
        if f0 <= 1e-12 * scale {
            continue;
        }
        let world = p + a.pos;
        made(MadeSpring {
            spring: Spring {
                a: 0,
                b: 0,
                on_a: qa.inverse() * (world - a.pos),
                on_b: qb.inverse() * (world - b.pos),
                direction: qa.inverse() * (fk / f0),
                f0,
                k: f0 * f0 / (2.0 * gc * split.area),
                opening: 0.0,
                last_gap: Vec3::zeros(),
                last_force: *fk,
                broken: false,
            },
            force: *fk,
            torque_a: p.cross(fk),
            torque_b: -(world - b.pos).cross(fk),
        });
    }
}

/// A body's inertia tensor in the world frame (kg·m²).
fn world_inertia(body: &Body) -> Matrix3<f64> {
    let r = body.orientation.to_rotation_matrix().into_inner();
    r * Matrix3::from_diagonal(&body.inertia) * r.transpose()
}

/// Angular acceleration (rad/s², world) of a body under the torque `torque` (N·m, world):
/// `I⁻¹ (T − ω × I ω)`.
pub fn angular_acceleration(body: &Body, torque: &Vec3) -> Vec3 {
    let q: &UnitQuaternion<f64> = &body.orientation;
    let w = q.inverse_transform_vector(&body.omega);
    let t = q.inverse_transform_vector(torque);
    let i = body.inertia;
    let l = w.component_mul(&i);
    q * (t - w.cross(&l)).component_div(&i)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(on: WeibullOn, beta: Option<f64>, limit: Option<f64>) -> FractureParams {
        let spec = FractureSpec {
            reference_strength: Some(1.5e9),
            reference_radius: Some(0.15e-3),
            weibull_modulus: 3.0,
            size_exponent: beta,
            weibull_on: on,
            comminution_limit: limit,
            sigma_c: 200e6,
            ..FractureSpec::default()
        };
        FractureParams::new(&spec, 95e9, 0.18, true, false)
    }

    /// The particle reading: a grain whose crushing force is S times the reference grain's
    /// has σc S and a contact strength S^(1/3), because the Hertz edge stress at a force F
    /// is (1 - 2ν)/3 · 3F/(2πa²) with a ∝ F^(1/3), i.e. ∝ F^(1/3). Checked here on the Hertz
    /// formula itself: the edge stress at S F_c equals S^(1/3) times that at F_c.
    #[test]
    fn particle_strength_scales_sigma_c_and_the_contact_strength_by_its_cube_root() {
        let p = params(WeibullOn::Particle, Some(0.9), None);
        let s = 2.7;
        assert_eq!(p.compressive_strength(s), 200e6 * s);
        assert!((p.contact_strength(s) / 1.5e9 - s.cbrt()).abs() < 1e-15);
        let (e_star, r, nu) = (95e9 / (2.0 * (1.0 - 0.18 * 0.18)), 0.15e-3, 0.18);
        let edge = |f: f64| {
            let a = (3.0 * f * r / (4.0 * e_star)).cbrt();
            criteria::contact_tensile_stress(f, a, nu)
        };
        assert!((edge(s * 9.4) / edge(9.4) - s.cbrt()).abs() < 1e-12);
        // The paper's reading scales the contact strength by the factor itself, and "both"
        // σc too.
        let c = params(WeibullOn::Contact, None, None);
        assert_eq!(c.contact_strength(s), 1.5e9 * s);
        assert_eq!(c.compressive_strength(s), 200e6);
        let b = params(WeibullOn::Both, None, None);
        assert_eq!(b.compressive_strength(s), 200e6 * s);
    }

    /// The size exponent defaults to Eq. 18's 2/w (the same draws, bit for bit, as before it
    /// was a key); given, a grain twice the reference radius with P = 1/e has 2^(−β).
    #[test]
    fn size_exponent_defaults_to_two_over_w_and_sets_the_size_effect() {
        assert_eq!(
            params(WeibullOn::Contact, None, None).size_exponent,
            2.0 / 3.0
        );
        let v = 4.0 / 3.0 * std::f64::consts::PI * (0.3e-3f64).powi(3);
        for grain in 1..50 {
            assert_eq!(
                grain_strength(7, grain, 2, v, 3.0, 0.15e-3),
                grain_strength_sized(7, grain, 2, v, 3.0, 2.0 / 3.0, 0.15e-3)
            );
        }
        let e = std::f64::consts::E;
        let f = criteria::weibull_factor_sized(1.0 / e, 3.0, 0.9, 0.3e-3, 0.15e-3);
        assert!((f - 2f64.powf(-0.9)).abs() < 1e-15, "{f}");
    }

    /// The comminution limit compares the piece's equivalent radius (3V/4π)^⅓ with the limit;
    /// no limit: nothing is below it.
    #[test]
    fn comminution_limit_reads_the_equivalent_radius() {
        let v = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        let p = params(WeibullOn::Particle, None, Some(0.1e-3));
        assert!(p.below_comminution_limit(v(0.099e-3)));
        assert!(!p.below_comminution_limit(v(0.101e-3)));
        let none = params(WeibullOn::Particle, None, None);
        assert!(!none.below_comminution_limit(v(1e-9)));
    }

    /// The grain load keeps what the check used to select by sorting all of a grain's critical
    /// contacts (stable, largest stress first): the count, the three largest in that order
    /// (equal stresses in the order they came), and the moment; on random contacts with ties.
    #[test]
    fn grain_load_keeps_the_three_largest_as_a_stable_sort_would() {
        let centre = Vec3::new(1e-3, -2e-3, 0.5e-3);
        let mut u = [0.0; 4000];
        crate::sample::uniforms(5, 77, 0, &mut u);
        let mut v = u.iter().copied();
        let mut next = move || v.next().unwrap();
        for case in 0..100 {
            let mut load = GrainLoad::default();
            let mut all = Vec::new();
            let mut moment = Matrix3::zeros();
            for _ in 0..(case % 9) {
                let force = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
                let point = centre + Vec3::new(next(), next(), next()) * 1e-4;
                // Hertz forces from a few values, so that stresses tie.
                let hertz = [0.5, 1.0, 1.0, 2.0][(next() * 4.0) as usize % 4];
                load.add(&centre, &force, &point, hertz, 1e-4, 0.2, 2e4);
                moment += force * (point - centre).transpose();
                let st = criteria::contact_tensile_stress(hertz, 1e-4, 0.2);
                if st > 2e4 {
                    all.push((st, point));
                }
            }
            all.sort_by(|a, b| b.0.total_cmp(&a.0));
            assert_eq!(load.count, all.len(), "case {case}");
            assert_eq!(load.moment, moment);
            let kept: Vec<(f64, Vec3)> = (0..load.count.min(3))
                .map(|k| (load.stress[k], load.point[k]))
                .collect();
            assert_eq!(kept, all[..all.len().min(3)].to_vec(), "case {case}");
            assert_eq!(load.top(), all.first().map_or(0.0, |x| x.0));
        }
    }
}
