//! The `[fracture]` table of a granular scene: the constants of particle fracture, with the
//! paper's values as defaults.

use serde::{Deserialize, Serialize};

/// Particle fracture of the granular model (granular paper, Section 3).
/// Stresses in Pa, compression positive where Hoek–Brown is concerned.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FractureSpec {
    /// Hoek–Brown material constant m_i (Eq. 14), > 0; default 20.56 (Fig. 6).
    #[serde(default = "default_mi")]
    pub mi: f64,
    /// Hoek–Brown compressive strength σ_c (Pa), > 0; default 592 MPa (Fig. 6). With
    /// `weibull` and `weibull_on = "both"`, the strength of a grain of `reference_radius` with
    /// P = 1/e; otherwise every grain's.
    #[serde(default = "default_sigma_c")]
    pub sigma_c: f64,
    /// Tensile strength σ_fM (Pa) of the contact criterion (Eq. 17); with `weibull`, that of
    /// a grain of `reference_radius` with P = 1/e (Eq. 18). Required with `fracture`, but
    /// with `weibull_on = "particle"`, where it defaults to the Hertz edge stress at the
    /// platen contacts of the reference grain failing by Hoek–Brown
    /// (`crate::fracture::platen_contact_strength`).
    pub reference_strength: Option<f64>,
    /// Reference equivalent radius x_M (m) of the Weibull size effect (Eq. 18); required with
    /// `weibull`.
    pub reference_radius: Option<f64>,
    /// Weibull modulus w (Eq. 18), > 0; default 1.
    #[serde(default = "default_weibull_modulus")]
    pub weibull_modulus: f64,
    /// Size exponent β of the strength: strengths scale as (x/x_M)^(−β) with the equivalent
    /// radius x; in [0, 6]. Default 2/w, Eq. 18 as its source derives it (a flawed area ∝ x²).
    /// With `weibull_on = "particle"` this is the exponent b of the particle strength F/d²
    /// that single-grain crushing tests measure.
    pub size_exponent: Option<f64>,
    /// Which strengths the Weibull factor scales (with `weibull`): `"contact"`, the contact
    /// tensile strength only, as the paper reads (Section 3.2 ties Weibull's statistics to the
    /// contact strength of Brzesowsky et al. and takes σc and m_i from Hoek and Martin);
    /// `"both"`, σc of Hoek–Brown as well; `"particle"`, the factor is the grain's particle
    /// strength (its crushing force over d², relative to the reference grain's): σc scales
    /// with it and the contact tensile strength with its cube root (the Hertz edge stress at
    /// a given force grows as the force's cube root). Default `"contact"`.
    #[serde(default)]
    pub weibull_on: WeibullOn,
    /// Comminution limit (m): a grain or piece whose equivalent radius (3V/4π)^⅓ is below it
    /// no longer splits; it stays whole (unbreakable) and goes on carrying load through its
    /// contacts. Default: none (every piece can split again).
    pub comminution_limit: Option<f64>,
    /// Contacts above the tensile strength that break a grain, in [3, 64]; default 3.
    #[serde(default = "default_critical_contacts")]
    pub critical_contacts: usize,
    /// Fracture toughness K_Ic (Pa·m^½) giving the cohesive energy G_c = K_Ic² / E' (Eq. 38);
    /// default 1.77 MPa·m^½ (silica sand).
    #[serde(default = "default_toughness")]
    pub toughness: f64,
    /// Cohesive springs n_s on a break plane, in [3, 16]; default 4.
    #[serde(default = "default_springs")]
    pub springs: usize,
    /// Spheres turn their principal directions to the ideal break plane (Section 3.3);
    /// default true.
    #[serde(default = "yes")]
    pub ideal_plane: bool,
    /// Random slight rotation of the break plane by θ in [θmax/2, θmax], θmax = arctan(1/5)
    /// (Section 3.3.1); default true.
    #[serde(default = "yes")]
    pub plane_jitter: bool,
}

/// The strengths a grain's Weibull factor scales (`fracture.weibull_on`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WeibullOn {
    /// The contact tensile strength σ_fM only (the paper's reading).
    #[default]
    Contact,
    /// The contact tensile strength and Hoek–Brown's σc.
    Both,
    /// The particle strength: σc scaled by the factor, the contact tensile strength by its
    /// cube root.
    Particle,
}

impl WeibullOn {
    pub fn as_str(self) -> &'static str {
        match self {
            WeibullOn::Contact => "contact",
            WeibullOn::Both => "both",
            WeibullOn::Particle => "particle",
        }
    }
}

fn default_mi() -> f64 {
    20.56
}
fn default_sigma_c() -> f64 {
    592e6
}
fn default_weibull_modulus() -> f64 {
    1.0
}
fn default_critical_contacts() -> usize {
    3
}
fn default_toughness() -> f64 {
    1.77e6
}
fn default_springs() -> usize {
    4
}
fn yes() -> bool {
    true
}

impl Default for FractureSpec {
    fn default() -> Self {
        FractureSpec {
            mi: default_mi(),
            sigma_c: default_sigma_c(),
            reference_strength: None,
            reference_radius: None,
            weibull_modulus: default_weibull_modulus(),
            size_exponent: None,
            weibull_on: WeibullOn::default(),
            comminution_limit: None,
            critical_contacts: default_critical_contacts(),
            toughness: default_toughness(),
            springs: default_springs(),
            ideal_plane: true,
            plane_jitter: true,
        }
    }
}
