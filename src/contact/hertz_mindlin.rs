//! Hertz–Mindlin contact between elastic spheres (and between a sphere and a rigid wall of
//! the same material), with optional viscous damping and Coulomb friction.
//!
//! Conventions (as LAMMPS `pair_style granular`): `n` is the unit normal pointing from body j
//! to body i, `δ > 0` the overlap, `v` the velocity of i's contact point relative to j's.
//! The returned force acts on i; j receives its opposite.
//!
//! * Normal (Hertz): `F_e = 4/3 E* sqrt(R*) δ^(3/2)`, `E* = E / (2 (1 - ν²))` for two bodies
//!   of one material, `R* = R_i R_j / (R_i + R_j)` (`R*` = R for a wall).
//! * Damping: `F_d = -c sqrt(m* S_n) v_n` with `S_n = 2 E* a`, `a = sqrt(R* δ)` the contact
//!   radius, and `c` from the coefficient of restitution ([`super::restitution`]). The total
//!   normal force is clamped at zero: a cohesionless contact never pulls.
//! * Tangential (Mindlin, no-slip stiffness `k_t = 8 G* a`, `G* = G / (2 (2 - ν))`): the
//!   elastic tangential displacement ξ is kept per contact, turned onto the current tangent
//!   plane with its length kept, and advanced by `v_t dt`; `F_t = -k_t ξ - c sqrt(m* S_n) v_t`
//!   (tangential damping equal to the normal one). When `|F_t| > μ F_n` the force is scaled to
//!   `μ F_n` and ξ reset to match it (Coulomb limit).

use std::cell::Cell;

use crate::state::Vec3;

/// Material constants of a Hertz contact (one material against itself).
#[derive(Debug, Clone, Copy)]
pub struct Hertz {
    /// Effective modulus E* (Pa).
    pub e_eff: f64,
}

impl Hertz {
    pub fn new(young: f64, poisson: f64) -> Self {
        Hertz {
            e_eff: young / (2.0 * (1.0 - poisson * poisson)),
        }
    }
}

/// Viscous normal damping `-c sqrt(m* S_n) v_n`.
#[derive(Debug, Clone, Copy)]
pub struct ViscousDamping {
    pub restitution: f64,
    /// The dimensionless coefficient c.
    pub coefficient: f64,
}

impl ViscousDamping {
    pub fn from_restitution(e: f64) -> Self {
        ViscousDamping {
            restitution: e,
            coefficient: super::restitution::damping_for_restitution(e),
        }
    }
}

thread_local! {
    static MINDLIN_BUILT: Cell<usize> = const { Cell::new(0) };
}

/// How many Mindlin tangential models this thread has constructed (tests use it to show that
/// a scene without `friction` never builds one).
pub fn mindlin_models_built() -> usize {
    MINDLIN_BUILT.with(|c| c.get())
}

/// Mindlin tangential model with the Coulomb limit.
#[derive(Debug, Clone, Copy)]
pub struct Mindlin {
    /// Effective shear modulus G* (Pa).
    pub g_eff: f64,
    /// Coulomb friction coefficient μ.
    pub mu: f64,
}

impl Mindlin {
    pub fn new(young: f64, poisson: f64, mu: f64) -> Self {
        MINDLIN_BUILT.with(|c| c.set(c.get() + 1));
        let g = young / (2.0 * (1.0 + poisson));
        Mindlin {
            g_eff: g / (2.0 * (2.0 - poisson)),
            mu,
        }
    }
}

/// The constants the force kernel reads, folded once. Absent sub-models leave zeros that the
/// kernel never reads (its const parameters switch them off at compile time).
#[derive(Debug, Clone, Copy, Default)]
pub struct KernelConsts {
    /// 4/3 E* (Pa).
    pub four_thirds_e: f64,
    /// 2 E* (Pa).
    pub two_e: f64,
    /// The damping coefficient c (dimensionless; 0 without damping).
    pub damping: f64,
    /// 8 G* (Pa; 0 without friction).
    pub eight_g: f64,
    /// Coulomb friction coefficient μ (0 without friction).
    pub mu: f64,
}

impl KernelConsts {
    pub fn new(hertz: &Hertz, damping: Option<&ViscousDamping>, mindlin: Option<&Mindlin>) -> Self {
        KernelConsts {
            four_thirds_e: 4.0 / 3.0 * hertz.e_eff,
            two_e: 2.0 * hertz.e_eff,
            damping: damping.map_or(0.0, |d| d.coefficient),
            eight_g: mindlin.map_or(0.0, |m| 8.0 * m.g_eff),
            mu: mindlin.map_or(0.0, |m| m.mu),
        }
    }
}

/// Result of one contact: the force on body i (N), the normal contact stiffness
/// `dF_e/dδ = 2 E* a` (N/m), and for energy accounts and fracture criteria the normal force
/// (N), its elastic (Hertz) part `F_e = 4/3 E* a δ` (N), the contact radius `a` (m), the
/// elastic energy stored in the contact (J: normal `(2/5) F_e δ`, tangential `k_t |ξ|² / 2`)
/// and the energy damping and sliding dissipated in this step (J). The kernel is always
/// inlined: callers that ignore a field pay nothing for it.
#[derive(Debug, Clone, Copy)]
pub struct ContactForce {
    pub force: Vec3,
    pub stiffness: f64,
    pub normal_force: f64,
    pub hertz_force: f64,
    pub radius: f64,
    pub elastic_energy: f64,
    pub dissipated: f64,
}

/// The Hertz–Mindlin force on body i for overlap `delta > 0` along `n`.
///
/// `v` is the velocity of i's contact point relative to j's; `hist` the tangential
/// displacement of this contact (unused without friction); `update` is false only for the
/// force evaluation before the first step, which must not advance the history.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn hertz_mindlin<const DAMP: bool, const FRIC: bool>(
    k: &KernelConsts,
    n: &Vec3,
    delta: f64,
    r_eff: f64,
    m_eff: f64,
    v: &Vec3,
    hist: &mut Vec3,
    dt: f64,
    update: bool,
) -> ContactForce {
    let a = (r_eff * delta).sqrt();
    let vn = v.dot(n);
    let fn_elastic = k.four_thirds_e * a * delta;
    let mut fn_total = fn_elastic;
    let mut eta = 0.0;
    let mut dissipated = 0.0;
    let mut elastic_energy = 0.4 * fn_elastic * delta;
    if DAMP {
        eta = k.damping * (m_eff * k.two_e * a).sqrt();
        fn_total -= eta * vn;
        fn_total = fn_total.max(0.0);
        // Power of the damping force against the normal motion, over the step.
        dissipated += (fn_elastic - fn_total) * vn * dt;
    }
    let mut force = n * fn_total;
    if FRIC {
        let vt = v - n * vn;
        let kt = k.eight_g * a;
        let mut stored_before = 0.0;
        let mut spring_before = Vec3::zeros();
        if update {
            let along_n = hist.dot(n);
            if along_n != 0.0 {
                let len = hist.norm();
                *hist -= n * along_n;
                let projected = hist.norm();
                if projected > 0.0 {
                    *hist *= len / projected;
                }
            }
            stored_before = 0.5 * kt * hist.norm_squared();
            spring_before = *hist * (-kt);
            *hist += vt * dt;
        }
        let mut ft = *hist * (-kt);
        if DAMP {
            ft -= vt * eta;
        }
        let limit = k.mu * fn_total;
        let ft2 = ft.norm_squared();
        if ft2 > limit * limit {
            if hist.norm_squared() > 0.0 {
                ft *= limit / ft2.sqrt();
                // Keep the elastic part of the limited force as the new displacement (as
                // LAMMPS's granular styles do), but never more than the Coulomb limit: where
                // damping alone exceeds twice the limit (fast glancing impacts of fragments),
                // that part points along the slip and holds more than the limit, an energy the
                // limited force can never give back, which a stiffening contact multiplies (kt
                // grows with a) and the next slipping step books as dissipated (crush_grain:
                // 0.3 mJ of 5 mJ in one step). While the slip goes on, the next step's trial
                // force exceeds the limit either way and the force applied is the limit.
                let mut elastic = ft;
                if DAMP {
                    elastic += vt * eta;
                    let e2 = elastic.norm_squared();
                    if e2 > limit * limit {
                        elastic *= limit / e2.sqrt();
                    }
                }
                *hist = elastic * (-1.0 / kt);
            } else {
                ft = Vec3::zeros();
            }
        }
        let stored = 0.5 * kt * hist.norm_squared();
        if update {
            // What the tangential force took from the relative motion over the step (its
            // spring part by the trapezoid rule, so that a sticking spring dissipates nothing),
            // less what the spring stored: tangential damping and Coulomb sliding together,
            // counted once.
            let spring = *hist * (-kt);
            let work = -((spring_before + spring) * 0.5 + (ft - spring)).dot(&vt) * dt;
            dissipated += work - (stored - stored_before);
        }
        elastic_energy += stored;
        force += ft;
    }
    ContactForce {
        force,
        stiffness: k.two_e * a,
        normal_force: fn_total,
        hertz_force: fn_elastic,
        radius: a,
        elastic_energy,
        dissipated,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn consts(mu: f64, c: f64) -> KernelConsts {
        let h = Hertz::new(60e9, 0.17);
        let d = ViscousDamping {
            restitution: 0.5,
            coefficient: c,
        };
        let m = Mindlin::new(60e9, 0.17, mu);
        KernelConsts::new(&h, Some(&d), Some(&m))
    }

    #[test]
    fn hertz_normal_force_matches_closed_form() {
        let k = consts(0.5, 0.0);
        let (r, delta) = (0.15e-3, 1e-6);
        let mut h = Vec3::zeros();
        let f = hertz_mindlin::<false, false>(
            &k,
            &Vec3::z(),
            delta,
            r,
            1.0,
            &Vec3::zeros(),
            &mut h,
            1e-8,
            true,
        );
        let e_eff = 60e9 / (2.0 * (1.0 - 0.17 * 0.17));
        let expected = 4.0 / 3.0 * e_eff * r.sqrt() * delta.powf(1.5);
        assert!((f.force.z - expected).abs() < 1e-12 * expected);
        assert!((f.stiffness - 2.0 * e_eff * (r * delta).sqrt()).abs() < 1e-6);
    }

    /// The Hertz part of the normal force, which the contact tensile stress (Eq. 17) reads,
    /// is `4/3 E* a δ` whatever the damping; the damped total differs while the bodies
    /// approach, and over the Hertz radius it grows without bound as a contact begins
    /// (`η v / a²` with `η ∝ a^½`), where the Hertz part's pressure falls to zero.
    #[test]
    fn the_hertz_force_is_the_elastic_part_and_its_pressure_vanishes_as_a_contact_begins() {
        let k = consts(0.5, 0.3);
        let e_eff = 60e9 / (2.0 * (1.0 - 0.17 * 0.17));
        let (r, m, v) = (0.15e-3, 1e-7, 3.0);
        let mut last_total = 0.0;
        for delta in [1e-8, 1e-9, 1e-10] {
            let mut h = Vec3::zeros();
            // i approaches j along n: the relative velocity of i is -v n.
            let f = hertz_mindlin::<true, false>(
                &k,
                &Vec3::z(),
                delta,
                r,
                m,
                &Vec3::new(0.0, 0.0, -v),
                &mut h,
                1e-9,
                true,
            );
            let elastic = 4.0 / 3.0 * e_eff * r.sqrt() * delta.powf(1.5);
            assert!((f.hertz_force - elastic).abs() < 1e-12 * elastic);
            assert!(f.normal_force > 2.0 * f.hertz_force);
            let a2 = f.radius * f.radius;
            // q0 = 3F / (2π a²): from the Hertz force 2 E* a / (π R), falling with a.
            let q_hertz = 3.0 * f.hertz_force / (2.0 * std::f64::consts::PI * a2);
            let expected = 2.0 * e_eff * f.radius / (std::f64::consts::PI * r);
            assert!((q_hertz / expected - 1.0).abs() < 1e-12);
            let q_total = 3.0 * f.normal_force / (2.0 * std::f64::consts::PI * a2);
            assert!(q_total > last_total);
            last_total = q_total;
        }
    }

    #[test]
    fn tangential_force_saturates_at_coulomb_limit() {
        let k = consts(0.3, 0.0);
        let mut h = Vec3::zeros();
        let v = Vec3::new(1.0, 0.0, 0.0);
        let mut last = Vec3::zeros();
        for _ in 0..10_000 {
            last = hertz_mindlin::<false, true>(
                &k,
                &Vec3::z(),
                1e-6,
                0.15e-3,
                1e-7,
                &v,
                &mut h,
                1e-8,
                true,
            )
            .force;
        }
        let fnorm = last.z;
        let ft = (last.x * last.x + last.y * last.y).sqrt();
        assert!((ft - 0.3 * fnorm).abs() < 1e-12 * fnorm);
        assert!(last.x < 0.0, "friction opposes the slip");
    }

    /// A fast glancing impact: the tangential damping force alone is several times the
    /// Coulomb limit. The spring may hold at most the limit (LAMMPS's rule would leave it
    /// holding `η|v_t| − μF_n` along the slip), so its energy stays `(μF_n)²/(2k_t)` however
    /// much the contact then stiffens.
    #[test]
    fn spring_holds_at_most_the_coulomb_limit_when_damping_exceeds_it() {
        let k = consts(0.5, 0.2);
        let n = Vec3::z();
        let (r, m) = (0.1e-3, 4e-8);
        let v = Vec3::new(135.0, 0.0, -34.0);
        let mut h = Vec3::new(1e-12, 0.0, 0.0);
        let dt = 1.4e-8;
        for delta in [2e-8, 5e-7, 1e-6] {
            let f = hertz_mindlin::<true, true>(&k, &n, delta, r, m, &v, &mut h, dt, true);
            let a = (r * delta).sqrt();
            let eta = 0.2 * (m * k.two_e * a).sqrt();
            let limit = 0.5 * f.normal_force;
            assert!(
                eta * 135.0 > 2.0 * limit,
                "damping {} vs limit {limit}",
                eta * 135.0
            );
            let kt = k.eight_g * a;
            let spring = kt * h.norm();
            assert!(
                spring <= limit * (1.0 + 1e-12),
                "spring {spring} N over the limit {limit} N"
            );
            let ft = (f.force.x * f.force.x + f.force.y * f.force.y).sqrt();
            assert!(
                (ft - limit).abs() < 1e-12 * limit,
                "applied {ft} N, limit {limit} N"
            );
            assert!(
                f.dissipated > 0.0,
                "a slipping step dissipates: {}",
                f.dissipated
            );
        }
    }
}
