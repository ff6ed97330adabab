//! The dlsm model's own scene tables (`material`, `sample`, `loading`), typed and checked,
//! and which samples, loadings, effects and integrators go together.
//!
//! Serde reads the tables into their raw form (`raw`: every key that some kind lacks is an
//! `Option`); the checks there turn it into the forms here, one variant per `kind` holding
//! exactly what that kind reads.

use serde::{Deserialize, Serialize};

use crate::scene::EffectKind;

mod raw;

pub(super) use raw::{DlsmScene as RawDlsmScene, validate};

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

/// The Voronoi sample: its domain (`kind`), about how many elements, and where the seeds
/// come from. See docs/scenes.md.
#[derive(Debug, Clone, Copy)]
pub struct SampleSpec {
    pub shape: SampleShape,
    /// About how many Voronoi elements to make, ≥ 8.
    pub elements: usize,
    /// How Voronoi seeds are placed (`method`, default "noisy_grid").
    pub seeds: Seeds,
}

impl SampleSpec {
    /// `sample.kind`.
    pub fn kind(&self) -> SampleKind {
        match self.shape {
            SampleShape::Box { .. } => SampleKind::VoronoiBox,
            SampleShape::Cylinder { .. } => SampleKind::VoronoiCylinder,
            SampleShape::Disc { .. } => SampleKind::VoronoiDisc,
            SampleShape::Ball { .. } => SampleKind::VoronoiBall,
        }
    }
}

/// The domain the Voronoi cells fill, one variant per `sample.kind`.
#[derive(Debug, Clone, Copy)]
pub enum SampleShape {
    /// `voronoi_box`: box edge lengths [x, y, z] (m), each > 0 (`box`, or a cube of edge
    /// `length`).
    Box { size: [f64; 3] },
    /// `voronoi_cylinder`, along x: length (m) and radius (m), > 0.
    Cylinder { length: f64, radius: f64 },
    /// `voronoi_disc`, in the x–y plane: diameter (m) and thickness (m), > 0.
    Disc { diameter: f64, thickness: f64 },
    /// `voronoi_ball`: radius (m), > 0.
    Ball { radius: f64 },
}

/// Where the Voronoi seeds come from (`method`), with its randomness.
#[derive(Debug, Clone, Copy)]
pub enum Seeds {
    /// One seed per cell of a regular grid, moved by a uniform noise (Section 7.1): noise
    /// range d in [0, 1], default 0.9.
    NoisyGrid { noise: f64 },
    /// Centres of a sphere packing with dispersed radii (Section 7.2): relative half-width δ
    /// of the uniform radius distribution, in [0.15, 0.9], default 0.25.
    Packing { radius_dispersion: f64 },
    /// A regular cubic grid (the noisy grid with d = 0).
    Grid,
}

impl Seeds {
    /// `sample.method`.
    pub fn method(&self) -> SampleMethod {
        match self {
            Seeds::NoisyGrid { .. } => SampleMethod::NoisyGrid,
            Seeds::Packing { .. } => SampleMethod::Packing,
            Seeds::Grid => SampleMethod::Grid,
        }
    }
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

/// What the loading prescribes, one variant per `loading.kind`.
#[derive(Debug, Clone, Copy)]
pub enum LoadingSpec {
    /// Nothing prescribed.
    None {
        /// Duration of the run (s), > 0.
        end_time: f64,
    },
    /// The elements on the x− and x+ faces of a box move apart along x (Section 8.2.1).
    Tension(TensionSpec),
    /// A cylinder released from a static tension or torsion field, x− face clamped
    /// (Section 8.2.2).
    FreeVibration(VibrationSpec),
    /// A disc squeezed across its vertical (y) diameter (Section 8.2.4).
    Brazilian(BrazilianSpec),
    /// A body thrown onto an inclined ground plane (Section 8.1).
    Drop(DropSpec),
}

/// `loading.kind = "tension"`.
#[derive(Debug, Clone, Copy)]
pub struct TensionSpec {
    /// Axial strain rate (1/s), > 0.
    pub strain_rate: f64,
    /// Strain at which the test ends, in (0, 1).
    pub end_strain: f64,
    /// Time (s), ≥ 0, over which the prescribed speeds rise smoothly from zero; default a
    /// tenth of the loading time.
    pub ramp_time: Option<f64>,
    /// With `fracture`: the run ends once the load has fallen below this fraction of its
    /// peak, in [0, 0.99] (0: never early); default 0.2.
    pub stop_fraction: Option<f64>,
    /// How the driven elements hold the x faces: "sliding" (y, z free, the default) or
    /// "clamped" (y, z held).
    pub grip: Grip,
}

/// `loading.kind = "free_vibration"`.
#[derive(Debug, Clone, Copy)]
pub struct VibrationSpec {
    /// The static field the vibration starts from.
    pub mode: VibrationMode,
    /// Its amplitude: the initial strain A of the tension mode, in [-0.01, 0.01] (default
    /// 1e-5), or the initial twist α (rad/m) of the torsion mode, in [-1, 1] (default 1e-4).
    pub amplitude: f64,
    /// Duration (s), > 0.
    pub end_time: f64,
}

/// `loading.kind = "brazilian"`.
#[derive(Debug, Clone, Copy)]
pub struct BrazilianSpec {
    /// Speed (m/s) of each loaded side, > 0.
    pub speed: f64,
    /// Diametral strain at which the test ends, in (0, 1).
    pub end_strain: f64,
    /// Loading arc 2α (degrees), in [0, 90], default 0: 0 loads the top and bottom
    /// elements; 0 with platens or jaws, > 0 with `arc_pressure`.
    pub arc_degrees: f64,
    /// How the disc is loaded: "elements" (prescribed speeds on the elements of the loading
    /// arcs, the default), "flat_platens" or "curved_jaws" (two rigid platens, or jaws of
    /// radius 1.5 R, touching the disc's elements through frictional contacts, driven at
    /// `speed`; the force is read on them) or "arc_pressure" (a uniform radial pressure over
    /// the loading arcs, set by a servo on their closure commanded at `speed`).
    pub load_by: LoadBy,
    /// Stiffness (N/m) of the servo of `load_by = "arc_pressure"`, > 0 (that loading only).
    pub servo_stiffness: Option<f64>,
    /// Time (s), ≥ 0, over which the prescribed speeds rise smoothly from zero; default a
    /// tenth of the loading time.
    pub ramp_time: Option<f64>,
    /// With `fracture`: the run ends once the load has fallen below this fraction of its
    /// peak, in [0, 0.99] (0: never early); default 0.2.
    pub stop_fraction: Option<f64>,
}

/// `loading.kind = "drop"`.
#[derive(Debug, Clone, Copy)]
pub struct DropSpec {
    /// Duration (s), > 0.
    pub end_time: f64,
    /// Initial velocity (m/s) of the dropped body, finite; default 0.
    pub initial_velocity: [f64; 3],
    /// Inclination (degrees) of the ground plane, descending towards +x, in [0, 60];
    /// default 0.
    pub ground_angle_degrees: f64,
    /// Gap (m) between the body and the ground at the start, ≥ 0; default 0.
    pub drop_height: f64,
}

/// The dlsm model's tables of a scene, checked.
#[derive(Debug, Clone)]
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
