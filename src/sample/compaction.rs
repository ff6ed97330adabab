//! Dynamic compaction of a packing to an isotropic confining pressure.
//!
//! The three upper walls of the box are servo-controlled (the PFC servo): each step a wall
//! moves by `α A (p - σ) / k`, where `σ` is the mean stress on the axis, `A` the face area and
//! `k` the summed contact stiffness on the wall, so that a stiff packing is pushed gently and
//! an empty wall advances at the largest allowed speed. Contacts are Hertz with strong viscous
//! damping (restitution 0.3) and, if asked, friction; non-viscous local damping (Cundall)
//! takes out the remaining kinetic energy.
//!
//! Servo phases (until every axis is within 1% of the target and the unbalanced force is below
//! 1e-2: a compressed gas shows the target stress in passing) alternate with hold phases
//! (walls fixed until the mean unbalanced force is below 1e-3 of the mean contact force):
//! a soft, nearly isostatic packing only settles when its walls stop moving. Compaction ends
//! when a settled packing carries the target within 5% on every axis. The bodies are then at
//! rest and the walls fixed; contact histories are not kept, so the sample is just positions
//! and radii, as a packing file would give it.

use crate::contact::hertz_mindlin::{Hertz, Mindlin, ViscousDamping};
use crate::effects::{ContactParams, PairParts, StepContext, build_contact};
use crate::error::{Error, Result};
use crate::integrate::{VelocityVerlet, rayleigh_time_step};
use crate::state::{Bodies, BoxFace, Forces, Vec3, Walls};

#[derive(Debug, Clone, Copy)]
pub struct CompactionReport {
    pub steps: u64,
    /// Mean stress on the x, y and z faces at the end (Pa).
    pub stresses: [f64; 3],
    /// Mean net force over mean contact force at the end.
    pub unbalanced: f64,
}

/// Fraction of the stress error a wall corrects per step.
/// Largest wall speed, as a strain per step.
const MAX_STRAIN_PER_STEP: f64 = 5e-6;
/// Fraction of the stress error a wall corrects per step.
const SERVO_GAIN: f64 = 0.1;
const LOCAL_DAMPING: f64 = 0.3;
/// Servo phases end when every axis is this close to the target (relative)...
const STRESS_TOLERANCE: f64 = 0.01;
/// ...and compaction ends when the settled packing is this close and at rest.
const SETTLED_STRESS_TOLERANCE: f64 = 0.05;
/// Longest single phase.
const PHASE_STEPS: u64 = 200_000;
const UNBALANCED_TOLERANCE: f64 = 1e-3;
const SERVO_UNBALANCED_TOLERANCE: f64 = 1e-2;
const CHECK_EVERY: u64 = 200;
const MAX_STEPS: u64 = 3_000_000;

const AXES: [(BoxFace, BoxFace); 3] = [
    (BoxFace::XMin, BoxFace::XMax),
    (BoxFace::YMin, BoxFace::YMax),
    (BoxFace::ZMin, BoxFace::ZMax),
];

/// Rows (grains) per part of the pair loop while a sample is prepared
/// ([`PairParts::PerRows`]). A sample of fewer than twice this many grains is prepared by the
/// plain loop with no team (the same bits as when preparation never used one); a larger one in
/// parts of this many rows, on the run's team when it has one: the same sample on any number
/// of threads, and the cores used where one thread alone took hours (a whole specimen).
pub const PREPARATION_PART_ROWS: usize = 1024;

/// Runs a preparation: with no team for a sample too small for parts (see
/// [`PREPARATION_PART_ROWS`]).
fn preparing<R>(grains: usize, f: impl FnOnce() -> R) -> R {
    if PairParts::PerRows(PREPARATION_PART_ROWS).count(grains) == 1 {
        crate::parallel::alone(f)
    } else {
        f()
    }
}

/// What to compact to, and the grains' material.
#[derive(Debug, Clone, Copy)]
pub struct CompactionSpec {
    /// Young's modulus (Pa), Poisson's ratio and density (kg/m³) of the grains.
    pub young: f64,
    pub poisson: f64,
    pub density: f64,
    /// Verlet skin (m) of the neighbour list; `None`: the default.
    pub skin: Option<f64>,
    /// The stress (Pa) every face must carry.
    pub pressure: f64,
    /// Friction coefficient while compacting.
    pub friction: f64,
}

/// Compresses the bodies in the box `walls` until every face carries `spec.pressure` (Pa).
pub fn compact_to_pressure(
    bodies: &mut Bodies,
    walls: &mut Walls,
    spec: &CompactionSpec,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<CompactionReport> {
    preparing(bodies.len(), || {
        compact_to_pressure_here(bodies, walls, spec, progress)
    })
}

fn compact_to_pressure_here(
    bodies: &mut Bodies,
    walls: &mut Walls,
    spec: &CompactionSpec,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<CompactionReport> {
    let (pressure, friction) = (spec.pressure, spec.friction);
    let params = ContactParams {
        hertz: Hertz::new(spec.young, spec.poisson),
        damping: Some(ViscousDamping::from_restitution(0.3)),
        mindlin: (friction > 0.0).then(|| Mindlin::new(spec.young, spec.poisson, friction)),
        wall_friction: None,
        sleeve_friction: None,
        skin: spec.skin,
        shapes: bodies.shape.iter().any(|s| !s.is_sphere()),
        parts: PairParts::PerRows(PREPARATION_PART_ROWS),
    };
    let dt = 0.2 * rayleigh_time_step(bodies.min_radius(), spec.density, spec.young, spec.poisson);
    let mut c = Compactor {
        contact: build_contact(params),
        vv: VelocityVerlet {
            track_orientation: bodies.shape.iter().any(|s| !s.is_sphere()),
        },
        forces: Forces::new(bodies.len()),
        dt,
        mean_r: bodies.radius.iter().sum::<f64>() / bodies.len() as f64,
        pressure,
        steps: 0,
    };
    let first = StepContext {
        dt,
        update_history: false,
    };
    c.contact.accumulate(&first, bodies, walls, &mut c.forces);
    progress(&format!(
        "compacting to {pressure:e} Pa (friction {friction}, time step {dt:.3e} s)"
    ));
    // Servo the walls onto the target, then hold them and let the packing settle; repeat until
    // it settles on target. Holding the walls lets a soft (near-isostatic) packing find
    // equilibrium, which a servo that keeps chasing the stress would not allow.
    loop {
        let servo = c.run(bodies, walls, Phase::Servo)?;
        let settled = c.run(bodies, walls, Phase::Hold)?;
        progress(&format!(
            "compacting: step {}, stresses {:.4e} {:.4e} {:.4e} Pa, unbalanced {:.2e}",
            c.steps,
            settled.stresses[0],
            settled.stresses[1],
            settled.stresses[2],
            settled.unbalanced
        ));
        let on_target = settled
            .stresses
            .iter()
            .all(|s| (s - pressure).abs() < SETTLED_STRESS_TOLERANCE * pressure);
        if on_target && settled.unbalanced < UNBALANCED_TOLERANCE {
            for i in 0..bodies.len() {
                bodies.vel[i] = Vec3::zeros();
                bodies.omega[i] = Vec3::zeros();
            }
            for w in &mut walls.walls {
                w.velocity = Vec3::zeros();
            }
            walls.clear_forces();
            return Ok(settled);
        }
        if c.steps >= MAX_STEPS {
            return Err(Error::run(format!(
                "compaction to {pressure:e} Pa did not settle in {} steps (stresses {:?} Pa after the servo phase, {:?} Pa settled, unbalanced {:.2e})",
                c.steps, servo.stresses, settled.stresses, settled.unbalanced
            )));
        }
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Phase {
    /// Walls servo-controlled until every axis is within STRESS_TOLERANCE of the target and
    /// the packing is near equilibrium (a compressed gas shows the target stress in passing).
    Servo,
    /// Walls fixed until the unbalanced force falls below UNBALANCED_TOLERANCE.
    Hold,
}

struct Compactor {
    contact: Box<dyn crate::effects::Effect>,
    vv: VelocityVerlet,
    forces: Forces,
    dt: f64,
    mean_r: f64,
    pressure: f64,
    steps: u64,
}

impl Compactor {
    fn run(
        &mut self,
        bodies: &mut Bodies,
        walls: &mut Walls,
        phase: Phase,
    ) -> Result<CompactionReport> {
        let dt = self.dt;
        let ctx = StepContext {
            dt,
            update_history: true,
        };
        let mut report = CompactionReport {
            steps: 0,
            stresses: [0.0; 3],
            unbalanced: f64::INFINITY,
        };
        for k in 1..=PHASE_STEPS {
            self.steps += 1;
            let size = walls.box_size();
            for (a, (lo, hi)) in AXES.iter().enumerate() {
                let speed = if phase == Phase::Hold {
                    0.0
                } else {
                    let sigma = 0.5 * (walls.face_stress(*lo) + walls.face_stress(*hi));
                    let area = size[(a + 1) % 3] * size[(a + 2) % 3];
                    let k = 0.5 * (walls.face(*lo).stiffness + walls.face(*hi).stiffness);
                    let vmax = MAX_STRAIN_PER_STEP * size[a] / dt;
                    if k > 0.0 {
                        (SERVO_GAIN * area * (self.pressure - sigma) / (k * dt)).clamp(-vmax, vmax)
                    } else {
                        vmax
                    }
                };
                let wall = walls.face_mut(*hi);
                wall.velocity = wall.normal * speed;
            }
            self.drift_and_forces(bodies, walls, &ctx);
            let check = k % CHECK_EVERY == 0;
            if check {
                report = self.measure(bodies, walls);
            }
            local_damping(&mut self.forces, bodies);
            self.vv.kick(bodies, &self.forces, dt);
            if check {
                if bodies.first_non_finite().is_some() {
                    return Err(Error::run(
                        "compaction became unstable (non-finite positions)",
                    ));
                }
                let on_target = report
                    .stresses
                    .iter()
                    .all(|s| (s - self.pressure).abs() < STRESS_TOLERANCE * self.pressure);
                let done = match phase {
                    Phase::Servo => on_target && report.unbalanced < SERVO_UNBALANCED_TOLERANCE,
                    Phase::Hold => report.unbalanced < UNBALANCED_TOLERANCE,
                };
                if done {
                    break;
                }
            }
        }
        Ok(report)
    }

    /// The first half of a velocity Verlet step: half kick, drift, the walls moved, and the
    /// contact forces at the new positions (the second half kick is the caller's, after any
    /// damping).
    fn drift_and_forces(&mut self, bodies: &mut Bodies, walls: &mut Walls, ctx: &StepContext) {
        self.vv.kick_drift(bodies, &self.forces, ctx.dt);
        walls.advance(ctx.dt);
        self.forces.clear();
        walls.clear_forces();
        self.contact
            .accumulate(ctx, bodies, walls, &mut self.forces);
    }

    /// Mean stress per axis and the unbalanced force ratio: mean net force on a body over the
    /// mean contact force, estimated from the pressure as `3 p V / (N_c 2 r̄)`.
    fn measure(&self, bodies: &Bodies, walls: &Walls) -> CompactionReport {
        let volume = walls.volume();
        let mut stresses = [0.0; 3];
        for (a, (lo, hi)) in AXES.iter().enumerate() {
            stresses[a] = 0.5 * (walls.face_stress(*lo) + walls.face_stress(*hi));
        }
        let contacts = self.contact.contacts() + walls.contacts();
        let mean_contact =
            3.0 * self.pressure * volume / (contacts.max(1) as f64 * 2.0 * self.mean_r);
        let mean_net =
            self.forces.force.iter().map(|f| f.norm()).sum::<f64>() / bodies.len() as f64;
        CompactionReport {
            steps: self.steps,
            stresses,
            unbalanced: mean_net / mean_contact,
        }
    }
}

/// Non-viscous local damping (Cundall): each force and torque component loses a fraction of
/// its size against the motion.
fn local_damping(forces: &mut Forces, bodies: &Bodies) {
    for (f, v) in forces.force.iter_mut().zip(&bodies.vel) {
        for a in 0..3 {
            f[a] -= LOCAL_DAMPING * f[a].abs() * v[a].signum();
        }
    }
    for (t, w) in forces.torque.iter_mut().zip(&bodies.omega) {
        for a in 0..3 {
            t[a] -= LOCAL_DAMPING * t[a].abs() * w[a].signum();
        }
    }
}

/// Compaction to a solid fraction: what to reach, and the grains' material.
#[derive(Debug, Clone, Copy)]
pub struct FractionSpec {
    /// Young's modulus (Pa), Poisson's ratio and density (kg/m³) of the grains.
    pub young: f64,
    pub poisson: f64,
    pub density: f64,
    /// Verlet skin (m) of the neighbour list; `None`: the default.
    pub skin: Option<f64>,
    /// Box edge lengths (m) at which the grains fill the target fraction.
    pub size: Vec3,
    /// Friction coefficient while compacting (0: none, as [`compact_to_fraction`] describes).
    pub friction: f64,
    /// The filling and the jamming pressure as fractions of E/(1 − ν²) (see
    /// `FILL_PRESSURE_PER_MODULUS`, `JAM_PRESSURE_PER_MODULUS`, the defaults).
    pub pressures_per_modulus: (f64, f64),
    /// `false` (the default): the grains count as jammed short of the target size when,
    /// settled, they carry the filling pressure. `true`, for a search of where grains jam:
    /// short of the target they count as jammed once, settled, they carry the jamming
    /// pressure (the filling pressure relaxes at rest, and waiting for it again made the
    /// search creep).
    pub search: bool,
}

impl FractionSpec {
    /// The pressures of frictionless compaction to a fraction.
    pub const DEFAULT_PRESSURES: (f64, f64) = (FILL_PRESSURE_PER_MODULUS, JAM_PRESSURE_PER_MODULUS);
}

/// Why [`compact_to_fraction`] stopped short: the grains jammed first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FractionJammed {
    /// The solid fraction asked for.
    pub target: f64,
    /// The solid fraction at which the settled packing carried the jamming pressure (the
    /// target itself when the faces got there).
    pub reached: f64,
    /// The mean face stress (Pa) the settled grains carried there.
    pub stress: f64,
    /// Steps taken.
    pub steps: u64,
}

/// Largest wall speed while filling, as a strain of the box per step.
const FILL_STRAIN_PER_STEP: f64 = 2e-5;
/// While filling, the faces wait whenever the grains carry more than this fraction of
/// E/(1 - ν²) (a relative Hertz overlap of about 2e-3): pushed harder, frictionless grains
/// rearrange sooner.
pub const FILL_PRESSURE_PER_MODULUS: f64 = 1e-4;
/// At the target size the grains count as jammed when, settled, they still carry this fraction
/// of E/(1 - ν²) (a relative overlap of about 5e-4): frictionless grains below jamming carry
/// nothing once they stop moving.
pub const JAM_PRESSURE_PER_MODULUS: f64 = 1e-5;
/// Background viscous damping while compacting: velocities decay by e in this many steps
/// (free-flying grains feel no contact damping; much stronger drag slows the rearrangements:
/// at 1000 steps the jammed preparation of 181 Mason grains took 5 times as many steps).
const DRAG_STEPS: f64 = 5000.0;
/// Settled: the mean grain speed is below this fraction of the largest wall speed.
const SETTLED_SPEED: f64 = 1e-3;
const FRACTION_MAX_STEPS: u64 = 2_000_000;

/// Dynamic compaction to a solid fraction (frictionless unless `spec.friction` says
/// otherwise): the three upper faces of the box move
/// in, each at most `FILL_STRAIN_PER_STEP` of its edge a step, until the box has `spec.size`;
/// whenever the mean face stress exceeds the filling pressure the faces wait for the grains to
/// rearrange. Contacts are Hertz with viscous damping (restitution 0.3) and `spec.friction`;
/// local damping and a background drag take out the kinetic energy. At the target size the
/// faces hold until the grains are at rest. If the grains, settled, still carry the filling
/// pressure before the target size, or the jamming pressure at it, they are jammed: the error
/// says at what fraction.
/// The bodies end at rest and the faces fixed, with no contact history kept.
pub fn compact_to_fraction(
    bodies: &mut Bodies,
    walls: &mut Walls,
    spec: &FractionSpec,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<std::result::Result<CompactionReport, FractionJammed>> {
    preparing(bodies.len(), || {
        compact_to_fraction_here(bodies, walls, spec, progress)
    })
}

fn compact_to_fraction_here(
    bodies: &mut Bodies,
    walls: &mut Walls,
    spec: &FractionSpec,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<std::result::Result<CompactionReport, FractionJammed>> {
    let shapes = bodies.shape.iter().any(|s| !s.is_sphere());
    let params = ContactParams {
        hertz: Hertz::new(spec.young, spec.poisson),
        damping: Some(ViscousDamping::from_restitution(0.3)),
        mindlin: (spec.friction > 0.0)
            .then(|| Mindlin::new(spec.young, spec.poisson, spec.friction)),
        wall_friction: None,
        sleeve_friction: None,
        skin: spec.skin,
        shapes,
        parts: PairParts::PerRows(PREPARATION_PART_ROWS),
    };
    let smallest = (0..bodies.len())
        .map(|i| {
            let s = bodies.shape[i].semi_axes(bodies.radius[i]);
            s.iter().copied().fold(f64::INFINITY, f64::min)
        })
        .fold(f64::INFINITY, f64::min);
    let dt = 0.2 * rayleigh_time_step(smallest, spec.density, spec.young, spec.poisson);
    let solid = bodies.solid_volume();
    let target = spec.size;
    let target_fraction = solid / walls.volume_of(target);
    let modulus = spec.young / (1.0 - spec.poisson.powi(2));
    let (fill_pressure, jam_pressure) = (
        spec.pressures_per_modulus.0 * modulus,
        spec.pressures_per_modulus.1 * modulus,
    );
    let mut c = Compactor {
        contact: build_contact(params),
        vv: VelocityVerlet {
            track_orientation: shapes,
        },
        forces: Forces::new(bodies.len()),
        dt,
        mean_r: bodies.radius.iter().sum::<f64>() / bodies.len() as f64,
        pressure: jam_pressure,
        steps: 0,
    };
    let ctx = StepContext {
        dt,
        update_history: true,
    };
    c.contact.accumulate(
        &StepContext {
            dt,
            update_history: false,
        },
        bodies,
        walls,
        &mut c.forces,
    );
    if spec.friction > 0.0 {
        progress(&format!(
            "compacting {} grains with friction {} towards solid fraction {target_fraction:.3} (time step {dt:.3e} s)",
            bodies.len(),
            spec.friction
        ));
    } else {
        progress(&format!(
            "compacting {} grains without friction to solid fraction {target_fraction:.3} (time step {dt:.3e} s)",
            bodies.len()
        ));
    }
    let start = walls.box_size();
    let wall_speed = FILL_STRAIN_PER_STEP * start.max() / dt;
    let drag = (-1.0 / DRAG_STEPS).exp();
    let mut waited = 0u64;
    loop {
        c.steps += 1;
        let size = walls.box_size();
        let mean_stress = AXES
            .iter()
            .map(|(lo, hi)| 0.5 * (walls.face_stress(*lo) + walls.face_stress(*hi)))
            .sum::<f64>()
            / 3.0;
        let pushing = mean_stress < fill_pressure;
        let mut at_target = true;
        for (a, (_, hi)) in AXES.iter().enumerate() {
            let left = size[a] - target[a];
            let speed = if left > 0.0 && pushing {
                (FILL_STRAIN_PER_STEP * start[a] / dt).min(left / dt)
            } else {
                0.0
            };
            at_target &= left <= 1e-12 * target[a];
            let wall = walls.face_mut(*hi);
            wall.velocity = wall.normal * speed;
        }
        c.drift_and_forces(bodies, walls, &ctx);
        local_damping(&mut c.forces, bodies);
        c.vv.kick(bodies, &c.forces, dt);
        for (v, w) in bodies.vel.iter_mut().zip(bodies.omega.iter_mut()) {
            *v *= drag;
            *w *= drag;
        }
        waited = if pushing && !at_target { 0 } else { waited + 1 };
        if c.steps % CHECK_EVERY != 0 {
            continue;
        }
        if bodies.first_non_finite().is_some() {
            return Err(Error::run(
                "compaction to a solid fraction became unstable (non-finite positions)",
            ));
        }
        let mean_speed = bodies.vel.iter().map(|v| v.norm()).sum::<f64>() / bodies.len() as f64;
        let settled = waited >= CHECK_EVERY && mean_speed < SETTLED_SPEED * wall_speed;
        let now = walls.box_size();
        let fraction = solid / walls.volume_of(now);
        if c.steps % (50 * CHECK_EVERY) == 0 {
            progress(&format!(
                "compacting: step {}, solid fraction {fraction:.4}, mean stress {mean_stress:.3e} Pa",
                c.steps
            ));
        }
        let jammed = if at_target || spec.search {
            mean_stress >= jam_pressure
        } else {
            mean_stress >= fill_pressure
        };
        if settled && jammed {
            return Ok(Err(FractionJammed {
                target: target_fraction,
                reached: fraction,
                stress: mean_stress,
                steps: c.steps,
            }));
        }
        if settled && at_target {
            for i in 0..bodies.len() {
                bodies.vel[i] = Vec3::zeros();
                bodies.omega[i] = Vec3::zeros();
            }
            for w in &mut walls.walls {
                w.velocity = Vec3::zeros();
            }
            let report = c.measure(bodies, walls);
            walls.clear_forces();
            return Ok(Ok(report));
        }
        if c.steps >= FRACTION_MAX_STEPS {
            return Err(Error::run(format!(
                "compaction to solid fraction {target_fraction:.3} did not settle in {} steps (solid fraction {fraction:.4}, mean stress {mean_stress:.3e} Pa)",
                c.steps
            )));
        }
    }
}
