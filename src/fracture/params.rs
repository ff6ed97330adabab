//! The scene's fracture constants resolved, the allowed ranges of the keys that count, and
//! each grain's keyed strength and jitter draws.

use super::*;

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
