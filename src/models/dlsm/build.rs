//! Building a dlsm run: the lattice's bonds and loading from a sample, the step's checks, and
//! the lattice's highest frequency.

use super::*;

impl Dlsm {
    /// The model on a freshly built sample, at t = 0 with nothing broken, and its step.
    pub(super) fn assemble(
        scene: &Scene,
        cfg: DlsmScene,
        s: DlsmSample,
    ) -> Result<(Self, f64, Vec<String>)> {
        let DlsmSample {
            domain,
            bodies,
            shapes,
            seeds,
            bonds,
            boundary: _,
            info,
        } = &s;
        let m = &cfg.material;
        let loading = DlsmLoading::build(&Setting {
            scene,
            cfg: &cfg,
            sample: &s,
        })?;
        let tensile_strength = if scene.has_effect(EffectKind::Fracture) {
            m.tensile_strength
        } else {
            None
        };
        let pipeline = ElementPipeline::build(scene, &cfg, &loading, bodies.len());
        let dt_critical = bonds.critical_time_step(&bodies.mass);
        let dt_rotational = rotational_time_step(bodies, bonds);
        // Eq. 39 bounds the translational springs; the rotational ones (K S, Eq. 31) are
        // stiffer for their inertia, so their counterpart bounds the step too.
        let mut dt_limit = dt_critical.min(dt_rotational);
        let platens = match &loading {
            DlsmLoading::Brazilian(l) => l.platens.iter().collect(),
            _ => Vec::new(),
        };
        for g in pipeline.ground.iter().chain(platens) {
            let lightest = bodies.mass.iter().copied().fold(f64::INFINITY, f64::min);
            dt_limit = dt_limit.min((lightest / g.stiffness).sqrt());
        }
        if let DlsmLoading::Brazilian(Brazilian {
            pressure: Some(arc),
            ..
        }) = &loading
        {
            dt_limit = dt_limit.min(arc.step_bound(bodies));
        }
        let dt = scene.time.step(dt_limit);
        let phi = match scene.time.integrator {
            IntegratorKind::TchamwaWielgosz => scene.time.phi.unwrap_or(DEFAULT_PHI),
            _ => 0.5,
        };
        let mut warnings = Vec::new();
        if !dt_critical.is_finite() {
            warnings.push("the sample has no cohesive contact".to_string());
        }
        if phi < 1.5 {
            warnings.push(format!(
                "phi = {phi}: the lattice has slowly growing (flutter) modes that phi of about 2 (time.integrator = \"tchamwa_wielgosz\") damps at a third of the critical step; runs of more than a few thousand steps may diverge"
            ));
        }
        let mut bodies = bodies.clone();
        let reference = bodies.pos.clone();
        if let DlsmLoading::FreeVibration(v) = &loading {
            for (p, seed) in bodies.pos.iter_mut().zip(seeds) {
                *p += v.initial_displacement(seed);
            }
        }
        if let DlsmLoading::Drop(_) = &loading {
            let v0 = Vec3::from(match cfg.loading {
                scene::LoadingSpec::Drop(d) => d.initial_velocity,
                _ => [0.0; 3],
            });
            bodies.vel.iter_mut().for_each(|v| *v = v0);
        }
        let model = Dlsm {
            bonds: bonds.clone(),
            shapes: shapes.clone(),
            domain: *domain,
            reference,
            sample: info.clone(),
            integrator: TchamwaWielgosz::new(phi),
            tensile_strength,
            dt_critical,
            dt_rotational,
            energy_fault: None,
            cfg,
            state: DlsmState {
                forces: Forces::new(bodies.len()),
                bodies,
                broken_order: Vec::new(),
                break_log: Vec::new(),
                first_break: None,
                pipeline,
                loading,
                stopped: false,
            },
        };
        Ok((model, dt, warnings))
    }

    /// Refuses a step the lattice cannot survive, at build (a restored run was checked when
    /// it was built). The scheme is stable for ω dt < √(2/φ) (φ = ½: velocity Verlet's 2).
    /// Eq. 39 bounds one spring at a time with E; the lattice's own highest frequency (each
    /// element held by all its springs, stiffness from λ + 2μ and μ) lies above 1/dt_limit, by
    /// a factor that grows towards ν = 0.5 and ν = -1: computed here on the undeformed
    /// lattice, it refuses the step instead of letting the run blow up.
    pub(super) fn check_step(&self, scene: &Scene, dt: f64) -> Result<()> {
        let mut undeformed = self.state.bodies.clone();
        undeformed.pos.clone_from(&self.reference);
        let (omega_max, stiffest) =
            lattice_highest_frequency(&undeformed, &self.bonds, &self.state.loading, 60);
        let phi = self.integrator.phi;
        let stable = (2.0 / phi).sqrt() / omega_max;
        if dt <= stable {
            return Ok(());
        }
        let (key, value, fix) = match scene.time.dt {
            DtSpec::Auto => (
                "time.safety",
                format!("{}", scene.time.safety),
                format!(
                    "set time.safety below {:.3}",
                    stable / dt * scene.time.safety
                ),
            ),
            DtSpec::Seconds(v) => (
                "time.dt",
                format!("{v:e} s"),
                format!("set time.dt below {stable:.3e} s"),
            ),
        };
        Err(scene.key_error(
            key,
            format!(
                "= {value} gives a step of {dt:.3e} s, above this lattice's stability limit of {stable:.3e} s (its highest vibration frequency, computed at build, is {omega_max:.4e} rad/s, at element {stiffest}; the scheme needs ω dt < √(2/φ) = {:.3} for φ = {phi}): {fix}",
                (2.0 / phi).sqrt()
            ),
        ))
    }
}

/// The rotational counterpart of Eq. 39: the smallest `sqrt(I_ij / (K S))` over the contacts,
/// with `I_ij = I_i I_j / (I_i + I_j)` of the smallest principal moments (s).
pub(super) fn rotational_time_step(bodies: &Bodies, bonds: &DlsmBonds) -> f64 {
    let mut dt = f64::INFINITY;
    for (c, p) in bonds.pair.iter().enumerate() {
        let (a, b) = (
            bodies.inertia[p[0] as usize].min(),
            bodies.inertia[p[1] as usize].min(),
        );
        let inertia = a * b / (a + b);
        let k = bonds.young * bonds.length0[c] * bonds.area[c];
        dt = dt.min((inertia / k).sqrt());
    }
    dt
}

/// The lattice's highest vibration frequency (rad/s) at its built configuration, computed by
/// `iterations` power iterations ([`crate::probe::modes`]) with the stiffness applied as a
/// forward difference of the springs' forces (no breaking), the loaded elements held as the
/// loading holds them; and the element that moves most in that mode. Ground contact and
/// gravity are left out (the ground's own bound is in the step limit).
pub fn lattice_highest_frequency(
    bodies: &Bodies,
    bonds: &DlsmBonds,
    loading: &DlsmLoading,
    iterations: usize,
) -> (f64, usize) {
    use crate::probe::modes::{
        MassScale, highest_eigenvalue, largest_motion, stiffness_by_difference,
    };
    let n = bodies.len();
    if n == 0 || bonds.contacts() == 0 {
        return (0.0, 0);
    }
    let length = bonds.length0.iter().copied().fold(f64::INFINITY, f64::min);
    let mut bonds = bonds.clone();
    let mut loading = loading.clone();
    let mut forces = Forces::new(n);
    let mut evaluate = |b: &Bodies| {
        bonds.evaluate(b, &mut forces, None);
        loading.as_loading_mut().constrain(&mut forces);
        forces
            .force
            .iter()
            .zip(&forces.torque)
            .map(|(f, t)| (*f, *t))
            .collect::<Vec<_>>()
    };
    let base = evaluate(bodies);
    let scale = MassScale::of(bodies);
    let mut trial = bodies.clone();
    let (lambda, mode) = highest_eigenvalue(n, iterations, |w, out| {
        stiffness_by_difference(
            bodies,
            &scale,
            length,
            &base,
            &mut trial,
            w,
            out,
            &mut evaluate,
        )
    });
    (lambda.sqrt(), largest_motion(&mode).0)
}
