//! The beam2d model's own scene tables (`material`, `sample`, `loading`, `neighbor`,
//! `fragments`), typed and checked.
//!
//! Serde reads the tables into their raw form (`raw`: every key that some kind or effect
//! lacks is an `Option`); the checks there turn it into the forms here, which hold what the
//! scene's loading kind and effects need, present where they are required.

use serde::Deserialize;

use crate::bond::beam2d::BreakingRule;
use crate::probe::fragments::{PowerLawFit, fit_power_law, fit_power_law_counted, mass_histogram};
use crate::sample::lattice2d::LatticeShape;
use crate::scene::{EffectKind, NeighborSpec};

mod raw;
pub(crate) use raw::SPEED_OF_LIGHT;

pub(super) use raw::{Beam2dScene as RawBeam2dScene, validate};

/// The polygons' material, the beams and their breaking (Eq. 7-13), contact damping
/// (Eq. 3-4). The polygons are rigid: no Poisson's ratio.
#[derive(Debug, Clone)]
pub struct Material {
    /// Young's modulus E (Pa) of the overlap repulsion, > 0.
    pub young: f64,
    /// Density ρ (kg/m³), > 0.
    pub density: f64,
    /// Coulomb friction coefficient μ, ≥ 0 (used by the `friction` effect).
    pub friction: f64,
    /// Normal damping coefficient γ_N (1/s), ≥ 0: required with the `damping` effect; 0
    /// without it (then unused).
    pub normal_damping: f64,
    /// Tangential (friction) coefficient γ_T (1/s), ≥ 0: required with the `friction`
    /// effect; 0 without it (then unused).
    pub tangential_damping: f64,
    /// The beams: present with the `beams` effect.
    pub beams: Option<BeamMaterial>,
}

/// The beams' material and breaking rule.
#[derive(Debug, Clone, Copy)]
pub struct BeamMaterial {
    /// Young's modulus E of the beams (Pa), > 0.
    pub young: f64,
    /// With the `beam_breaking` effect: the stretching threshold t_ε (strain, > 0), the
    /// bending threshold t_Θ (rad, > 0) and how the terms combine (`beam_breaking_rule`:
    /// "eq13", the default, the paper's Eq. 13 as printed, "squared", "mean_angle" or
    /// "either_sign"; docs/validation.md, "Ablation").
    pub breaking: Option<BreakingRule>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SampleKind {
    /// Voronoi polygons of one random point per square of a regular grid.
    VectorizableRandomLattice,
}

/// The vectorizable random lattice (`kind = "vectorizable_random_lattice"`, the only kind).
#[derive(Debug, Clone, Copy)]
pub struct SampleSpec {
    /// Lattice spacing (m) of the grid of squares, > 0.
    pub spacing: f64,
    /// Largest distance (m) of a square's point from its centre, in [0, spacing].
    pub disorder: f64,
    /// The outline the polygons are cut to (`outline`): a rectangle of `cells` [nx, ny] grid
    /// squares, each ≥ 2, or a disc of `diameter` (m), more than three spacings across.
    pub shape: LatticeShape,
    /// Thickness (m) out of plane, > 0 (default 1).
    pub thickness: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadingKind {
    /// Uniaxial elongation, then compression from the same start, under plane stress with
    /// free sides (Section 3.1).
    ElasticModuli,
    /// Strain-controlled compression between confined horizontal boundaries (Section 3.2).
    ConfinedCompression,
    /// The centre polygon explodes (Section 3.3.1).
    Explosion,
    /// One polygon at the lower middle is shot into the block (Section 3.3.2).
    Projectile,
}

impl LoadingKind {
    pub fn as_str(self) -> &'static str {
        match self {
            LoadingKind::ElasticModuli => "elastic_moduli",
            LoadingKind::ConfinedCompression => "confined_compression",
            LoadingKind::Explosion => "explosion",
            LoadingKind::Projectile => "projectile",
        }
    }
}

/// What the loading prescribes, one variant per `loading.kind`.
#[derive(Debug, Clone, Copy)]
pub enum LoadingSpec {
    /// Uniaxial elongation, then compression from the same start, under plane stress with
    /// free sides (Section 3.1).
    ElasticModuli(DrivenSpec),
    /// Strain-controlled compression between confined horizontal boundaries (Section 3.2).
    ConfinedCompression(DrivenSpec),
    /// The centre polygon explodes (Section 3.3.1).
    Explosion {
        /// Energy E0 (J), > 0.
        energy: f64,
        /// The centre polygon: "spent" (default: removed once it has kicked its neighbours)
        /// or "kept" (left at rest, still bonded to them).
        explosive: Explosive,
        end: QuietEnd,
    },
    /// One polygon at the lower middle is shot into the block (Section 3.3.2).
    Projectile {
        /// Speed (m/s) of the projectile polygon, in (0, c).
        speed: f64,
        /// The projectile polygon: "bonded" (default: a polygon of the block, its beams
        /// intact) or "free" (its beams cut before the start: a loose grain shot into the
        /// block).
        projectile: Projectile,
        end: QuietEnd,
    },
}

/// The driven layers of `elastic_moduli` and `confined_compression`.
#[derive(Debug, Clone, Copy)]
pub struct DrivenSpec {
    /// Strain rate (1/s) of the driven layers, > 0.
    pub strain_rate: f64,
    /// Strain at which the test ends, in (0, 0.5).
    pub end_strain: f64,
    /// Time (s), ≥ 0, over which the driven boundaries reach their final speed (uniform
    /// acceleration); default 0.
    pub ramp_time: f64,
}

/// When an explosion or projectile run ends.
#[derive(Debug, Clone, Copy)]
pub struct QuietEnd {
    /// The run stops after this many steps without a beam breaking, ≥ 1 (default 300).
    pub quiet_steps: u64,
    /// The longest the run may last (s), > 0.
    pub end_time: f64,
}

/// What becomes of the explosion's centre polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Explosive {
    #[default]
    Spent,
    Kept,
}

/// Whether the projectile polygon starts bonded to the block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Projectile {
    #[default]
    Bonded,
    Free,
}

/// How fragment masses are binned and where the power law F(m) ~ m^-β is fitted
/// (docs/validation.md, "How β is fitted").
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FragmentSpec {
    /// A fixed fit range [lo, hi] in mean polygon masses; absent: the counted rule below.
    #[serde(default)]
    pub fit_range: Option<[f64; 2]>,
    /// The counted rule: the fit starts at the first bin whose centre is at least this many
    /// mean polygon masses ...
    #[serde(default = "default_fit_from")]
    pub fit_from: f64,
    /// ... and ends before the first bin after it with fewer fragments than this per run.
    #[serde(default = "default_min_per_bin")]
    pub min_per_bin: f64,
    /// Logarithmic bins per decade of mass.
    #[serde(default = "default_bins_per_decade")]
    pub bins_per_decade: u32,
}

fn default_fit_from() -> f64 {
    2.0
}

fn default_min_per_bin() -> f64 {
    5.0
}

fn default_bins_per_decade() -> u32 {
    4
}

impl Default for FragmentSpec {
    fn default() -> Self {
        FragmentSpec {
            fit_range: None,
            fit_from: default_fit_from(),
            min_per_bin: default_min_per_bin(),
            bins_per_decade: default_bins_per_decade(),
        }
    }
}

impl FragmentSpec {
    /// The power law fitted to the fragment `masses` (kg) of `runs` runs pooled, binned in
    /// units of `unit` (the mean polygon mass).
    pub fn fit(&self, masses: &[f64], unit: f64, runs: usize) -> Option<PowerLawFit> {
        let bins = mass_histogram(masses, unit, self.bins_per_decade, runs);
        match self.fit_range {
            Some([lo, hi]) => fit_power_law(&bins, lo * unit, hi * unit),
            None => fit_power_law_counted(&bins, self.fit_from * unit, self.min_per_bin, runs),
        }
    }
}

/// The beam2d model's tables of a scene, checked.
#[derive(Debug, Clone)]
pub struct Beam2dScene {
    pub material: Material,
    pub sample: SampleSpec,
    pub loading: LoadingSpec,
    pub neighbor: NeighborSpec,
    /// The fragment mass histogram and its power-law fit.
    pub fragments: FragmentSpec,
}

/// The effects of the beam2d model, in evaluation order.
pub const EFFECTS: [EffectKind; 5] = [
    EffectKind::Contact,
    EffectKind::Damping,
    EffectKind::Friction,
    EffectKind::Beams,
    EffectKind::BeamBreaking,
];
