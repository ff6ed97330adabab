//! The scene file: what to simulate, in TOML, SI units throughout.
//!
//! `docs/scenes.md` documents every key with its unit and allowed range. Loading goes
//! text -> TOML table -> `--set` overrides -> typed [`Scene`] (unknown keys rejected) ->
//! range checks ([`validate`]). Every failure is one sentence naming the file and the key.

mod dlsm;
mod overrides;
mod parse;
mod validate;
mod validate_beam2d;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

pub use overrides::apply_override;

/// A complete scene, as read from a file and checked.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Name of the run, echoed in outputs.
    pub name: String,
    /// Seed of every random choice (sample generation, later fracture statistics).
    #[serde(default = "default_seed")]
    pub seed: u64,
    pub material: Material,
    pub sample: SampleSpec,
    #[serde(default)]
    pub model: ModelSpec,
    /// The effects that build the force pipeline; nothing else is constructed.
    #[serde(default)]
    pub effects: Vec<EffectKind>,
    pub loading: LoadingSpec,
    #[serde(default)]
    pub time: TimeSpec,
    #[serde(default)]
    pub output: OutputSpec,
    #[serde(default)]
    pub gravity: GravitySpec,
    #[serde(default)]
    pub neighbor: NeighborSpec,
    #[serde(default)]
    pub walls: WallSpec,
    // granular particle fracture
    /// Criteria, strength statistics, break planes and cohesion of breaking grains (used by
    /// the `fracture`, `weibull` and `cohesion` effects).
    #[serde(default)]
    pub fracture: FractureSpec,
    /// Where the scene came from (for messages and relative paths); not a key.
    #[serde(skip)]
    pub source: SceneSource,
    // beam2d: the fragment mass histogram and its power-law fit.
    #[serde(default)]
    pub fragments: FragmentSpec,
}

fn default_seed() -> u64 {
    1
}

/// Where a scene came from: the file label used in messages and the folder that relative
/// paths in the scene (such as `sample.file`) are resolved against.
#[derive(Debug, Clone, Default)]
pub struct SceneSource {
    pub label: String,
    pub dir: PathBuf,
    /// The keys given with `--set`, to say so in messages.
    pub overridden: Vec<String>,
    /// The scene text and the `--set` overrides as given: a checkpoint stores them to rebuild
    /// the very same scene.
    pub text: String,
    pub overrides: Vec<String>,
}

/// Elastic and contact properties of the grains (and of the walls, which share them).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E (Pa), > 0.
    pub young: f64,
    /// Poisson's ratio ν, in (-1, 0.5). Required by the sphere models; `beam2d` does not read
    /// it (its polygons are rigid), so there it may be left out (NaN marks it absent).
    #[serde(default = "absent")]
    pub poisson: f64,
    /// Density ρ (kg/m³), > 0.
    pub density: f64,
    /// Coulomb friction coefficient μ, ≥ 0 (used by the `friction` effect).
    #[serde(default)]
    pub friction: f64,
    /// Normal coefficient of restitution e, in (0, 1] (used by the `damping` effect).
    #[serde(default = "one")]
    pub restitution: f64,
    // beam2d (docs/scenes.md): beams (Eq. 7-12), their breaking (Eq. 13), contact damping (Eq. 3-4).
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
    // dlsm
    /// Tensile strength σf (Pa) of a cohesive contact (Eq. 36), for the `fracture` effect.
    pub tensile_strength: Option<f64>,
    /// Normal stiffness (N/m) of element–ground contacts (`contact` effect).
    pub contact_stiffness: Option<f64>,
}

fn one() -> f64 {
    1.0
}

fn absent() -> f64 {
    f64::NAN
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
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
    /// beam2d: Voronoi polygons of one random point per square of a regular grid.
    VectorizableRandomLattice,
    /// dlsm: Voronoi cells filling a box.
    VoronoiBox,
    /// dlsm: Voronoi cells filling a cylinder along x.
    VoronoiCylinder,
    /// dlsm: Voronoi cells filling a disc in the x–y plane.
    VoronoiDisc,
    /// dlsm: Voronoi cells filling a ball.
    VoronoiBall,
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
            SampleKind::VectorizableRandomLattice => "vectorizable_random_lattice",
            SampleKind::VoronoiBox => "voronoi_box",
            SampleKind::VoronoiCylinder => "voronoi_cylinder",
            SampleKind::VoronoiDisc => "voronoi_disc",
            SampleKind::VoronoiBall => "voronoi_ball",
        }
    }
}

/// How the sample is made. Which keys apply depends on `kind`; see docs/scenes.md.
#[derive(Debug, Clone, Serialize, Deserialize)]
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
    // granular particle fracture
    /// Orientation of the grains' principal directions: "random" (uniform; the default for
    /// random packings) or "aligned" with the box axes (the default for the other kinds).
    pub orientations: Option<Orientations>,
    /// Grain shape of random packings: "sphere" (default) or "poly_ellipsoid".
    pub shape: Option<GrainShape>,
    /// Poly-ellipsoids of random packings: each semi-axis is drawn uniformly in
    /// [r / aspect_ratio_max, r] for a packed sphere of radius r; in [1, 4], default 2.
    pub aspect_ratio_max: Option<f64>,
    /// The grain of `kind = "single"`: semi-axes [a+, a-, b+, b-, c+, c-] (m) along the
    /// grain's +x, -x, +y, -y, +z, -z.
    pub semi_axes: Option<[f64; 6]>,
    // beam2d: the vectorizable random lattice.
    /// Lattice spacing (m) of the grid of squares.
    pub spacing: Option<f64>,
    /// Largest distance (m) of a square's point from its centre, in [0, spacing].
    pub disorder: Option<f64>,
    /// The outline the polygons are cut to.
    pub outline: Option<Outline>,
    /// Grid squares [nx, ny] of a rectangle.
    pub cells: Option<[usize; 2]>,
    /// Diameter (m) of a disc (beam2d, dlsm).
    pub diameter: Option<f64>,
    /// Thickness (m): out of plane of the beam2d solid (default 1), of a dlsm disc.
    pub thickness: Option<f64>,
    // dlsm
    /// How Voronoi seeds are placed.
    pub method: Option<SampleMethod>,
    /// Noise range d of the noisy grid, in [0, 1] (Section 7.1).
    pub noise: Option<f64>,
    /// About how many Voronoi elements to make.
    pub elements: Option<usize>,
    /// Edge of a cubic box, or length of a cylinder (m).
    pub length: Option<f64>,
    /// Radius of a cylinder or ball (m).
    pub radius: Option<f64>,
    /// Relative half-width δ of the uniform radius distribution of the packing method.
    pub radius_dispersion: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Orientations {
    Random,
    Aligned,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GrainShape {
    Sphere,
    PolyEllipsoid,
}

/// beam2d: the outline of a polygon sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outline {
    /// `cells` squares of `spacing`, lower left corner at the origin.
    Rectangle,
    /// A disc of `diameter` centred at the origin.
    Disc,
}

impl Outline {
    pub fn as_str(self) -> &'static str {
        match self {
            Outline::Rectangle => "rectangle",
            Outline::Disc => "disc",
        }
    }
}

/// dlsm: where Voronoi seeds come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
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

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// Spheres (and, with fracture, poly-ellipsoids) with Hertz–Mindlin contacts.
    #[default]
    Granular,
    /// 2D Voronoi polygons joined by breakable beams (polygon-beam-fragmentation-2d).
    Beam2d,
    /// Voronoi polyhedra joined by the distinct lattice spring model (brittle elastic solid).
    Dlsm,
}

impl ModelKind {
    pub fn as_str(self) -> &'static str {
        match self {
            ModelKind::Granular => "granular",
            ModelKind::Beam2d => "beam2d",
            ModelKind::Dlsm => "dlsm",
        }
    }
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    #[serde(default)]
    pub kind: ModelKind,
}

/// One entry of the scene's `effects` list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EffectKind {
    /// Hertz normal contact force between grains and with walls.
    Contact,
    /// Viscous normal (and tangential) damping mapped from `material.restitution`.
    Damping,
    /// Mindlin tangential force with contact history and the Coulomb limit.
    Friction,
    /// Body force m·g.
    Gravity,
    /// granular: particle fracture by the Hoek–Brown and contact tensile criteria, subdivision
    /// into two sub-poly-ellipsoids. dlsm: cohesive contacts break for good when σxx > σf
    /// (Eq. 36) and turn into frictional, non-cohesive polyhedron contacts.
    Fracture,
    /// Cohesive springs between the sub-particles of a split (Eq. 35–43).
    Cohesion,
    /// Weibull statistics and size effect of the grains' strength (Eq. 18).
    Weibull,
    /// beam2d: elastic beams between neighbouring polygons (Eq. 7-12).
    Beams,
    /// beam2d: beams break by Eq. 13 and never return.
    BeamBreaking,
}

impl EffectKind {
    pub fn as_str(self) -> &'static str {
        match self {
            EffectKind::Contact => "contact",
            EffectKind::Damping => "damping",
            EffectKind::Friction => "friction",
            EffectKind::Gravity => "gravity",
            EffectKind::Fracture => "fracture",
            EffectKind::Cohesion => "cohesion",
            EffectKind::Weibull => "weibull",
            EffectKind::Beams => "beams",
            EffectKind::BeamBreaking => "beam_breaking",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
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
    /// beam2d: uniaxial elongation, then compression from the same start, under plane stress
    /// with free sides (Section 3.1).
    ElasticModuli,
    /// beam2d: strain-controlled compression between confined horizontal boundaries
    /// (Section 3.2).
    ConfinedCompression,
    /// beam2d: the centre polygon explodes (Section 3.3.1).
    Explosion,
    /// beam2d: one polygon at the lower middle is shot into the block (Section 3.3.2).
    Projectile,
    /// dlsm: the elements on the x− and x+ faces of a box move apart along x (Section 8.2.1).
    Tension,
    /// dlsm: a cylinder released from a static tension or torsion field, x− face clamped
    /// (Section 8.2.2).
    FreeVibration,
    /// dlsm: a disc squeezed across its vertical (y) diameter (Section 8.2.4).
    Brazilian,
    /// dlsm: a body thrown onto an inclined ground plane (Section 8.1).
    Drop,
}

impl LoadingKind {
    pub fn as_str(self) -> &'static str {
        match self {
            LoadingKind::None => "none",
            LoadingKind::Oedometer => "oedometer",
            LoadingKind::Platens => "platens",
            LoadingKind::ElasticModuli => "elastic_moduli",
            LoadingKind::ConfinedCompression => "confined_compression",
            LoadingKind::Explosion => "explosion",
            LoadingKind::Projectile => "projectile",
            LoadingKind::Tension => "tension",
            LoadingKind::FreeVibration => "free_vibration",
            LoadingKind::Brazilian => "brazilian",
            LoadingKind::Drop => "drop",
        }
    }
}

/// dlsm: the static field a free vibration starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VibrationMode {
    /// u = A x.
    Tension,
    /// A twist of α rad/m about the x axis.
    Torsion,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadingSpec {
    pub kind: LoadingKind,
    /// Axial engineering strain rate (1/s), > 0: the driven wall moves at rate × initial height.
    pub strain_rate: Option<f64>,
    /// Axial strain at which the run ends, in (0, 1).
    pub end_strain: Option<f64>,
    /// Duration of the run (s) for `kind = "none"`.
    pub end_time: Option<f64>,
    /// Speed (m/s), > 0: of the top platen (`platens`), of the projectile polygon (beam2d
    /// `projectile`), of each loaded side of a Brazilian disc (dlsm `brazilian`).
    pub speed: Option<f64>,
    // granular particle fracture
    /// Platen travel (m) at which a `platens` run ends, > 0.
    pub end_displacement: Option<f64>,
    // beam2d loadings.
    /// Time (s) over which the driven boundaries reach their final speed (beam2d: uniform
    /// acceleration; dlsm tension and brazilian: a smooth rise from zero).
    pub ramp_time: Option<f64>,
    /// Energy E0 (J) of the explosion.
    pub energy: Option<f64>,
    /// The run stops after this many steps without a beam breaking (explosion, projectile).
    pub quiet_steps: Option<u64>,
    // dlsm
    /// Loading arc 2α (degrees) of the Brazilian test; 0 loads the top and bottom elements.
    pub arc_degrees: Option<f64>,
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

/// The time step: a number of seconds, or "auto" for the Rayleigh critical step × safety.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum DtSpec {
    #[default]
    Auto,
    Seconds(f64),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorKind {
    #[default]
    VelocityVerlet,
    /// beam2d: Gear's fifth-order predictor–corrector.
    Gear5,
    /// dlsm: Tchamwa–Wielgosz with `time.phi` (Eq. 37–38).
    TchamwaWielgosz,
}

impl IntegratorKind {
    pub fn as_str(self) -> &'static str {
        match self {
            IntegratorKind::VelocityVerlet => "velocity_verlet",
            IntegratorKind::Gear5 => "gear5",
            IntegratorKind::TchamwaWielgosz => "tchamwa_wielgosz",
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    #[serde(default)]
    pub dt: DtSpec,
    /// Fraction of the Rayleigh critical time step used when `dt = "auto"`, in (0, 1].
    #[serde(default = "default_safety")]
    pub safety: f64,
    #[serde(default)]
    pub integrator: IntegratorKind,
    // dlsm
    /// φ of the Tchamwa–Wielgosz scheme, ≥ 0.5 (0.5 is velocity Verlet).
    pub phi: Option<f64>,
}

fn default_safety() -> f64 {
    0.2
}

impl Default for TimeSpec {
    fn default() -> Self {
        TimeSpec {
            dt: DtSpec::Auto,
            safety: default_safety(),
            integrator: IntegratorKind::VelocityVerlet,
            phi: None,
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Steps between rows of series.csv, ≥ 1.
    #[serde(default = "default_every")]
    pub every: u64,
    /// Steps between VTK snapshots; 0 writes none.
    #[serde(default)]
    pub vtk: u64,
    // granular particle fracture
    /// Axial strains at which summary.json reports the stress (`stress_at_strain`) and
    /// psd.csv the size distribution (oedometer runs with `fracture`); default 0.05, 0.1,
    /// 0.2, 0.3, 0.4 (those up to `loading.end_strain`).
    pub report_strains: Option<Vec<f64>>,
}

fn default_every() -> u64 {
    100
}

impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            every: default_every(),
            vtk: 0,
            report_strains: None,
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GravitySpec {
    /// Gravitational acceleration (m/s²), used by the `gravity` effect.
    #[serde(default = "default_g")]
    pub acceleration: [f64; 3],
}

fn default_g() -> [f64; 3] {
    [0.0, 0.0, -9.81]
}

impl Default for GravitySpec {
    fn default() -> Self {
        GravitySpec {
            acceleration: default_g(),
        }
    }
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NeighborSpec {
    /// Verlet skin (m) of the neighbour list; default 0.4 × the smallest radius.
    pub skin: Option<f64>,
}

/// The walls of the container (same elastic material as the grains).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// Coulomb friction between grains and walls (default: material.friction); 0 models
    /// lubricated walls.
    pub friction: Option<f64>,
}

/// Particle fracture of the granular model (poly-ellipsoid-fracture-shpb.txt, Section 3).
/// Stresses in Pa, compression positive where Hoek–Brown is concerned.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FractureSpec {
    /// Hoek–Brown material constant m_i (Eq. 14), > 0; default 20.56 (Fig. 6).
    #[serde(default = "default_mi")]
    pub mi: f64,
    /// Hoek–Brown compressive strength σ_c (Pa), > 0; default 592 MPa (Fig. 6). With
    /// `weibull`, the strength of a grain of `reference_radius` with P = 1/e.
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
            critical_contacts: default_critical_contacts(),
            toughness: default_toughness(),
            springs: default_springs(),
            ideal_plane: true,
            plane_jitter: true,
        }
    }
}

/// beam2d: how fragment masses are binned and where the power law F(m) ~ m^-β is fitted.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FragmentSpec {
    /// The fit range [lo, hi] in mean polygon masses.
    #[serde(default = "default_fit_range")]
    pub fit_range: [f64; 2],
    /// Logarithmic bins per decade of mass.
    #[serde(default = "default_bins_per_decade")]
    pub bins_per_decade: u32,
}

fn default_fit_range() -> [f64; 2] {
    [2.0, 20.0]
}

fn default_bins_per_decade() -> u32 {
    4
}

impl Default for FragmentSpec {
    fn default() -> Self {
        FragmentSpec {
            fit_range: default_fit_range(),
            bins_per_decade: default_bins_per_decade(),
        }
    }
}

impl Scene {
    /// Reads, overrides and checks a scene file. `overrides` are `KEY=VALUE` strings as
    /// given to `--set`.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Scene> {
        let label = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::input(
                &label,
                format!("cannot read the scene file ({})", io_reason(&e)),
            )
        })?;
        let dir = path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from("."));
        Scene::from_toml(&text, &label, &dir, overrides)
    }

    /// Parses scene text. `label` names it in messages; relative paths resolve against `dir`.
    pub fn from_toml(text: &str, label: &str, dir: &Path, overrides: &[String]) -> Result<Scene> {
        let mut scene = parse::parse(text, label, overrides)?;
        scene.source = SceneSource {
            label: label.to_string(),
            dir: dir.to_path_buf(),
            overridden: overrides
                .iter()
                .filter_map(|o| o.split_once('=').map(|(k, _)| k.trim().to_string()))
                .collect(),
            text: text.to_string(),
            overrides: overrides.to_vec(),
        };
        validate::validate(&scene)?;
        Ok(scene)
    }

    /// An input error about `key` of this scene, one sentence.
    pub fn key_error(&self, key: &str, message: impl AsRef<str>) -> Error {
        let via = if self.source.overridden.iter().any(|k| k == key) {
            " (set with --set)"
        } else {
            ""
        };
        Error::input(
            &self.source.label,
            format!("{key}{via} {}", message.as_ref()),
        )
    }

    /// Resolves a path given in the scene relative to the scene file's folder.
    pub fn resolve(&self, path: &str) -> PathBuf {
        let p = Path::new(path);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.source.dir.join(p)
        }
    }

    pub fn has_effect(&self, effect: EffectKind) -> bool {
        self.effects.contains(&effect)
    }
}

/// The short reason of an I/O error, without the "(os error 2)" noise.
pub(crate) fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
        _ => e.to_string(),
    }
}

impl Serialize for DtSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            DtSpec::Auto => s.serialize_str("auto"),
            DtSpec::Seconds(v) => s.serialize_f64(*v),
        }
    }
}

impl<'de> Deserialize<'de> for DtSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = DtSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"auto\" or a time step in seconds")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<DtSpec, E> {
                if v == "auto" {
                    Ok(DtSpec::Auto)
                } else {
                    Err(E::invalid_value(serde::de::Unexpected::Str(v), &self))
                }
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<DtSpec, E> {
                Ok(DtSpec::Seconds(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<DtSpec, E> {
                Ok(DtSpec::Seconds(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<DtSpec, E> {
                Ok(DtSpec::Seconds(v as f64))
            }
        }
        d.deserialize_any(V)
    }
}
