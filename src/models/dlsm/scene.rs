//! The dlsm model's own scene tables (`material`, `sample`, `loading`), typed and checked,
//! and which samples, loadings, effects and integrators go together.

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::scene::validate::{Range, check, check_bodies, require};
use crate::scene::{EffectKind, IntegratorKind, Scene};

/// The elastic solid and its strength.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E (Pa), > 0.
    pub young: f64,
    /// Poisson's ratio ν, in (-1, 0.5).
    pub poisson: f64,
    /// Density ρ (kg/m³), > 0.
    pub density: f64,
    /// Coulomb friction coefficient μ of broken contacts and of the ground, ≥ 0.
    #[serde(default)]
    pub friction: f64,
    /// Tensile strength σf (Pa) of a cohesive contact (Eq. 36), for the `fracture` effect.
    pub tensile_strength: Option<f64>,
    /// Normal stiffness (N/m) of element–ground contacts (`contact` effect).
    pub contact_stiffness: Option<f64>,
    /// The elements' strain measure: "green_pushed" (the default), "green_rotated" or
    /// "linear" (Eq. 15 as printed); they differ at second order in the strain.
    pub strain_measure: Option<crate::bond::dlsm::StrainMeasure>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SampleKind {
    /// Voronoi cells filling a box.
    VoronoiBox,
    /// Voronoi cells filling a cylinder along x.
    VoronoiCylinder,
    /// Voronoi cells filling a disc in the x–y plane.
    VoronoiDisc,
    /// Voronoi cells filling a ball.
    VoronoiBall,
}

impl SampleKind {
    pub fn as_str(self) -> &'static str {
        match self {
            SampleKind::VoronoiBox => "voronoi_box",
            SampleKind::VoronoiCylinder => "voronoi_cylinder",
            SampleKind::VoronoiDisc => "voronoi_disc",
            SampleKind::VoronoiBall => "voronoi_ball",
        }
    }
}

/// Where Voronoi seeds come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SampleMethod {
    /// One seed per cell of a regular grid, moved by a uniform noise (Section 7.1).
    NoisyGrid,
    /// Centres of a sphere packing with dispersed radii (Section 7.2).
    Packing,
    /// A regular cubic grid (the noisy grid with d = 0).
    Grid,
}

impl SampleMethod {
    pub fn as_str(self) -> &'static str {
        match self {
            SampleMethod::NoisyGrid => "noisy_grid",
            SampleMethod::Packing => "packing",
            SampleMethod::Grid => "grid",
        }
    }
}

/// The Voronoi sample. Which keys apply depends on `kind`; see docs/scenes.md.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleSpec {
    pub kind: SampleKind,
    /// How Voronoi seeds are placed.
    pub method: Option<SampleMethod>,
    /// Noise range d of the noisy grid, in [0, 1] (Section 7.1).
    pub noise: Option<f64>,
    /// About how many Voronoi elements to make.
    pub elements: Option<usize>,
    /// Edge of a cubic box, or length of a cylinder (m).
    pub length: Option<f64>,
    /// Box edge lengths [x, y, z] (m).
    #[serde(rename = "box")]
    pub box_size: Option<[f64; 3]>,
    /// Radius of a cylinder or ball (m).
    pub radius: Option<f64>,
    /// Diameter (m) and thickness (m) of a disc.
    pub diameter: Option<f64>,
    pub thickness: Option<f64>,
    /// Relative half-width δ of the uniform radius distribution of the packing method.
    pub radius_dispersion: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadingKind {
    /// Nothing prescribed; the run lasts `end_time`.
    None,
    /// The elements on the x− and x+ faces of a box move apart along x (Section 8.2.1).
    Tension,
    /// A cylinder released from a static tension or torsion field, x− face clamped
    /// (Section 8.2.2).
    FreeVibration,
    /// A disc squeezed across its vertical (y) diameter (Section 8.2.4).
    Brazilian,
    /// A body thrown onto an inclined ground plane (Section 8.1).
    Drop,
}

impl LoadingKind {
    pub fn as_str(self) -> &'static str {
        match self {
            LoadingKind::None => "none",
            LoadingKind::Tension => "tension",
            LoadingKind::FreeVibration => "free_vibration",
            LoadingKind::Brazilian => "brazilian",
            LoadingKind::Drop => "drop",
        }
    }
}

/// The static field a free vibration starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VibrationMode {
    /// u = A x.
    Tension,
    /// A twist of α rad/m about the x axis.
    Torsion,
}

/// How the driven elements of a tension test hold the x− and x+ faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Grip {
    /// Driven along x, rotations held, y and z free: the faces slide (uniaxial stress).
    #[default]
    Sliding,
    /// Driven along x with y, z and the rotations held: the faces are bonded to the grips.
    Clamped,
}

impl Grip {
    pub fn as_str(self) -> &'static str {
        match self {
            Grip::Sliding => "sliding",
            Grip::Clamped => "clamped",
        }
    }
}

/// How a Brazilian disc is loaded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadBy {
    /// Prescribed speeds on the elements of the loading arcs (the paper's Fig. 16a).
    Elements,
    /// Two rigid flat platens pressed onto the disc.
    FlatPlatens,
    /// Two rigid curved jaws of radius 1.5 R (the ISRM's) pressed onto the disc.
    CurvedJaws,
    /// A uniform radial pressure over the loading arcs, set by a servo on their closure.
    ArcPressure,
}

impl LoadBy {
    /// Rigid platens or jaws, which find the elements they touch (no loading arc of their own).
    pub fn presses(self) -> bool {
        matches!(self, LoadBy::FlatPlatens | LoadBy::CurvedJaws)
    }

    pub fn as_str(self) -> &'static str {
        match self {
            LoadBy::Elements => "elements",
            LoadBy::FlatPlatens => "flat_platens",
            LoadBy::CurvedJaws => "curved_jaws",
            LoadBy::ArcPressure => "arc_pressure",
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadingSpec {
    pub kind: LoadingKind,
    /// Axial strain rate (1/s) of the tension test, > 0.
    pub strain_rate: Option<f64>,
    /// Strain at which the tension or Brazilian test ends, in (0, 1).
    pub end_strain: Option<f64>,
    /// Duration (s) of a free vibration, a drop or `kind = "none"`.
    pub end_time: Option<f64>,
    /// Speed (m/s) of each loaded side of a Brazilian disc, > 0.
    pub speed: Option<f64>,
    /// Time (s) over which the prescribed speeds rise smoothly from zero.
    pub ramp_time: Option<f64>,
    /// How the tension test's driven elements hold the x faces: "sliding" (y, z free, the
    /// default) or "clamped" (y, z held).
    pub grip: Option<Grip>,
    /// Loading arc 2α (degrees) of the Brazilian test; 0 loads the top and bottom elements.
    pub arc_degrees: Option<f64>,
    /// How a Brazilian disc is loaded: "elements" (prescribed speeds on the elements of the
    /// loading arcs, the default), "flat_platens" or "curved_jaws" (two rigid platens, or
    /// jaws of radius 1.5 R, touching the disc's elements through frictional contacts,
    /// driven at `speed`; the force is read on them) or "arc_pressure" (a uniform radial
    /// pressure over the loading arcs, set by a servo on their closure commanded at
    /// `speed`).
    pub load_by: Option<LoadBy>,
    /// Stiffness (N/m) of the servo of `load_by = "arc_pressure"`, > 0.
    pub servo_stiffness: Option<f64>,
    /// With `fracture`: the run ends once the load has fallen below this fraction of its
    /// peak (0: never early).
    pub stop_fraction: Option<f64>,
    /// The static field a free vibration starts from.
    pub mode: Option<VibrationMode>,
    /// Initial strain A of a free vibration in tension.
    pub initial_strain: Option<f64>,
    /// Initial twist α (rad/m) of a free vibration in torsion.
    pub twist: Option<f64>,
    /// Initial velocity (m/s) of a dropped body.
    pub initial_velocity: Option<[f64; 3]>,
    /// Inclination (degrees) of the ground plane, descending towards +x.
    pub ground_angle_degrees: Option<f64>,
    /// Gap (m) between the dropped body and the ground at the start.
    pub drop_height: Option<f64>,
}

/// The dlsm model's tables of a scene.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DlsmScene {
    pub material: Material,
    pub sample: SampleSpec,
    pub loading: LoadingSpec,
}

/// The effects of the dlsm model.
pub const EFFECTS: [EffectKind; 4] = [
    EffectKind::Fracture,
    EffectKind::Contact,
    EffectKind::Friction,
    EffectKind::Gravity,
];

/// Range checks of a dlsm scene, and what goes with what.
pub fn validate(s: &Scene, d: &DlsmScene) -> Result<()> {
    let m = &d.material;
    check(s, "material.young", m.young, Range::POSITIVE, "Pa")?;
    check(s, "material.poisson", m.poisson, Range::open(-1.0, 0.5), "")?;
    check(s, "material.density", m.density, Range::POSITIVE, "kg/m³")?;
    check(s, "material.friction", m.friction, Range::NON_NEGATIVE, "")?;
    if let Some(sf) = m.tensile_strength {
        check(s, "material.tensile_strength", sf, Range::POSITIVE, "Pa")?;
    }
    if let Some(k) = m.contact_stiffness {
        check(s, "material.contact_stiffness", k, Range::POSITIVE, "N/m")?;
    }
    validate_sample(s, &d.sample)?;
    validate_loading(s, &d.loading)?;
    let t = &s.time;
    match (t.integrator, t.phi) {
        (IntegratorKind::TchamwaWielgosz, Some(phi)) => {
            check(s, "time.phi", phi, Range::closed(0.5, 10.0), "")?;
        }
        (IntegratorKind::VelocityVerlet, Some(_)) => {
            return Err(s.key_error(
                "time.phi",
                "applies to time.integrator = \"tchamwa_wielgosz\" (velocity Verlet is φ = 0.5)",
            ));
        }
        _ => {}
    }
    let sample = d.sample.kind;
    let loading = d.loading.kind;
    let needs = match loading {
        LoadingKind::Tension => Some(SampleKind::VoronoiBox),
        LoadingKind::FreeVibration => Some(SampleKind::VoronoiCylinder),
        LoadingKind::Brazilian => Some(SampleKind::VoronoiDisc),
        LoadingKind::None | LoadingKind::Drop => None,
    };
    if let Some(k) = needs {
        if sample != k {
            return Err(s.key_error(
                "loading.kind",
                format!(
                    "= \"{}\" needs sample.kind = \"{}\", not \"{}\"",
                    loading.as_str(),
                    k.as_str(),
                    sample.as_str()
                ),
            ));
        }
    }
    if s.has_effect(EffectKind::Fracture) {
        require(
            s,
            "material.tensile_strength",
            m.tensile_strength,
            "for the \"fracture\" effect",
        )?;
    }
    s.requires_contact(EffectKind::Friction)?;
    if s.has_effect(EffectKind::Contact) {
        if loading != LoadingKind::Drop {
            return Err(s.key_error(
                "effects",
                "lists \"contact\", the element–ground contact, which needs the ground of loading.kind = \"drop\"",
            ));
        }
        require(
            s,
            "material.contact_stiffness",
            m.contact_stiffness,
            "for the \"contact\" effect of model.kind = \"dlsm\"",
        )?;
    }
    Ok(())
}

/// The keys of a Voronoi sample.
fn validate_sample(s: &Scene, p: &SampleSpec) -> Result<()> {
    let why = format!("for sample.kind = \"{}\"", p.kind.as_str());
    let n = require(s, "sample.elements", p.elements, &why)?;
    if n < 8 {
        return Err(s.key_error(
            "sample.elements",
            format!("= {n} is outside the allowed range [8, ∞)"),
        ));
    }
    check_bodies(s, "sample.elements", n as f64, "elements")?;
    // Each applies to its method only and is ignored by the others, so that one scene can
    // switch methods with --set.
    if let Some(d) = p.noise {
        check(s, "sample.noise", d, Range::closed(0.0, 1.0), "")?;
    }
    if let Some(delta) = p.radius_dispersion {
        check(
            s,
            "sample.radius_dispersion",
            delta,
            Range::closed(0.15, 0.9),
            "",
        )?;
    }
    let positive = |key: &str, v: Option<f64>| -> Result<f64> {
        let v = require(s, key, v, &why)?;
        check(s, key, v, Range::POSITIVE, "m")?;
        Ok(v)
    };
    match p.kind {
        SampleKind::VoronoiBox => match (p.box_size, p.length) {
            (Some(_), Some(_)) => {
                return Err(s.key_error(
                    "sample.length",
                    "and sample.box both give the box; keep one",
                ));
            }
            (Some(bx), None) => {
                for (axis, v) in ["x", "y", "z"].iter().zip(bx) {
                    if !Range::POSITIVE.contains(v) {
                        return Err(s.key_error(
                            "sample.box",
                            format!("has {axis} edge {v}, outside the allowed range (0, ∞) m"),
                        ));
                    }
                }
            }
            (None, l) => {
                positive("sample.length", l)?;
            }
        },
        SampleKind::VoronoiCylinder => {
            positive("sample.length", p.length)?;
            positive("sample.radius", p.radius)?;
        }
        SampleKind::VoronoiDisc => {
            positive("sample.diameter", p.diameter)?;
            positive("sample.thickness", p.thickness)?;
        }
        SampleKind::VoronoiBall => {
            positive("sample.radius", p.radius)?;
        }
    }
    Ok(())
}

/// The keys of the dlsm loadings.
fn validate_loading(s: &Scene, l: &LoadingSpec) -> Result<()> {
    let why = format!("for loading.kind = \"{}\"", l.kind.as_str());
    if let Some(t) = l.ramp_time {
        check(s, "loading.ramp_time", t, Range::NON_NEGATIVE, "s")?;
    }
    if let Some(f) = l.stop_fraction {
        check(s, "loading.stop_fraction", f, Range::closed(0.0, 0.99), "")?;
    }
    match l.kind {
        LoadingKind::Tension => {
            let rate = require(s, "loading.strain_rate", l.strain_rate, &why)?;
            check(s, "loading.strain_rate", rate, Range::POSITIVE, "1/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, &why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
        }
        _ if l.grip.is_some() => {
            return Err(s.key_error(
                "loading.grip",
                format!(
                    "applies to loading.kind = \"tension\", not \"{}\"",
                    l.kind.as_str()
                ),
            ));
        }
        LoadingKind::FreeVibration => {
            let mode = require(s, "loading.mode", l.mode, &why)?;
            match mode {
                VibrationMode::Tension => {
                    if let Some(a) = l.initial_strain {
                        check(
                            s,
                            "loading.initial_strain",
                            a,
                            Range::closed(-0.01, 0.01),
                            "",
                        )?;
                    }
                }
                VibrationMode::Torsion => {
                    if let Some(t) = l.twist {
                        check(s, "loading.twist", t, Range::closed(-1.0, 1.0), "rad/m")?;
                    }
                }
            }
            let end = require(s, "loading.end_time", l.end_time, &why)?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
        }
        LoadingKind::Brazilian => {
            let v = require(s, "loading.speed", l.speed, &why)?;
            check(s, "loading.speed", v, Range::POSITIVE, "m/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, &why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
            let arc = l.arc_degrees.unwrap_or(0.0);
            check(
                s,
                "loading.arc_degrees",
                arc,
                Range::closed(0.0, 90.0),
                "degrees",
            )?;
            let by = l.load_by.unwrap_or(LoadBy::Elements);
            match by {
                by if by.presses() && arc > 0.0 => {
                    return Err(s.key_error(
                        "loading.arc_degrees",
                        format!(
                            "= {arc} is outside the allowed range [0, 0] degrees with loading.load_by = \"{}\", whose contact makes its own arc: leave it out or 0",
                            by.as_str()
                        ),
                    ));
                }
                LoadBy::ArcPressure if arc <= 0.0 => {
                    return Err(s.key_error(
                        "loading.arc_degrees",
                        "is 0, and loading.load_by = \"arc_pressure\" spreads its pressure over the loading arc: give it in the allowed range (0, 90] degrees",
                    ));
                }
                _ => {}
            }
            match (l.servo_stiffness, by) {
                (Some(k), LoadBy::ArcPressure) => {
                    check(s, "loading.servo_stiffness", k, Range::POSITIVE, "N/m")?;
                }
                (Some(_), _) => {
                    return Err(s.key_error(
                        "loading.servo_stiffness",
                        format!(
                            "applies to loading.load_by = \"arc_pressure\", not \"{}\"",
                            by.as_str()
                        ),
                    ));
                }
                (None, _) => {}
            }
        }
        LoadingKind::Drop => {
            let end = require(s, "loading.end_time", l.end_time, &why)?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
            if let Some(a) = l.ground_angle_degrees {
                check(
                    s,
                    "loading.ground_angle_degrees",
                    a,
                    Range::closed(0.0, 60.0),
                    "degrees",
                )?;
            }
            if let Some(h) = l.drop_height {
                check(s, "loading.drop_height", h, Range::NON_NEGATIVE, "m")?;
            }
            if let Some(v) = l.initial_velocity {
                if v.iter().any(|c| !c.is_finite()) {
                    return Err(
                        s.key_error("loading.initial_velocity", "has a non-finite component")
                    );
                }
            }
        }
        LoadingKind::None => {
            let end = require(s, "loading.end_time", l.end_time, &why)?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
        }
    }
    Ok(())
}
