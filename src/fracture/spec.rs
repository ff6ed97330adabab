//! The `[fracture]` table of a granular scene: the constants of particle fracture, with the
//! paper's values as defaults.

use serde::{Deserialize, Serialize};

/// Particle fracture of the granular model (poly-ellipsoid-fracture-shpb.txt, Section 3).
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
    /// a grain of `reference_radius` with P = 1/e (Eq. 18). Required with `fracture`.
    pub reference_strength: Option<f64>,
    /// Reference equivalent radius x_M (m) of the Weibull size effect (Eq. 18); required with
    /// `weibull`.
    pub reference_radius: Option<f64>,
    /// Weibull modulus w (Eq. 18), > 0; default 1.
    #[serde(default = "default_weibull_modulus")]
    pub weibull_modulus: f64,
    /// Which strengths the Weibull factor scales (with `weibull`): `"contact"`, the contact
    /// tensile strength only, as the paper reads (Section 3.2 ties Weibull's statistics to the
    /// contact strength of Brzesowsky et al. and takes σc and m_i from Hoek and Martin);
    /// `"both"`, σc of Hoek–Brown as well. Default `"contact"`.
    #[serde(default)]
    pub weibull_on: WeibullOn,
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
}

impl WeibullOn {
    pub fn as_str(self) -> &'static str {
        match self {
            WeibullOn::Contact => "contact",
            WeibullOn::Both => "both",
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
            weibull_on: WeibullOn::default(),
            critical_contacts: default_critical_contacts(),
            toughness: default_toughness(),
            springs: default_springs(),
            ideal_plane: true,
            plane_jitter: true,
        }
    }
}
