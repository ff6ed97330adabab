//! The granular model's own scene tables (`material`, `sample`, `loading`, `walls`,
//! `neighbor`, `fracture`), typed and checked. Keys of other models are refused by name.
//!
//! Serde reads the tables into their raw form (`raw`: every key that some kind lacks is an
//! `Option`); the checks there turn it into the forms here, one variant per `kind` holding
//! exactly what that kind reads, so that building needs no second look at which keys are
//! present.

use serde::Deserialize;

use crate::fracture::FractureSpec;
use crate::scene::{EffectKind, NeighborSpec};

mod raw;
mod sleeve;

pub(super) use raw::{GranularScene as RawGranularScene, validate};

/// Elastic and contact properties of the grains (and of the walls, which share them).
#[derive(Debug, Clone)]
pub struct Material {
    /// Young's modulus E (Pa), > 0.
    pub young: f64,
    /// Poisson's ratio ν, in (-1, 0.5).
    pub poisson: f64,
    /// Density ρ (kg/m³), > 0.
    pub density: f64,
    /// Coulomb friction coefficient μ, ≥ 0 (used by the `friction` effect); default 0.
    pub friction: f64,
    /// Normal coefficient of restitution e, in (0, 1] (used by the `damping` effect);
    /// default 1.
    pub restitution: f64,
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
    /// first loading step (the default for ellipsoid grains).
    Compaction,
    /// Jammed at the fraction under a light seating pressure, by compaction with a friction
    /// searched between none and the grains' own (`crate::sample::compact_jammed`): a
    /// sample that carries load before loading, as a laboratory's consolidated specimen.
    Jammed,
}

impl Packing {
    pub fn as_str(self) -> &'static str {
        match self {
            Packing::Geometric => "geometric",
            Packing::Compaction => "compaction",
            Packing::Jammed => "jammed",
        }
    }
}

/// How the sample is made: the grains its `kind` makes, then, with `pressure`, a servo
/// compaction to that pressure. See docs/scenes.md.
#[derive(Debug, Clone)]
pub struct SampleSpec {
    pub grains: Grains,
    /// Confining pressure (Pa), > 0 (range-checked for random samples): after the packing,
    /// servo-controlled walls compress the sample until every wall carries this stress.
    pub compaction: Option<PressureCompaction>,
}

impl SampleSpec {
    /// `sample.kind`.
    pub fn kind(&self) -> SampleKind {
        match &self.grains {
            Grains::Random(_) => SampleKind::Random,
            Grains::Lattice(l) if l.hcp => SampleKind::Hcp,
            Grains::Lattice(_) => SampleKind::SimpleCubic,
            Grains::File(f) => f.format,
            Grains::EllipsoidAssembly { .. } => SampleKind::EllipsoidAssembly,
            Grains::Single(_) => SampleKind::Single,
        }
    }
}

impl SampleSpec {
    /// Whether the grains may be other than spheres (poly-ellipsoids, ellipsoids).
    pub fn non_spherical(&self) -> bool {
        matches!(
            &self.grains,
            Grains::Random(RandomSample {
                shape: RandomShape::PolyEllipsoids { .. } | RandomShape::Ellipsoids { .. },
                ..
            }) | Grains::EllipsoidAssembly { .. }
        )
    }
}

/// `sample.pressure` and the friction while compacting to it.
#[derive(Debug, Clone, Copy)]
pub struct PressureCompaction {
    /// Confining pressure (Pa) every wall carries at the end.
    pub pressure: f64,
    /// Friction coefficient while compacting to `pressure`, ≥ 0 (`compaction_friction`;
    /// default: material.friction).
    pub friction: f64,
}

/// The grains of each `sample.kind`.
#[derive(Debug, Clone)]
pub enum Grains {
    /// `random`: a random packing in a box.
    Random(RandomSample),
    /// `simple_cubic`, `hcp`: touching spheres on a lattice.
    Lattice(LatticeSample),
    /// `text`, `lammps_data`, `yade_text`: spheres read from a packing file.
    File(FileSample),
    /// `ellipsoid_assembly`: an ellipsoid assembly file (CSV, relative to the scene file)
    /// imported as it is, in the box its grains span.
    EllipsoidAssembly { file: String },
    /// `single`: one grain on the bottom of a box whose top touches it.
    Single(SingleGrain),
}

/// `kind = "random"`.
#[derive(Debug, Clone)]
pub struct RandomSample {
    pub shape: RandomShape,
    pub amount: Amount,
    /// Box edge lengths [x, y, z] (m), each > 0.
    pub box_size: [f64; 3],
    /// Orientation of the grains' principal directions: "random" (uniform; the default) or
    /// "aligned" with the box axes.
    pub orientations: Orientations,
}

impl RandomSample {
    /// How the sample reaches its solid fraction (`packing`): "geometric" (default for
    /// spheres and poly-ellipsoids) or "compaction" (default, and the only method, for
    /// ellipsoids).
    pub fn packing(&self) -> Packing {
        match self.shape {
            RandomShape::Spheres { packing, .. } | RandomShape::PolyEllipsoids { packing, .. } => {
                packing
            }
            RandomShape::Ellipsoids { packing, .. } => packing,
        }
    }
}

/// The grains of a random packing (`shape`).
#[derive(Debug, Clone)]
pub enum RandomShape {
    /// `shape = "sphere"` (the default).
    Spheres { radii: Radii, packing: Packing },
    /// `shape = "poly_ellipsoid"`: each packed sphere of radius r becomes a poly-ellipsoid
    /// whose semi-axes are drawn uniformly in [r / aspect_ratio_max, r].
    PolyEllipsoids {
        radii: Radii,
        /// In [1, 4], default 2.
        aspect_ratio_max: f64,
        packing: Packing,
    },
    /// `shape = "ellipsoid"`: ellipsoids whose semi-axes are drawn from the grains of
    /// `grain_file` (CSV, relative to the scene file), packed by compaction (loose or
    /// jammed).
    Ellipsoids {
        grain_file: String,
        packing: Packing,
    },
}

/// The truncated normal radius distribution of a random packing (m).
#[derive(Debug, Clone, Copy)]
pub struct Radii {
    /// Mean radius (m), > 0.
    pub mean: f64,
    /// Standard deviation (m), ≥ 0; 0 (the default): monodisperse.
    pub sd: f64,
    /// Smallest radius (m) the truncated normal may give, in (0, mean]; default mean − 3 sd
    /// (at least 1% of the mean).
    pub min: f64,
    /// Largest radius (m) the truncated normal may give, ≥ mean; default mean + 3 sd.
    pub max: f64,
}

/// How many grains a random packing has: `count`, `solid_fraction`, or both (then the box
/// keeps its shape, scaled to the fraction).
#[derive(Debug, Clone, Copy)]
pub enum Amount {
    /// Number of grains, ≥ 1.
    Count(usize),
    /// Grains are drawn until they fill this solid fraction of the box: in (0, 0.65] for the
    /// geometric packing, (0, 0.9] for compaction (whose last grain is kept only if that lands
    /// closer, and which refuses whole grains that miss the fraction by more than
    /// `sample::FRACTION_TOLERANCE`).
    SolidFraction(f64),
    /// `count` grains, the box scaled to `solid_fraction`.
    Both { count: usize, solid_fraction: f64 },
}

impl Amount {
    pub fn count(self) -> Option<usize> {
        match self {
            Amount::Count(n) | Amount::Both { count: n, .. } => Some(n),
            Amount::SolidFraction(_) => None,
        }
    }
}

/// `kind = "simple_cubic"` or `"hcp"`.
#[derive(Debug, Clone, Copy)]
pub struct LatticeSample {
    /// Hexagonal close packed (`hcp`) rather than simple cubic.
    pub hcp: bool,
    /// The lattice radius (m), > 0 (`radius_mean`).
    pub radius: f64,
    /// Lattice layers [nx, ny, nz], each ≥ 1.
    pub layers: [usize; 3],
    /// Orientation of the spheres' principal directions; default "aligned".
    pub orientations: Orientations,
}

/// `kind = "text"`, `"lammps_data"` or `"yade_text"`.
#[derive(Debug, Clone)]
pub struct FileSample {
    /// Which of the three formats.
    pub format: SampleKind,
    /// Packing file, relative to the scene file.
    pub file: String,
    /// Box edge lengths [x, y, z] (m) when the file gives none.
    pub box_size: Option<[f64; 3]>,
    /// Orientation of the spheres' principal directions; default "aligned".
    pub orientations: Orientations,
}

/// `kind = "single"`.
#[derive(Debug, Clone, Copy)]
pub struct SingleGrain {
    /// Semi-axes [a+, a-, b+, b-, c+, c-] (m), each > 0, along the grain's +x, -x, +y, -y,
    /// +z, -z.
    pub semi_axes: [f64; 6],
    /// Box edge lengths [x, y, z] (m); x and y exceed the grain's largest extent.
    pub box_size: [f64; 3],
    /// Orientation of the grain's principal directions; default "aligned".
    pub orientations: Orientations,
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

/// How the walls move, one variant per `loading.kind`.
#[derive(Debug, Clone, Copy)]
pub enum LoadingSpec {
    /// Walls stay where the sample put them.
    None {
        /// Duration of the run (s), > 0.
        end_time: f64,
    },
    /// Oedometric compression: the top (+z) wall moves down at a constant strain rate, the
    /// other five walls are fixed.
    Oedometer {
        /// Axial engineering strain rate (1/s), > 0: the driven wall moves at rate × initial
        /// height.
        strain_rate: f64,
        /// Axial strain at which the run ends, in (0, 1).
        end_strain: f64,
    },
    /// Flat platens: the top (+z) wall moves down, the bottom is fixed (single-grain
    /// crushing).
    Platens {
        /// Speed (m/s) of the top platen, > 0.
        speed: f64,
        /// Platen travel (m) at which the run ends, > 0.
        end_displacement: f64,
    },
}

/// The walls of the container (same elastic material as the grains).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// Coulomb friction between grains and walls, ≥ 0 (default: material.friction); 0 models
    /// lubricated walls.
    pub friction: Option<f64>,
    /// The sample confined laterally by a rigid cylinder (an SHPB specimen's sleeve)
    /// inscribed in the box's x–y section, its axis along z, in place of the four side faces;
    /// the two z faces close it. Default false.
    #[serde(default)]
    pub sleeve: bool,
    /// Coulomb friction between grains and the sleeve, ≥ 0 (default: `friction`, else
    /// material.friction); with `sleeve` only.
    pub sleeve_friction: Option<f64>,
}

/// The granular model's tables of a scene, checked.
#[derive(Debug, Clone)]
pub struct GranularScene {
    pub material: Material,
    pub sample: SampleSpec,
    pub loading: LoadingSpec,
    pub walls: WallSpec,
    pub neighbor: NeighborSpec,
    /// Criteria, strength statistics, break planes and cohesion of breaking grains (used by
    /// the `fracture`, `weibull` and `cohesion` effects).
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
