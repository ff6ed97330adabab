//! The raw form of the beam2d tables, as serde reads them (every key that some kind or
//! effect lacks is an `Option`), and the checks that turn it into the typed forms of the
//! parent module.
//!
//! The raw structs have the names of the typed ones they become (those are `typed::` here):
//! serde's type errors print a struct's name ("expected struct SampleSpec"), and the messages
//! stay as they were.

use serde::Deserialize;

use super::{
    self as typed, BeamMaterial, DrivenSpec, Explosive, FragmentSpec, LoadingKind, Projectile,
    QuietEnd, SampleKind,
};
use crate::bond::beam2d::{BreakingForm, BreakingRule};
use crate::error::Result;
use crate::sample::lattice2d::{LatticeShape, Outline};
use crate::scene::validate::{Range, check, require};
use crate::scene::{EffectKind, NeighborSpec, Scene};

/// Steps without a beam breaking after which an explosion or projectile run stops, unless
/// `loading.quiet_steps` says otherwise.
const DEFAULT_QUIET_STEPS: u64 = 300;

/// `[material]` as written: the keys of the beams, the breaking rule and the damping are
/// required with their effects only.
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
    pub beam_breaking_rule: Option<BreakingForm>,
}

/// `[sample]` as written: the vectorizable random lattice.
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

/// `[loading]` as written. Which keys apply depends on `kind`.
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

/// The beam2d model's tables of a scene as written: the model's `Section`.
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

/// Range checks of a beam2d scene; the scene in its typed form.
pub fn validate(s: &Scene, b: &Beam2dScene) -> Result<typed::Beam2dScene> {
    s.requires_contact(EffectKind::Damping)?;
    s.requires_contact(EffectKind::Friction)?;
    let sample = validate_lattice(s, &b.sample)?;
    let material = validate_material(s, &b.material)?;
    let loading = validate_loading(s, &b.loading, &b.sample)?;
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
    Ok(typed::Beam2dScene {
        material,
        sample,
        loading,
        neighbor: b.neighbor.clone(),
        fragments: b.fragments.clone(),
    })
}

/// `[material]`, checked against the effects, in its typed form.
fn validate_material(s: &Scene, m: &Material) -> Result<typed::Material> {
    check(s, "material.young", m.young, Range::POSITIVE, "Pa")?;
    check(s, "material.density", m.density, Range::POSITIVE, "kg/m³")?;
    check(s, "material.friction", m.friction, Range::NON_NEGATIVE, "")?;
    if s.has_effect(EffectKind::BeamBreaking) && !s.has_effect(EffectKind::Beams) {
        return Err(s.key_error(
            "effects",
            "lists \"beam_breaking\" without \"beams\"; it breaks beams, so add \"beams\"",
        ));
    }
    if m.beam_breaking_rule.is_some() && !s.has_effect(EffectKind::BeamBreaking) {
        return Err(s.key_error(
            "material.beam_breaking_rule",
            "is given without the \"beam_breaking\" effect; it says how beams break, so remove \
             it or add \"beam_breaking\" to effects",
        ));
    }
    let mut beams = None;
    if s.has_effect(EffectKind::Beams) {
        let why = "for the \"beams\" effect";
        let e = require(s, "material.beam_young", m.beam_young, why)?;
        check(s, "material.beam_young", e, Range::POSITIVE, "Pa")?;
        beams = Some(BeamMaterial {
            young: e,
            breaking: None,
        });
    }
    if let (true, Some(beams)) = (s.has_effect(EffectKind::BeamBreaking), &mut beams) {
        let why = "for the \"beam_breaking\" effect";
        let strain = require(
            s,
            "material.beam_strain_threshold",
            m.beam_strain_threshold,
            why,
        )?;
        check(
            s,
            "material.beam_strain_threshold",
            strain,
            Range::POSITIVE,
            "",
        )?;
        let bending = require(
            s,
            "material.beam_bending_threshold",
            m.beam_bending_threshold,
            why,
        )?;
        check(
            s,
            "material.beam_bending_threshold",
            bending,
            Range::POSITIVE,
            "rad",
        )?;
        beams.breaking = Some(BreakingRule {
            strain,
            bending,
            form: m.beam_breaking_rule.unwrap_or_default(),
        });
    }
    let (mut normal_damping, mut tangential_damping) = (0.0, 0.0);
    if s.has_effect(EffectKind::Damping) {
        normal_damping = require(
            s,
            "material.normal_damping",
            m.normal_damping,
            "for the \"damping\" effect of model.kind = \"beam2d\"",
        )?;
        check(
            s,
            "material.normal_damping",
            normal_damping,
            Range::NON_NEGATIVE,
            "1/s",
        )?;
    }
    if s.has_effect(EffectKind::Friction) {
        tangential_damping = require(
            s,
            "material.tangential_damping",
            m.tangential_damping,
            "for the \"friction\" effect of model.kind = \"beam2d\"",
        )?;
        check(
            s,
            "material.tangential_damping",
            tangential_damping,
            Range::NON_NEGATIVE,
            "1/s",
        )?;
    }
    Ok(typed::Material {
        young: m.young,
        density: m.density,
        friction: m.friction,
        normal_damping,
        tangential_damping,
        beams,
    })
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
pub(crate) const SPEED_OF_LIGHT: f64 = 299_792_458.0;

/// `[loading]`, checked against the sample, in its typed form.
fn validate_loading(s: &Scene, l: &LoadingSpec, p: &SampleSpec) -> Result<typed::LoadingSpec> {
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
    Ok(match l.kind {
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
            let driven = DrivenSpec {
                strain_rate: rate,
                end_strain: end,
                ramp_time: l.ramp_time.unwrap_or(0.0),
            };
            if l.kind == LoadingKind::ConfinedCompression {
                typed::LoadingSpec::ConfinedCompression(driven)
            } else {
                typed::LoadingSpec::ElasticModuli(driven)
            }
        }
        LoadingKind::Explosion | LoadingKind::Projectile => {
            let (mut energy, mut speed) = (0.0, 0.0);
            if l.kind == LoadingKind::Explosion {
                let e = require(s, "loading.energy", l.energy, &why)?;
                energy = e;
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
                speed = v;
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
            let end = QuietEnd {
                quiet_steps: l.quiet_steps.unwrap_or(DEFAULT_QUIET_STEPS),
                end_time: end,
            };
            if l.kind == LoadingKind::Explosion {
                typed::LoadingSpec::Explosion {
                    energy,
                    explosive: l.explosive.unwrap_or_default(),
                    end,
                }
            } else {
                typed::LoadingSpec::Projectile {
                    speed,
                    projectile: l.projectile.unwrap_or_default(),
                    end,
                }
            }
        }
    })
}

/// The vectorizable random lattice's keys, and the lattice in its typed form.
fn validate_lattice(s: &Scene, p: &SampleSpec) -> Result<typed::SampleSpec> {
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
    let (shape, squares) = match outline {
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
            (
                LatticeShape::Rectangle(cells),
                cells[0] as f64 * cells[1] as f64,
            )
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
            (LatticeShape::Disc(d), (d / spacing).powi(2))
        }
    };
    crate::scene::validate::check_bodies(s, "sample.spacing", squares, "polygons")?;
    Ok(typed::SampleSpec {
        spacing,
        disorder,
        shape,
        thickness: p.thickness.unwrap_or(1.0),
    })
}
