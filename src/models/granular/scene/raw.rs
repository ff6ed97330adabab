//! The raw form of the granular tables, as serde reads them (every key that some kind
//! lacks is an `Option`), and the checks that turn it into the typed forms of the parent
//! module. Each failure names the key, its value and the allowed range.
//!
//! The raw structs have the names of the typed ones they become (those are `typed::` here):
//! serde's type errors print a struct's name ("expected struct SampleSpec"), and the messages
//! stay as they were.

use serde::Deserialize;

use super::{
    self as typed, Amount, FileSample, GrainShape, Grains, LatticeSample, LoadingKind,
    Orientations, Packing, PressureCompaction, Radii, RandomSample, RandomShape, SampleKind,
    SingleGrain, WallSpec,
};
use crate::error::Result;
use crate::fracture::{FractureSpec, WeibullOn};
use crate::scene::validate::{Range, check, check_bodies, require};
use crate::scene::{EffectKind, NeighborSpec, Scene};

/// `[material]` as written; `poisson` is optional here so that its absence is reported as
/// this model's requirement.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E (Pa), > 0.
    pub young: f64,
    /// Poisson's ratio ν, in (-1, 0.5).
    pub poisson: Option<f64>,
    /// Density ρ (kg/m³), > 0.
    pub density: f64,
    /// Coulomb friction coefficient μ, ≥ 0 (used by the `friction` effect).
    #[serde(default)]
    pub friction: f64,
    /// Normal coefficient of restitution e, in (0, 1] (used by the `damping` effect).
    #[serde(default = "one")]
    pub restitution: f64,
}

fn one() -> f64 {
    1.0
}

/// How the sample is made. Which keys apply depends on `kind`; see docs/scenes.md.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleSpec {
    pub kind: SampleKind,
    /// Number of spheres (random packings).
    pub count: Option<usize>,
    /// Mean radius (m) of the truncated normal radius distribution, or the lattice radius.
    pub radius_mean: Option<f64>,
    /// Standard deviation of the radius (m); 0 or absent: monodisperse.
    pub radius_sd: Option<f64>,
    /// Smallest radius (m) the truncated normal may give.
    pub radius_min: Option<f64>,
    /// Largest radius (m) the truncated normal may give.
    pub radius_max: Option<f64>,
    /// Box edge lengths [x, y, z] (m).
    #[serde(rename = "box")]
    pub box_size: Option<[f64; 3]>,
    /// Target solid fraction of the random packing (geometric packing, no overlaps).
    pub solid_fraction: Option<f64>,
    /// Confining pressure (Pa): after the geometric packing, servo-controlled walls compress
    /// the sample until every wall carries this stress.
    pub pressure: Option<f64>,
    /// Friction coefficient while compacting to `pressure` (default: material.friction).
    pub compaction_friction: Option<f64>,
    /// Lattice layers [nx, ny, nz] (simple_cubic, hcp).
    pub layers: Option<[usize; 3]>,
    /// Packing file (text, lammps_data), relative to the scene file.
    pub file: Option<String>,
    /// Orientation of the grains' principal directions: "random" (uniform; the default for
    /// random packings) or "aligned" with the box axes (the default for the other kinds).
    pub orientations: Option<Orientations>,
    /// Grain shape of random packings: "sphere" (default), "poly_ellipsoid" or "ellipsoid".
    pub shape: Option<GrainShape>,
    /// Ellipsoid assembly file (CSV, relative to the scene file) whose grains' semi-axes
    /// `shape = "ellipsoid"` draws from.
    pub grain_file: Option<String>,
    /// How a random sample reaches `solid_fraction`: "geometric" (default for spheres and
    /// poly-ellipsoids) or "compaction" (default for ellipsoids).
    pub packing: Option<Packing>,
    /// Poly-ellipsoids of random packings: each semi-axis is drawn uniformly in
    /// [r / aspect_ratio_max, r] for a packed sphere of radius r; in [1, 4], default 2.
    pub aspect_ratio_max: Option<f64>,
    /// The grain of `kind = "single"`: semi-axes [a+, a-, b+, b-, c+, c-] (m) along the
    /// grain's +x, -x, +y, -y, +z, -z.
    pub semi_axes: Option<[f64; 6]>,
}

/// `[loading]` as written. Which keys apply depends on `kind`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadingSpec {
    pub kind: LoadingKind,
    /// Axial engineering strain rate (1/s), > 0: the driven wall moves at rate × initial height.
    pub strain_rate: Option<f64>,
    /// Axial strain at which the run ends, in (0, 1).
    pub end_strain: Option<f64>,
    /// Duration of the run (s) for `kind = "none"`.
    pub end_time: Option<f64>,
    /// Speed (m/s) of the top platen, > 0.
    pub speed: Option<f64>,
    /// Platen travel (m) at which a `platens` run ends, > 0.
    pub end_displacement: Option<f64>,
}

/// The granular model's tables of a scene as written: the model's `Section`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GranularScene {
    pub material: Material,
    pub sample: SampleSpec,
    pub loading: LoadingSpec,
    #[serde(default)]
    pub walls: WallSpec,
    #[serde(default)]
    pub neighbor: NeighborSpec,
    /// Criteria, strength statistics, break planes and cohesion of breaking grains (used by
    /// the `fracture`, `weibull` and `cohesion` effects).
    #[serde(default)]
    pub fracture: FractureSpec,
}

/// Range checks of a granular scene, and the scene in its typed form: each failure names the
/// key, its value and the range.
pub fn validate(s: &Scene, g: &GranularScene) -> Result<typed::GranularScene> {
    let m = &g.material;
    check(s, "material.young", m.young, Range::POSITIVE, "Pa")?;
    let nu = require(
        s,
        "material.poisson",
        m.poisson,
        "for model.kind = \"granular\"",
    )?;
    check(s, "material.poisson", nu, Range::open(-1.0, 0.5), "")?;
    check(s, "material.density", m.density, Range::POSITIVE, "kg/m³")?;
    check(s, "material.friction", m.friction, Range::NON_NEGATIVE, "")?;
    check(
        s,
        "material.restitution",
        m.restitution,
        Range::open_closed(0.0, 1.0),
        "",
    )?;
    let material = typed::Material {
        young: m.young,
        poisson: nu,
        density: m.density,
        friction: m.friction,
        restitution: m.restitution,
    };
    let sample = validate_sample(s, &g.sample, material.friction)?;
    validate_effects(s)?;
    validate_fracture(s, &g.fracture)?;
    let l = &g.loading;
    let loading = match l.kind {
        LoadingKind::Oedometer => {
            let why = "for loading.kind = \"oedometer\"";
            let rate = require(s, "loading.strain_rate", l.strain_rate, why)?;
            check(s, "loading.strain_rate", rate, Range::POSITIVE, "1/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
            typed::LoadingSpec::Oedometer {
                strain_rate: rate,
                end_strain: end,
            }
        }
        LoadingKind::Platens => {
            let why = "for loading.kind = \"platens\"";
            let speed = require(s, "loading.speed", l.speed, why)?;
            check(s, "loading.speed", speed, Range::POSITIVE, "m/s")?;
            let travel = require(s, "loading.end_displacement", l.end_displacement, why)?;
            check(s, "loading.end_displacement", travel, Range::POSITIVE, "m")?;
            typed::LoadingSpec::Platens {
                speed,
                end_displacement: travel,
            }
        }
        LoadingKind::None => {
            let end = require(
                s,
                "loading.end_time",
                l.end_time,
                "for loading.kind = \"none\"",
            )?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
            typed::LoadingSpec::None { end_time: end }
        }
    };
    if let Some(mu) = g.walls.friction {
        check(s, "walls.friction", mu, Range::NON_NEGATIVE, "")?;
    }
    super::sleeve::validate_sleeve(s, &g.walls, &sample)?;
    if let Some(skin) = g.neighbor.skin {
        check(s, "neighbor.skin", skin, Range::POSITIVE, "m")?;
    }
    if let Some(strains) = &s.output.report_strains {
        for &e in strains {
            check(s, "output.report_strains", e, Range::open(0.0, 1.0), "")?;
        }
    }
    Ok(typed::GranularScene {
        material,
        sample,
        loading,
        walls: g.walls.clone(),
        neighbor: g.neighbor.clone(),
        fracture: g.fracture.clone(),
    })
}

/// The `[fracture]` keys, and what the fracture effects need.
fn validate_fracture(s: &Scene, f: &FractureSpec) -> Result<()> {
    check(s, "fracture.mi", f.mi, Range::POSITIVE, "")?;
    check(s, "fracture.sigma_c", f.sigma_c, Range::POSITIVE, "Pa")?;
    check(
        s,
        "fracture.weibull_modulus",
        f.weibull_modulus,
        Range::POSITIVE,
        "",
    )?;
    check(
        s,
        "fracture.toughness",
        f.toughness,
        Range::POSITIVE,
        "Pa m^0.5",
    )?;
    check(
        s,
        "fracture.critical_contacts",
        f.critical_contacts as f64,
        Range::closed(
            crate::fracture::CRITICAL_CONTACTS.0 as f64,
            crate::fracture::CRITICAL_CONTACTS.1 as f64,
        ),
        "",
    )?;
    check(
        s,
        "fracture.springs",
        f.springs as f64,
        Range::closed(
            crate::fracture::SPRINGS.0 as f64,
            crate::fracture::SPRINGS.1 as f64,
        ),
        "",
    )?;
    if let Some(v) = f.reference_strength {
        check(s, "fracture.reference_strength", v, Range::POSITIVE, "Pa")?;
    }
    if let Some(v) = f.reference_radius {
        check(s, "fracture.reference_radius", v, Range::POSITIVE, "m")?;
    }
    if let Some(v) = f.size_exponent {
        check(s, "fracture.size_exponent", v, Range::closed(0.0, 6.0), "")?;
    }
    if let Some(v) = f.comminution_limit {
        check(s, "fracture.comminution_limit", v, Range::POSITIVE, "m")?;
    }
    let derived = s.has_effect(EffectKind::Weibull) && f.weibull_on == WeibullOn::Particle;
    if s.has_effect(EffectKind::Fracture) && !derived {
        require(
            s,
            "fracture.reference_strength",
            f.reference_strength,
            "with the \"fracture\" effect (the contact tensile strength; derived from sigma_c only with weibull_on = \"particle\")",
        )?;
    }
    if s.has_effect(EffectKind::Weibull) {
        require(
            s,
            "fracture.reference_radius",
            f.reference_radius,
            "with the \"weibull\" effect",
        )?;
    }
    Ok(())
}

/// `[sample]`, checked, in its typed form; `friction` is the material's (the default of
/// `compaction_friction`).
fn validate_sample(s: &Scene, p: &SampleSpec, friction: f64) -> Result<typed::SampleSpec> {
    let kind = p.kind.as_str();
    let why = format!("for sample.kind = \"{kind}\"");
    let orientations = |default| p.orientations.unwrap_or(default);
    let grains = match p.kind {
        SampleKind::Random if p.shape == Some(GrainShape::Ellipsoid) => {
            let (grain_file, box_size, amount) = validate_ellipsoid_sample(s, p)?;
            Grains::Random(RandomSample {
                shape: RandomShape::Ellipsoids {
                    grain_file,
                    packing: packing(p),
                },
                amount,
                box_size,
                orientations: orientations(Orientations::Random),
            })
        }
        SampleKind::Random => {
            let mean = require(s, "sample.radius_mean", p.radius_mean, &why)?;
            check(s, "sample.radius_mean", mean, Range::POSITIVE, "m")?;
            let sd = p.radius_sd.unwrap_or(0.0);
            check(s, "sample.radius_sd", sd, Range::NON_NEGATIVE, "m")?;
            if let Some(rmin) = p.radius_min {
                check(
                    s,
                    "sample.radius_min",
                    rmin,
                    Range::open_closed(0.0, mean),
                    "m",
                )?;
            }
            if let Some(rmax) = p.radius_max {
                check(
                    s,
                    "sample.radius_max",
                    rmax,
                    Range::closed(mean, f64::INFINITY),
                    "m",
                )?;
            }
            let bx = require(s, "sample.box", p.box_size, &why)?;
            check_box(s, bx)?;
            if let Some(n) = p.count {
                if n == 0 {
                    return Err(
                        s.key_error("sample.count", "= 0 is outside the allowed range [1, ∞)")
                    );
                }
                check_bodies(s, "sample.count", n as f64, "spheres")?;
            }
            if let Some(phi) = p.solid_fraction {
                check_solid_fraction(s, p, phi)?;
                if p.count.is_none() {
                    let grain = 4.0 / 3.0 * std::f64::consts::PI * mean.powi(3);
                    let n = phi * bx[0] * bx[1] * bx[2] / grain;
                    check_bodies(s, "sample.box", n, "spheres at that solid fraction")?;
                }
            }
            let Some(amount) = amount(p) else {
                return Err(s.key_error(
                    "sample.count",
                    format!("or sample.solid_fraction is required {why}"),
                ));
            };
            if let Some(pr) = p.pressure {
                check(s, "sample.pressure", pr, Range::POSITIVE, "Pa")?;
            }
            if let Some(mu) = p.compaction_friction {
                check(s, "sample.compaction_friction", mu, Range::NON_NEGATIVE, "")?;
            }
            let radii = Radii {
                mean,
                sd,
                min: p.radius_min.unwrap_or((mean - 3.0 * sd).max(0.01 * mean)),
                max: p.radius_max.unwrap_or(mean + 3.0 * sd),
            };
            let packing = packing(p);
            let shape = if p.shape == Some(GrainShape::PolyEllipsoid) {
                RandomShape::PolyEllipsoids {
                    radii,
                    aspect_ratio_max: p.aspect_ratio_max.unwrap_or(2.0),
                    packing,
                }
            } else {
                RandomShape::Spheres { radii, packing }
            };
            Grains::Random(RandomSample {
                shape,
                amount,
                box_size: bx,
                orientations: orientations(Orientations::Random),
            })
        }
        SampleKind::SimpleCubic | SampleKind::Hcp => {
            let r = require(s, "sample.radius_mean", p.radius_mean, &why)?;
            check(s, "sample.radius_mean", r, Range::POSITIVE, "m")?;
            let layers = require(s, "sample.layers", p.layers, &why)?;
            if layers.contains(&0) {
                return Err(s.key_error(
                    "sample.layers",
                    "has a zero entry; each of [nx, ny, nz] must be in [1, ∞)",
                ));
            }
            let n = layers.iter().map(|&l| l as f64).product::<f64>();
            check_bodies(s, "sample.layers", n, "spheres")?;
            Grains::Lattice(LatticeSample {
                hcp: p.kind == SampleKind::Hcp,
                radius: r,
                layers,
                orientations: orientations(Orientations::Aligned),
            })
        }
        SampleKind::Text
        | SampleKind::LammpsData
        | SampleKind::YadeText
        | SampleKind::EllipsoidAssembly => {
            let Some(file) = p.file.clone() else {
                return Err(s.key_error("sample.file", format!("is required {why}")));
            };
            if p.kind == SampleKind::EllipsoidAssembly {
                Grains::EllipsoidAssembly { file }
            } else {
                Grains::File(FileSample {
                    format: p.kind,
                    file,
                    box_size: p.box_size,
                    orientations: orientations(Orientations::Aligned),
                })
            }
        }
        SampleKind::Single => {
            let semi = require(s, "sample.semi_axes", p.semi_axes, &why)?;
            for v in semi {
                if !Range::POSITIVE.contains(v) {
                    return Err(s.key_error(
                        "sample.semi_axes",
                        format!("has {v}, outside the allowed range (0, ∞) m"),
                    ));
                }
            }
            let bx = require(s, "sample.box", p.box_size, &why)?;
            let width = 2.0 * semi.iter().copied().fold(0.0, f64::max);
            for (axis, v) in ["x", "y"].iter().zip(bx) {
                if v <= width {
                    return Err(s.key_error(
                        "sample.box",
                        format!(
                            "has {axis} edge {v} m, which must exceed the grain's largest extent {width} m"
                        ),
                    ));
                }
            }
            Grains::Single(SingleGrain {
                semi_axes: semi,
                box_size: bx,
                orientations: orientations(Orientations::Aligned),
            })
        }
    };
    if let Some(a) = p.aspect_ratio_max {
        check(s, "sample.aspect_ratio_max", a, Range::closed(1.0, 4.0), "")?;
    }
    let shape = match p.shape {
        Some(GrainShape::PolyEllipsoid) => Some("poly_ellipsoid"),
        Some(GrainShape::Ellipsoid) => Some("ellipsoid"),
        _ => None,
    };
    if let (Some(shape), true) = (shape, p.kind != SampleKind::Random) {
        return Err(s.key_error(
            "sample.shape",
            format!("= \"{shape}\" applies to sample.kind = \"random\" only, not \"{kind}\""),
        ));
    }
    if p.grain_file.is_some() && p.shape != Some(GrainShape::Ellipsoid) {
        return Err(s.key_error(
            "sample.grain_file",
            "applies to sample.shape = \"ellipsoid\" only (the grains' semi-axes are drawn from it)",
        ));
    }
    if let (Some(packing), true) = (p.packing, p.kind != SampleKind::Random) {
        return Err(s.key_error(
            "sample.packing",
            format!(
                "= \"{}\" applies to sample.kind = \"random\" only, not \"{kind}\"",
                packing.as_str()
            ),
        ));
    }
    if p.shape == Some(GrainShape::Ellipsoid) && p.packing == Some(Packing::Geometric) {
        return Err(s.key_error(
            "sample.packing",
            "= \"geometric\" packs spheres only; ellipsoid grains reach their solid fraction by \"compaction\" or \"jammed\"",
        ));
    }
    // Keys that do not apply to the kind are refused, as everywhere else: a box, an amount or a
    // compaction friction the sample never reads used to be ignored without a word.
    let applies: &[(&str, bool, &str)] = &[
        (
            "sample.count",
            p.count.is_some() && p.kind != SampleKind::Random,
            "applies to sample.kind = \"random\" only",
        ),
        (
            "sample.solid_fraction",
            p.solid_fraction.is_some() && p.kind != SampleKind::Random,
            "applies to sample.kind = \"random\" only",
        ),
        (
            "sample.box",
            p.box_size.is_some()
                && matches!(
                    p.kind,
                    SampleKind::EllipsoidAssembly | SampleKind::SimpleCubic | SampleKind::Hcp
                ),
            "applies to sample.kind = \"random\", \"single\" and the sphere files only (an \
             assembly's box is the one its grains span, a lattice's the one its layers fill)",
        ),
        (
            "sample.compaction_friction",
            p.compaction_friction.is_some() && p.pressure.is_none(),
            "applies with sample.pressure only (the friction while compacting to that pressure; \
             packing = \"compaction\" compacts without friction)",
        ),
    ];
    for &(key, given, why) in applies {
        if given {
            let what = if key == "sample.compaction_friction" {
                "is given without sample.pressure".to_string()
            } else {
                format!("is given for sample.kind = \"{kind}\"")
            };
            return Err(s.key_error(key, format!("{what}; it {why}, so remove it")));
        }
    }
    // `pressure` compacts every kind of sample (random ones are checked above, in their order;
    // the others here: a negative pressure used to reach the compaction unchecked).
    if let Some(pr) = p.pressure {
        check(s, "sample.pressure", pr, Range::POSITIVE, "Pa")?;
    }
    if let Some(mu) = p.compaction_friction {
        check(s, "sample.compaction_friction", mu, Range::NON_NEGATIVE, "")?;
    }
    let compaction = p.pressure.map(|pressure| PressureCompaction {
        pressure,
        friction: p.compaction_friction.unwrap_or(friction),
    });
    Ok(typed::SampleSpec { grains, compaction })
}

/// `sample.box` of a random packing: each edge positive.
fn check_box(s: &Scene, bx: [f64; 3]) -> Result<()> {
    for (axis, v) in ["x", "y", "z"].iter().zip(bx) {
        if !Range::POSITIVE.contains(v) {
            return Err(s.key_error(
                "sample.box",
                format!("has {axis} edge {v}, outside the allowed range (0, ∞) m"),
            ));
        }
    }
    Ok(())
}

/// `count`, `solid_fraction` or both; none when neither is given.
fn amount(p: &SampleSpec) -> Option<Amount> {
    match (p.count, p.solid_fraction) {
        (Some(count), Some(solid_fraction)) => Some(Amount::Both {
            count,
            solid_fraction,
        }),
        (Some(n), None) => Some(Amount::Count(n)),
        (None, Some(phi)) => Some(Amount::SolidFraction(phi)),
        (None, None) => None,
    }
}

/// The method a random sample reaches its solid fraction by.
fn packing(p: &SampleSpec) -> Packing {
    p.packing
        .unwrap_or(if p.shape == Some(GrainShape::Ellipsoid) {
            Packing::Compaction
        } else {
            Packing::Geometric
        })
}

/// The solid fractions each packing method may be asked for: growth without overlap stops
/// near random close packing (0.65 is above what it reaches in any box); frictionless
/// compaction reports where the grains jam, so only fractions a packing cannot hold at all
/// (0.9) are refused here.
fn check_solid_fraction(s: &Scene, p: &SampleSpec, phi: f64) -> Result<()> {
    let top = match packing(p) {
        Packing::Geometric => 0.65,
        Packing::Compaction | Packing::Jammed => 0.9,
    };
    check(
        s,
        "sample.solid_fraction",
        phi,
        Range::open_closed(0.0, top),
        &format!("for sample.packing = \"{}\"", packing(p).as_str()),
    )
}

/// A random sample of ellipsoid grains: sizes come from `grain_file`, so the radius keys do
/// not apply. Gives the grain file, the box and the amount.
fn validate_ellipsoid_sample(s: &Scene, p: &SampleSpec) -> Result<(String, [f64; 3], Amount)> {
    let why = "for sample.shape = \"ellipsoid\"";
    for (key, v) in [
        ("sample.radius_mean", p.radius_mean),
        ("sample.radius_sd", p.radius_sd),
        ("sample.radius_min", p.radius_min),
        ("sample.radius_max", p.radius_max),
        ("sample.aspect_ratio_max", p.aspect_ratio_max),
    ] {
        if v.is_some() {
            return Err(s.key_error(
                key,
                "does not apply with sample.shape = \"ellipsoid\": the grains' semi-axes are drawn from sample.grain_file",
            ));
        }
    }
    let grain_file = require(s, "sample.grain_file", p.grain_file.as_ref(), why)?.clone();
    let bx = require(s, "sample.box", p.box_size, why)?;
    check_box(s, bx)?;
    let amount = match amount(p) {
        Some(Amount::Count(0) | Amount::Both { count: 0, .. }) => {
            return Err(s.key_error("sample.count", "= 0 is outside the allowed range [1, ∞)"));
        }
        None => {
            return Err(s.key_error(
                "sample.count",
                format!("or sample.solid_fraction is required {why}"),
            ));
        }
        Some(amount) => amount,
    };
    if let Some(n) = amount.count() {
        check_bodies(s, "sample.count", n as f64, "grains")?;
    }
    if let Some(phi) = p.solid_fraction {
        check_solid_fraction(s, p, phi)?;
    }
    if let Some(pr) = p.pressure {
        check(s, "sample.pressure", pr, Range::POSITIVE, "Pa")?;
    }
    if let Some(mu) = p.compaction_friction {
        check(s, "sample.compaction_friction", mu, Range::NON_NEGATIVE, "")?;
    }
    Ok((grain_file, bx, amount))
}

/// Effects that act on something another effect builds.
fn validate_effects(s: &Scene) -> Result<()> {
    for (effect, needs) in [
        (EffectKind::Cohesion, EffectKind::Fracture),
        (EffectKind::Weibull, EffectKind::Fracture),
    ] {
        if s.has_effect(effect) && !s.has_effect(needs) {
            return Err(s.key_error(
                "effects",
                format!(
                    "lists \"{}\" without \"{}\"; it acts on breaking grains, so add \"{}\"",
                    effect.as_str(),
                    needs.as_str(),
                    needs.as_str()
                ),
            ));
        }
    }
    for needs_contact in [
        EffectKind::Damping,
        EffectKind::Friction,
        EffectKind::Fracture,
    ] {
        s.requires_contact(needs_contact)?;
    }
    Ok(())
}
