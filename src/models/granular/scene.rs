//! The granular model's own scene tables (`material`, `sample`, `loading`, `walls`,
//! `neighbor`, `fracture`), typed and checked. Keys of other models are refused by name.

use serde::Deserialize;

use crate::error::Result;
use crate::fracture::FractureSpec;
use crate::scene::validate::{Range, check, check_bodies, require};
use crate::scene::{EffectKind, NeighborSpec, Scene};

/// Elastic and contact properties of the grains (and of the walls, which share them).
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

impl Material {
    /// ν, checked present at load.
    pub fn poisson(&self) -> f64 {
        self.poisson.unwrap_or(f64::NAN)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SampleKind {
    /// Random polydisperse packing in a box.
    Random,
    /// Simple cubic lattice of equal spheres.
    SimpleCubic,
    /// Hexagonal close packed lattice of equal spheres.
    Hcp,
    /// A text packing: `x y z r` per line (m).
    Text,
    /// A LAMMPS data file, atom_style sphere.
    LammpsData,
    /// A YADE `ymport.text` / `export.textExt(..., 'x_y_z_r')` file: `x y z r` per line.
    YadeText,
    /// One grain (`semi_axes`) resting on the bottom of a box whose top touches it.
    Single,
    /// An ellipsoid assembly file (CSV: semi-axes, centre and axis angles a grain), imported
    /// as it is, in the box its grains span.
    EllipsoidAssembly,
}

impl SampleKind {
    pub fn as_str(self) -> &'static str {
        match self {
            SampleKind::Random => "random",
            SampleKind::SimpleCubic => "simple_cubic",
            SampleKind::Hcp => "hcp",
            SampleKind::Text => "text",
            SampleKind::LammpsData => "lammps_data",
            SampleKind::YadeText => "yade_text",
            SampleKind::Single => "single",
            SampleKind::EllipsoidAssembly => "ellipsoid_assembly",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Orientations {
    Random,
    Aligned,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GrainShape {
    Sphere,
    PolyEllipsoid,
    /// Ellipsoids (poly-ellipsoids with equal halves) whose semi-axes are drawn from the
    /// grains of `grain_file`.
    Ellipsoid,
}

/// How a random sample reaches its solid fraction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Packing {
    /// Growth and collective rearrangement of spheres, no overlap (spheres and
    /// poly-ellipsoids inscribed in them; jams near 0.6 in small boxes).
    Geometric,
    /// Grains placed at a low solid fraction, then compressed by the box's faces without
    /// friction until they fill the fraction; friction is the material's again from the
    /// first loading step (the default, and the only method, for ellipsoid grains).
    Compaction,
}

impl Packing {
    pub fn as_str(self) -> &'static str {
        match self {
            Packing::Geometric => "geometric",
            Packing::Compaction => "compaction",
        }
    }
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

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadingKind {
    /// Walls stay where the sample put them; the run lasts `end_time`.
    None,
    /// Oedometric compression: the top (+z) wall moves down at a constant strain rate, the
    /// other five walls are fixed.
    Oedometer,
    /// Flat platens: the top (+z) wall moves down at `speed` until it has travelled
    /// `end_displacement`; the bottom is fixed (single-grain crushing).
    Platens,
}

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

/// The walls of the container (same elastic material as the grains).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// Coulomb friction between grains and walls (default: material.friction); 0 models
    /// lubricated walls.
    pub friction: Option<f64>,
}

/// The granular model's tables of a scene.
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

/// The effects of the granular model.
pub const EFFECTS: [EffectKind; 7] = [
    EffectKind::Contact,
    EffectKind::Damping,
    EffectKind::Friction,
    EffectKind::Gravity,
    EffectKind::Fracture,
    EffectKind::Cohesion,
    EffectKind::Weibull,
];

/// Range checks of a granular scene: each failure names the key, its value and the range.
pub fn validate(s: &Scene, g: &GranularScene) -> Result<()> {
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
    validate_sample(s, &g.sample)?;
    validate_effects(s)?;
    validate_fracture(s, &g.fracture)?;
    let l = &g.loading;
    match l.kind {
        LoadingKind::Oedometer => {
            let why = "for loading.kind = \"oedometer\"";
            let rate = require(s, "loading.strain_rate", l.strain_rate, why)?;
            check(s, "loading.strain_rate", rate, Range::POSITIVE, "1/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
        }
        LoadingKind::Platens => {
            let why = "for loading.kind = \"platens\"";
            let speed = require(s, "loading.speed", l.speed, why)?;
            check(s, "loading.speed", speed, Range::POSITIVE, "m/s")?;
            let travel = require(s, "loading.end_displacement", l.end_displacement, why)?;
            check(s, "loading.end_displacement", travel, Range::POSITIVE, "m")?;
        }
        LoadingKind::None => {
            let end = require(
                s,
                "loading.end_time",
                l.end_time,
                "for loading.kind = \"none\"",
            )?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
        }
    }
    if let Some(mu) = g.walls.friction {
        check(s, "walls.friction", mu, Range::NON_NEGATIVE, "")?;
    }
    if let Some(skin) = g.neighbor.skin {
        check(s, "neighbor.skin", skin, Range::POSITIVE, "m")?;
    }
    if let Some(strains) = &s.output.report_strains {
        for &e in strains {
            check(s, "output.report_strains", e, Range::open(0.0, 1.0), "")?;
        }
    }
    Ok(())
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
    if s.has_effect(EffectKind::Fracture) {
        require(
            s,
            "fracture.reference_strength",
            f.reference_strength,
            "with the \"fracture\" effect (the contact tensile strength)",
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

fn validate_sample(s: &Scene, p: &SampleSpec) -> Result<()> {
    let kind = p.kind.as_str();
    let why = format!("for sample.kind = \"{kind}\"");
    match p.kind {
        SampleKind::Random if p.shape == Some(GrainShape::Ellipsoid) => {
            validate_ellipsoid_sample(s, p)?;
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
            for (axis, v) in ["x", "y", "z"].iter().zip(bx) {
                if !Range::POSITIVE.contains(v) {
                    return Err(s.key_error(
                        "sample.box",
                        format!("has {axis} edge {v}, outside the allowed range (0, ∞) m"),
                    ));
                }
            }
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
            if p.count.is_none() && p.solid_fraction.is_none() {
                return Err(s.key_error(
                    "sample.count",
                    format!("or sample.solid_fraction is required {why}"),
                ));
            }
            if let Some(pr) = p.pressure {
                check(s, "sample.pressure", pr, Range::POSITIVE, "Pa")?;
            }
            if let Some(mu) = p.compaction_friction {
                check(s, "sample.compaction_friction", mu, Range::NON_NEGATIVE, "")?;
            }
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
        }
        SampleKind::Text
        | SampleKind::LammpsData
        | SampleKind::YadeText
        | SampleKind::EllipsoidAssembly => {
            if p.file.is_none() {
                return Err(s.key_error("sample.file", format!("is required {why}")));
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
        }
    }
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
            "= \"geometric\" packs spheres only; ellipsoid grains reach their solid fraction by \"compaction\"",
        ));
    }
    Ok(())
}

/// The method a random sample reaches its solid fraction by.
pub fn packing(p: &SampleSpec) -> Packing {
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
        Packing::Compaction => 0.9,
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
/// not apply.
fn validate_ellipsoid_sample(s: &Scene, p: &SampleSpec) -> Result<()> {
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
    require(s, "sample.grain_file", p.grain_file.as_ref(), why)?;
    let bx = require(s, "sample.box", p.box_size, why)?;
    for (axis, v) in ["x", "y", "z"].iter().zip(bx) {
        if !Range::POSITIVE.contains(v) {
            return Err(s.key_error(
                "sample.box",
                format!("has {axis} edge {v}, outside the allowed range (0, ∞) m"),
            ));
        }
    }
    match (p.count, p.solid_fraction) {
        (Some(0), _) => {
            return Err(s.key_error("sample.count", "= 0 is outside the allowed range [1, ∞)"));
        }
        (Some(n), _) => check_bodies(s, "sample.count", n as f64, "grains")?,
        (None, None) => {
            return Err(s.key_error(
                "sample.count",
                format!("or sample.solid_fraction is required {why}"),
            ));
        }
        _ => {}
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
    Ok(())
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
