//! The plain structs the kernels take and give, as the C header declares them: no library
//! type appears in them, only doubles and integers.

/// A grain as the kernels see it (SI, world frame).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumBody {
    /// Centre of mass (m).
    pub pos: [f64; 3],
    /// Velocity (m/s).
    pub vel: [f64; 3],
    /// Angular velocity (rad/s).
    pub omega: [f64; 3],
    /// Orientation: body (principal) frame to world, w x y z.
    pub quat: [f64; 4],
    /// Mass (kg).
    pub mass: f64,
    /// Bounding radius (m); a sphere's radius.
    pub radius: f64,
    /// Semi-axes a+ a- b+ b- c+ c- (m); a sphere: all = radius (not read).
    pub semi: [f64; 6],
    /// Octant origin in the body frame (m); a sphere: 0.
    pub origin: [f64; 3],
    /// Shape frame to body frame, w x y z; a sphere: 1 0 0 0.
    pub to_body: [f64; 4],
    /// Principal moments of inertia (kg m^2).
    pub inertia: [f64; 3],
    /// 1: a sphere, 0: a poly-ellipsoid (any nonzero value: a sphere).
    pub sphere: i32,
}

/// The folded constants of the Hertz-Mindlin kernel and which sub-models are on, as
/// `fractum_kernel_contact_law` makes them.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumContactLaw {
    /// 4/3 E* (Pa), E* = E / (2 (1 - nu^2)).
    pub four_thirds_e: f64,
    /// 2 E* (Pa).
    pub two_e: f64,
    /// The damping coefficient c (dimensionless; 0 without damping).
    pub damping: f64,
    /// 8 G* (Pa), G* = G / (2 (2 - nu)); 0 without friction.
    pub eight_g: f64,
    /// Coulomb friction coefficient (dimensionless; 0 without friction).
    pub mu: f64,
    /// Nonzero: the damping effect is on.
    pub damp: i32,
    /// Nonzero: the friction effect is on.
    pub friction: i32,
}

/// What a pair slot (or a wall candidate) remembers between evaluations: the tangential
/// displacement (m), the last contact normal (warm start; 0 0 0 when none) and the held
/// Hertz radius (m; 0 while not touching). 7 doubles: LAMMPS's per-contact history layout.
/// Start a new pair with all zeros.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumPairMemory {
    /// Tangential displacement (m).
    pub hist: [f64; 3],
    /// Last contact normal (unit, from B to A), 0 0 0 before the first contact.
    pub normal: [f64; 3],
    /// Held Hertz radius (m), 0 while not touching.
    pub radius: f64,
}

/// Where a body's shape sits in the world for one force evaluation: the octant origin (m)
/// and the rotation from the shape frame to the world, row by row (its columns are the shape
/// frame's x, y and z axes in world coordinates). `fractum_kernel_placement` computes it; a sphere's is
/// not read.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumPlacement {
    pub origin: [f64; 3],
    pub rot: [f64; 9],
}

/// Geometry of one contact.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumGeometry {
    /// Unit normal from B (or the wall) to A.
    pub normal: [f64; 3],
    /// Overlap (m), > 0.
    pub depth: f64,
    /// Contact point (m), midway between the two deepest points.
    pub point: [f64; 3],
    /// Deepest point of A into B (m).
    pub point_a: [f64; 3],
    /// Deepest point of B into A (m); for a wall, the foot of point_a on the plane.
    pub point_b: [f64; 3],
    /// Hertz equivalent radius (m).
    pub r_eff: f64,
    /// 1: touching; 0: separated (every other field 0).
    pub touching: i32,
}

/// One contact's force and what a record keeps (force on A; B, or the wall, gets the
/// opposite).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumContact {
    /// Force on A (N).
    pub force: [f64; 3],
    /// Torque on A about its centre of mass (N m).
    pub torque_a: [f64; 3],
    /// Torque on B about its centre of mass (N m); 0 against a wall.
    pub torque_b: [f64; 3],
    /// Contact point (m).
    pub point: [f64; 3],
    /// Unit normal from B (or the wall) to A.
    pub normal: [f64; 3],
    /// Normal force (N).
    pub normal_force: f64,
    /// Its elastic (Hertz) part 4/3 E* a delta (N): the force the contact tensile stress
    /// (Eq. 17, fractum_kernel_contact_tensile_stress) reads.
    pub hertz_force: f64,
    /// Hertz contact radius a (m).
    pub radius: f64,
    /// Normal contact stiffness 2 E* a (N/m).
    pub stiffness: f64,
    /// Elastic energy stored in the contact (J).
    pub energy: f64,
    /// Energy damping and sliding dissipated in this step (J).
    pub dissipated: f64,
    /// 1: in contact; 0: no contact, every other field 0.
    pub touching: i32,
}

/// Grain fracture constants (FractureParams, resolved).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumFractureLaw {
    /// Hoek-Brown m_i (dimensionless).
    pub mi: f64,
    /// Uniaxial compressive strength sigma_c (Pa).
    pub sigma_c: f64,
    /// Contact tensile strength sigma_fM (Pa).
    pub sigma_f: f64,
    /// Poisson's ratio of the grains (dimensionless).
    pub poisson: f64,
    /// Critical contacts that break a grain (3 to 64: fractum_kernel_fracture_range).
    pub critical_contacts: i32,
    /// Nonzero: a sphere first turns its principal directions to the ideal break plane.
    pub ideal_plane: i32,
    /// Nonzero: a sphere's break plane takes the random slight rotation.
    pub plane_jitter: i32,
    /// Springs per break plane, 0 without cohesion (else 3 to 16: fractum_kernel_fracture_range).
    pub springs: i32,
    /// Cohesive energy G_c (J/m^2), 0 without cohesion.
    pub gc: f64,
    /// Nonzero: a grain's Weibull factor scales sigma_c as well as sigma_f (a scene's
    /// `fracture.weibull_on = "both"`); 0: sigma_f only (`"contact"`, the paper's reading).
    pub weibull_sigma_c: i32,
    /// Nonzero: a grain's Weibull factor is its particle strength (`fracture.weibull_on =
    /// "particle"`, with `weibull_sigma_c` nonzero): sigma_c scales with it and the contact
    /// tensile strength with its cube root, so the critical contacts are those above
    /// `sigma_f * cbrt(strength)`.
    pub particle_strength: i32,
    /// Equivalent radius (3V/4π)^(1/3) (m, >= 0) below which a piece no longer splits
    /// (`fracture.comminution_limit`): fractum_kernel_check finds no break for it. 0: none.
    pub comminution_limit: f64,
}

/// Why a grain breaks. kind 0: it does not; 1: Hoek-Brown on its average stress (`stress`,
/// Pa, tension positive, row-major); 2: critical contacts (`normal`: the unit normal of the
/// plane through them). value: the stress that broke it (Pa; the largest principal
/// compression, or the largest contact tensile stress).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumTrigger {
    /// 0 none, 1 Hoek-Brown, 2 contacts.
    pub kind: i32,
    /// Average stress (Pa, tension positive, row-major); kind 1 only.
    pub stress: [f64; 9],
    /// Unit normal of the critical contacts' plane; kind 2 only.
    pub normal: [f64; 3],
    /// The stress that broke the grain (Pa).
    pub value: f64,
}

/// What a grain's contacts load it with, as Fractum's fracture check sums it
/// (`fractum::fracture::GrainLoad`; `fractum_kernel_grain_load_add` adds one contact): the
/// moment of the contact forces about its centre, 9 doubles row-major (N m), the number of
/// critical contacts, and the three largest (stress, Pa, and point, m), largest first. Start
/// from all zeros each evaluation.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumGrainLoad {
    pub moment: [f64; 9],
    pub count: i64,
    pub stress: [f64; 3],
    pub point: [[f64; 3]; 3],
}

/// A split made, waiting for the halves' forces to set its springs (world frame).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumPending {
    /// The parent's centre of mass (m).
    pub centroid: [f64; 3],
    /// The parent's acceleration (m/s^2).
    pub accel: [f64; 3],
    /// The parent's angular acceleration (rad/s^2).
    pub alpha: [f64; 3],
    /// The parent's angular velocity (rad/s).
    pub omega: [f64; 3],
    /// The spring points (m); the first `count` are used.
    pub points: [[f64; 3]; 16],
    /// Spring points (0 without cohesion; at most 16).
    pub count: i32,
    /// Area each spring stands for (m^2).
    pub area: f64,
}

/// A split: the axis of the parent's shape frame it splits normal to (-1: the shape forbids
/// breaking, nothing else set), the + half (which the parent becomes), the - half (a new
/// body) and the pending bond.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumSplit {
    /// 0, 1 or 2 (x, y, z of the parent's shape frame); -1: no split.
    pub axis: i32,
    /// The + half: the parent becomes it.
    pub plus: FractumBody,
    /// The - half: a new body.
    pub minus: FractumBody,
    /// What `fractum_kernel_bond` needs once the halves' forces are known.
    pub pending: FractumPending,
}

/// One cohesive spring between bodies A and B.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumSpring {
    /// The spring's end on A, in A's body frame (m).
    pub on_a: [f64; 3],
    /// The spring's end on B, in B's body frame (m).
    pub on_b: [f64; 3],
    /// Unit direction of the force on A, in A's body frame.
    pub direction: [f64; 3],
    /// Initial force f_i (N).
    pub f0: f64,
    /// Softening stiffness k (N/m).
    pub k: f64,
    /// Largest elongation reached (m).
    pub opening: f64,
    /// The ends' separation (A's end minus B's, world; m) at the last evaluation.
    pub last_gap: [f64; 3],
    /// The force on A at the last evaluation (N, world).
    pub last_force: [f64; 3],
    /// 1: broken for good.
    pub broken: i32,
}

/// A host's per-atom arrays as the bulk integrator kernels read and write them: each a table
/// of row pointers (`double **`, the layout of LAMMPS's `atom->x` and of `fix property/atom`
/// arrays), row `i` atom `i`'s values. Atoms `0..n` whose `mask[i] & groupbit` is nonzero are
/// advanced (`mask` null: all of them).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct FractumAtomRows {
    /// The atoms advanced are among the first `n` (a host's owned atoms).
    pub n: i32,
    /// The group bit each advanced atom's `mask` has (with `mask` given).
    pub groupbit: i32,
    /// Per-atom group masks (null: every atom is advanced).
    pub mask: *const i32,
    /// Centres of mass (m), 3 doubles a row.
    pub x: *const *mut f64,
    /// Velocities (m/s), 3 doubles a row.
    pub v: *const *mut f64,
    /// Angular velocities (rad/s, world), 3 doubles a row.
    pub omega: *const *mut f64,
    /// Forces (N), 3 doubles a row.
    pub force: *const *const f64,
    /// Torques (N m, world), 3 doubles a row.
    pub torque: *const *const f64,
    /// Masses (kg), one double an atom.
    pub mass: *const f64,
    /// Bounding radii (m), one double an atom.
    pub radius: *const f64,
    /// Orientations, body (principal) frame to world, w x y z in a row's first 4 doubles.
    /// Null: spheres that track no orientation (moments 2/5 m r^2, as `FractumBody` gives a
    /// sphere without shape arrays).
    pub quat: *const *mut f64,
    /// Principal moments of inertia (kg m^2) in a row's first 3 doubles; read with `quat`.
    pub inertia: *const *const f64,
    /// Summed travels (m) in a row's first double, each grown by its atom's drift
    /// (`fractum_kernel_travel`); null: not summed. Read with `quat` only.
    pub travel: *const *mut f64,
}

/// A host's neighbour list as LAMMPS keeps it (`NeighList` with the history fix's pages):
/// row `ii` of `inum` is atom `ilist[ii]`, its `numneigh[i]` candidates at `firstneigh[i]`
/// (each `& index_mask` a partner's index), and, where the host keeps the pairs' records,
/// each candidate's record of `stride` doubles at `firstvalue[i]` and its kept flag at
/// `firsttouch[i]` (both null: no records kept; `stride` still sets the records' layout).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct FractumNeighbours {
    pub inum: i32,
    pub ilist: *const i32,
    pub numneigh: *const i32,
    pub firstneigh: *const *const i32,
    pub index_mask: i32,
    pub firsttouch: *const *mut i32,
    pub firstvalue: *const *mut f64,
    pub stride: i32,
}

/// One touching pair contact of a host's evaluation, as `fractum_kernel_sum_contacts` sums
/// it into its two atoms: the force on atom `i` (the opposite on `j`), each atom's torque,
/// and what fracture and the step adaptation read of it.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FractumTouching {
    /// The host's index of the atom whose row found the contact.
    pub i: i32,
    /// The host's index of its partner.
    pub j: i32,
    /// Force on `i` (N); `j` takes the opposite.
    pub force: [f64; 3],
    /// Torque on `i` (N m, world).
    pub torque_i: [f64; 3],
    /// Torque on `j` (N m, world).
    pub torque_j: [f64; 3],
    /// Contact point (m).
    pub point: [f64; 3],
    /// Hertz normal force (N) and held Hertz radius (m): the contact tensile stress.
    pub hertz_force: f64,
    pub radius: f64,
    /// The contact's shares of `i`'s and `j`'s rows of the frequency bound (rad²/s²).
    pub share_i: f64,
    pub share_j: f64,
}
