//! The beam2d model's own scene tables (`material`, `sample`, `loading`, `neighbor`,
//! `fragments`), typed and checked.

use serde::Deserialize;

use crate::bond::beam2d::BreakingForm;
use crate::error::Result;
use crate::probe::fragments::{PowerLawFit, fit_power_law, fit_power_law_counted, mass_histogram};
use crate::sample::lattice2d::Outline;
use crate::scene::validate::{Range, check, require};
use crate::scene::{EffectKind, NeighborSpec, Scene};

/// The polygons' material, the beams and their breaking (Eq. 7-13), contact damping
/// (Eq. 3-4). The polygons are rigid: no Poisson's ratio.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E (Pa) of the overlap repulsion, > 0.
    pub young: f64,
    /// Density ρ (kg/m³), > 0.
    pub density: f64,
    /// Coulomb friction coefficient μ, ≥ 0 (used by the `friction` effect).
    #[serde(default)]
    pub friction: f64,
    /// Young's modulus E of the beams (Pa), > 0.
    pub beam_young: Option<f64>,
    /// Stretching threshold t_ε of the breaking rule (strain), > 0.
    pub beam_strain_threshold: Option<f64>,
    /// Bending threshold t_Θ of the breaking rule (rad), > 0.
    pub beam_bending_threshold: Option<f64>,
    /// Normal damping coefficient γ_N (1/s), ≥ 0.
    pub normal_damping: Option<f64>,
    /// Tangential (friction) coefficient γ_T (1/s), ≥ 0.
    pub tangential_damping: Option<f64>,
    /// How the breaking rule's terms combine: "eq13" (default, the paper's Eq. 13 as
    /// printed), "squared", "mean_angle" or "either_sign" (docs/validation.md, "Ablation").
    #[serde(default)]
    pub beam_breaking_rule: BreakingForm,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SampleKind {
    /// Voronoi polygons of one random point per square of a regular grid.
    VectorizableRandomLattice,
}

/// The vectorizable random lattice.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleSpec {
    pub kind: SampleKind,
    /// Lattice spacing (m) of the grid of squares.
    pub spacing: Option<f64>,
    /// Largest distance (m) of a square's point from its centre, in [0, spacing].
    pub disorder: Option<f64>,
    /// The outline the polygons are cut to.
    pub outline: Option<Outline>,
    /// Grid squares [nx, ny] of a rectangle.
    pub cells: Option<[usize; 2]>,
    /// Diameter (m) of a disc.
    pub diameter: Option<f64>,
    /// Thickness (m) out of plane (default 1).
    pub thickness: Option<f64>,
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

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadingSpec {
    pub kind: LoadingKind,
    /// Strain rate (1/s) of the driven layers, > 0.
    pub strain_rate: Option<f64>,
    /// Strain at which the moduli or compression test ends, in (0, 0.5).
    pub end_strain: Option<f64>,
    /// Time (s) over which the driven boundaries reach their final speed (uniform
    /// acceleration).
    pub ramp_time: Option<f64>,
    /// Energy E0 (J) of the explosion.
    pub energy: Option<f64>,
    /// Speed (m/s) of the projectile polygon, > 0.
    pub speed: Option<f64>,
    /// The run stops after this many steps without a beam breaking (explosion, projectile).
    pub quiet_steps: Option<u64>,
    /// The longest an explosion or projectile run may last (s).
    pub end_time: Option<f64>,
    /// The explosion's centre polygon: "spent" (default: removed once it has kicked its
    /// neighbours) or "kept" (left at rest, still bonded to them); explosion only.
    pub explosive: Option<Explosive>,
    /// The projectile polygon: "bonded" (default: a polygon of the block, its beams intact) or
    /// "free" (its beams cut before the start: a loose grain shot into the block); projectile
    /// only.
    pub projectile: Option<Projectile>,
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

/// The beam2d model's tables of a scene.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Beam2dScene {
    pub material: Material,
    pub sample: SampleSpec,
    pub loading: LoadingSpec,
    #[serde(default)]
    pub neighbor: NeighborSpec,
    /// The fragment mass histogram and its power-law fit.
    #[serde(default)]
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

/// Range checks of a beam2d scene.
pub fn validate(s: &Scene, b: &Beam2dScene) -> Result<()> {
    s.requires_contact(EffectKind::Damping)?;
    s.requires_contact(EffectKind::Friction)?;
    validate_lattice(s, &b.sample)?;
    validate_material(s, &b.material)?;
    validate_loading(s, &b.loading, &b.sample)?;
    if let Some(skin) = b.neighbor.skin {
        check(s, "neighbor.skin", skin, Range::POSITIVE, "m")?;
    }
    let f = &b.fragments;
    if let Some([lo, hi]) = f.fit_range {
        check(
            s,
            "fragments.fit_range",
            lo,
            Range::POSITIVE,
            "mean polygon masses",
        )?;
        check(
            s,
            "fragments.fit_range",
            hi,
            Range::open(lo, f64::INFINITY),
            "mean polygon masses (the upper end must exceed the lower)",
        )?;
    }
    check(
        s,
        "fragments.fit_from",
        f.fit_from,
        Range::POSITIVE,
        "mean polygon masses",
    )?;
    check(
        s,
        "fragments.min_per_bin",
        f.min_per_bin,
        Range::POSITIVE,
        "fragments per run",
    )?;
    if f.bins_per_decade == 0 {
        return Err(s.key_error(
            "fragments.bins_per_decade",
            "= 0 is outside the allowed range [1, ∞)",
        ));
    }
    Ok(())
}

fn validate_material(s: &Scene, m: &Material) -> Result<()> {
    check(s, "material.young", m.young, Range::POSITIVE, "Pa")?;
    check(s, "material.density", m.density, Range::POSITIVE, "kg/m³")?;
    check(s, "material.friction", m.friction, Range::NON_NEGATIVE, "")?;
    if s.has_effect(EffectKind::BeamBreaking) && !s.has_effect(EffectKind::Beams) {
        return Err(s.key_error(
            "effects",
            "lists \"beam_breaking\" without \"beams\"; it breaks beams, so add \"beams\"",
        ));
    }
    if s.has_effect(EffectKind::Beams) {
        let why = "for the \"beams\" effect";
        let e = require(s, "material.beam_young", m.beam_young, why)?;
        check(s, "material.beam_young", e, Range::POSITIVE, "Pa")?;
    }
    if s.has_effect(EffectKind::BeamBreaking) {
        let why = "for the \"beam_breaking\" effect";
        let t = require(
            s,
            "material.beam_strain_threshold",
            m.beam_strain_threshold,
            why,
        )?;
        check(s, "material.beam_strain_threshold", t, Range::POSITIVE, "")?;
        let t = require(
            s,
            "material.beam_bending_threshold",
            m.beam_bending_threshold,
            why,
        )?;
        check(
            s,
            "material.beam_bending_threshold",
            t,
            Range::POSITIVE,
            "rad",
        )?;
    }
    if s.has_effect(EffectKind::Damping) {
        let g = require(
            s,
            "material.normal_damping",
            m.normal_damping,
            "for the \"damping\" effect of model.kind = \"beam2d\"",
        )?;
        check(s, "material.normal_damping", g, Range::NON_NEGATIVE, "1/s")?;
    }
    if s.has_effect(EffectKind::Friction) {
        let g = require(
            s,
            "material.tangential_damping",
            m.tangential_damping,
            "for the \"friction\" effect of model.kind = \"beam2d\"",
        )?;
        check(
            s,
            "material.tangential_damping",
            g,
            Range::NON_NEGATIVE,
            "1/s",
        )?;
    }
    Ok(())
}

/// The smallest disc an explosion is sure to find an inner centre polygon in, in lattice
/// spacings s. Every point of the plane is within √2 s of the point of its square, so a cell
/// lies within √2 s of its point: the cell holding the centre has its centroid within 2√2 s of
/// it, so has the chosen polygon (the centroid nearest the centre), whose cell then lies within
/// 4√2 s = 5.66 s of the centre, inside a disc of 12 s across (even as the 256-gon). Discs
/// between 3 (the lattice's own limit) and 12 spacings across were refused at build or not,
/// as the seed fell (30 seeds: 9 refused at 3.05 spacings, 1 at 3.8, none from 4).
const EXPLOSION_DISC_SPACINGS: f64 = 12.0;

/// The projectile's speed must stay below this (m/s): the polygons move by Newton's laws, and a
/// speed of 1e308 m/s, finite itself, gave an infinite kinetic energy in series.csv.
const SPEED_OF_LIGHT: f64 = 299_792_458.0;

fn validate_loading(s: &Scene, l: &LoadingSpec, p: &SampleSpec) -> Result<()> {
    let kind = l.kind.as_str();
    let why = format!("for loading.kind = \"{kind}\"");
    let outline = require(
        s,
        "sample.outline",
        p.outline,
        "for sample.kind = \"vectorizable_random_lattice\"",
    )?;
    if l.explosive.is_some() && l.kind != LoadingKind::Explosion {
        return Err(s.key_error(
            "loading.explosive",
            format!(
                "is given {why}; it belongs to loading.kind = \"explosion\" only, so remove it"
            ),
        ));
    }
    if l.projectile.is_some() && l.kind != LoadingKind::Projectile {
        return Err(s.key_error(
            "loading.projectile",
            format!(
                "is given {why}; it belongs to loading.kind = \"projectile\" only, so remove it"
            ),
        ));
    }
    match l.kind {
        LoadingKind::ElasticModuli | LoadingKind::ConfinedCompression => {
            if outline != Outline::Rectangle {
                return Err(s.key_error(
                    "sample.outline",
                    format!("= \"{}\" cannot be loaded {why}, which drives the top and bottom of a rectangle; use \"rectangle\"", outline.as_str()),
                ));
            }
            let rate = require(s, "loading.strain_rate", l.strain_rate, &why)?;
            check(s, "loading.strain_rate", rate, Range::POSITIVE, "1/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, &why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 0.5), "")?;
            if let Some(ramp) = l.ramp_time {
                check(s, "loading.ramp_time", ramp, Range::NON_NEGATIVE, "s")?;
            }
        }
        LoadingKind::Explosion | LoadingKind::Projectile => {
            if l.kind == LoadingKind::Explosion {
                let e = require(s, "loading.energy", l.energy, &why)?;
                check(s, "loading.energy", e, Range::POSITIVE, "J")?;
                if let (Outline::Disc, Some(d), Some(spacing)) = (outline, p.diameter, p.spacing) {
                    check(
                        s,
                        "sample.diameter",
                        d,
                        Range::closed(EXPLOSION_DISC_SPACINGS * spacing, f64::INFINITY),
                        "m (at least 12 lattice spacings for an explosion: the centre polygon must not touch the rim)",
                    )?;
                }
            } else {
                if outline != Outline::Rectangle {
                    return Err(s.key_error(
                        "sample.outline",
                        format!(
                            "= \"{}\" has no lower middle to shoot from {why}; use \"rectangle\"",
                            outline.as_str()
                        ),
                    ));
                }
                let v = require(s, "loading.speed", l.speed, &why)?;
                check(
                    s,
                    "loading.speed",
                    v,
                    Range::open(0.0, SPEED_OF_LIGHT),
                    "m/s (below the speed of light: the model is Newtonian)",
                )?;
            }
            let end = require(
                s,
                "loading.end_time",
                l.end_time,
                &format!("{why} (the longest the run may last)"),
            )?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
            if l.quiet_steps == Some(0) {
                return Err(s.key_error(
                    "loading.quiet_steps",
                    "= 0 is outside the allowed range [1, ∞)",
                ));
            }
        }
    }
    Ok(())
}

/// The vectorizable random lattice's keys.
fn validate_lattice(s: &Scene, p: &SampleSpec) -> Result<()> {
    let why = "for sample.kind = \"vectorizable_random_lattice\"";
    let spacing = require(s, "sample.spacing", p.spacing, why)?;
    check(s, "sample.spacing", spacing, Range::POSITIVE, "m")?;
    let disorder = require(s, "sample.disorder", p.disorder, why)?;
    check(
        s,
        "sample.disorder",
        disorder,
        Range::closed(0.0, spacing),
        "m (0 to sample.spacing)",
    )?;
    if let Some(t) = p.thickness {
        check(s, "sample.thickness", t, Range::POSITIVE, "m")?;
    }
    let outline = require(s, "sample.outline", p.outline, why)?;
    let squares = match outline {
        Outline::Rectangle => {
            let cells = require(
                s,
                "sample.cells",
                p.cells,
                "for sample.outline = \"rectangle\"",
            )?;
            if cells.iter().any(|&c| c < 2) {
                return Err(s.key_error(
                    "sample.cells",
                    format!("= {cells:?} has an entry below 2; each of [nx, ny] must be in [2, ∞)"),
                ));
            }
            cells[0] as f64 * cells[1] as f64
        }
        Outline::Disc => {
            let d = require(
                s,
                "sample.diameter",
                p.diameter,
                "for sample.outline = \"disc\"",
            )?;
            check(
                s,
                "sample.diameter",
                d,
                Range::open(3.0 * spacing, f64::INFINITY),
                "m (more than three lattice spacings)",
            )?;
            (d / spacing).powi(2)
        }
    };
    crate::scene::validate::check_bodies(s, "sample.spacing", squares, "polygons")
}
