//! Voronoi samples for the `dlsm` model (dlsm paper, Section 7).
//!
//! Seeds come from a noisy grid (Section 7.1: one point per cell of a regular grid, moved by
//! a uniform noise of range `d` times the cell), a regular grid (d = 0, cubic cells) or a
//! sphere packing with dispersed radii whose centres become seeds (Section 7.2). voro++
//! (through `voro_rs`) tessellates the domain: a box, a cylinder (axis x), a disc (axis z) or
//! a ball. Curved walls cut each cell by the plane tangent to the wall at the point nearest
//! to its seed, so the domain becomes a polyhedral approximation of the curved one.
//!
//! Each cell carries its volume, centroid, inertia tensor and, per face, the neighbour (a
//! cell or a domain boundary) with the shared face's area, outward normal and centroid.

use nalgebra::Matrix3;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
#[cfg(feature = "voronoi")]
use voro_rs::prelude::*;

use super::pack_geometric;
#[cfg(feature = "voronoi")]
use crate::shape::polyhedron::FaceGeometry;
use crate::shape::polyhedron::{Polyhedron, principal_axes};
use crate::state::{Bodies, Vec3, spatial_order};

/// The region a sample fills.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Domain {
    /// The box [lo, hi].
    Box { lo: Vec3, hi: Vec3 },
    /// A cylinder along x from x = 0 to `length`, axis through y = z = 0.
    Cylinder { length: f64, radius: f64 },
    /// A disc in the x–y plane, centred on the origin, z from −thickness/2 to thickness/2.
    Disc { diameter: f64, thickness: f64 },
    /// A ball centred on the origin.
    Ball { radius: f64 },
}

/// A boundary of a domain, as the faces of the cells that lie on it name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Boundary {
    XMin,
    XMax,
    YMin,
    YMax,
    ZMin,
    ZMax,
    /// The curved wall of a cylinder, disc or ball.
    Curved,
}

/// The six faces of a box domain, in voro++'s order of wall ids (−1 … −6).
pub const BOX_FACES: [Boundary; 6] = [
    Boundary::XMin,
    Boundary::XMax,
    Boundary::YMin,
    Boundary::YMax,
    Boundary::ZMin,
    Boundary::ZMax,
];

/// voro++ gives container faces the neighbour ids −1 … −6 (x−, x+, y−, y+, z−, z+); the
/// curved wall gets this one.
#[cfg_attr(not(feature = "voronoi"), allow(dead_code))]
const CURVED_WALL_ID: i32 = -7;

/// What lies across a face of a cell.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Neighbour {
    Cell(usize),
    Boundary(Boundary),
}

/// One face of a cell.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CellFace {
    pub neighbour: Neighbour,
    /// Area (m²).
    pub area: f64,
    /// Outward unit normal.
    pub normal: Vec3,
    /// Centroid of the face (m).
    pub centroid: Vec3,
}

/// A Voronoi cell.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct VoronoiCell {
    /// The seed (m): the point whose Voronoi cell this is.
    pub seed: Vec3,
    /// Vertices in the global frame; face k of the polyhedron is `faces[k]`.
    pub polyhedron: Polyhedron,
    /// Volume (m³).
    pub volume: f64,
    /// Centroid (m).
    pub centroid: Vec3,
    /// Inertia tensor about the centroid per unit density (m⁵).
    pub inertia: Matrix3<f64>,
    pub faces: Vec<CellFace>,
}

impl VoronoiCell {
    /// Moves the cell by `d`.
    pub fn translate(&mut self, d: &Vec3) {
        self.seed += d;
        self.centroid += d;
        self.polyhedron.vertices.iter_mut().for_each(|v| *v += d);
        self.faces.iter_mut().for_each(|f| f.centroid += d);
    }
}

impl Domain {
    /// The bounding box [lo, hi].
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match *self {
            Domain::Box { lo, hi } => (lo, hi),
            Domain::Cylinder { length, radius } => (
                Vec3::new(0.0, -radius, -radius),
                Vec3::new(length, radius, radius),
            ),
            Domain::Disc {
                diameter,
                thickness,
            } => {
                let (r, h) = (0.5 * diameter, 0.5 * thickness);
                (Vec3::new(-r, -r, -h), Vec3::new(r, r, h))
            }
            Domain::Ball { radius } => (Vec3::repeat(-radius), Vec3::repeat(radius)),
        }
    }

    /// Volume (m³) of the exact (not tessellated) domain.
    pub fn volume(&self) -> f64 {
        use std::f64::consts::PI;
        match *self {
            Domain::Box { lo, hi } => (hi - lo).product(),
            Domain::Cylinder { length, radius } => PI * radius * radius * length,
            Domain::Disc {
                diameter,
                thickness,
            } => PI * 0.25 * diameter * diameter * thickness,
            Domain::Ball { radius } => 4.0 / 3.0 * PI * radius.powi(3),
        }
    }

    /// Distance from `p` to the curved wall, positive inside (infinite for a box).
    pub fn curved_clearance(&self, p: &Vec3) -> f64 {
        match *self {
            Domain::Box { .. } => f64::INFINITY,
            Domain::Cylinder { radius, .. } => radius - p.y.hypot(p.z),
            Domain::Disc { diameter, .. } => 0.5 * diameter - p.x.hypot(p.y),
            Domain::Ball { radius } => radius - p.norm(),
        }
    }

    /// True when `p` lies strictly inside the domain.
    pub fn contains(&self, p: &Vec3) -> bool {
        let (lo, hi) = self.bounds();
        (0..3).all(|a| p[a] > lo[a] && p[a] < hi[a]) && self.curved_clearance(p) > 0.0
    }

    /// Length scale used to tessellate in units of order one (voro++'s tolerances are
    /// absolute): the curved radius, or the largest box edge.
    #[cfg_attr(not(feature = "voronoi"), allow(dead_code))]
    fn scale(&self) -> f64 {
        match *self {
            Domain::Box { lo, hi } => (hi - lo).max(),
            Domain::Cylinder { radius, .. } | Domain::Ball { radius } => radius,
            Domain::Disc { diameter, .. } => 0.5 * diameter,
        }
    }
}

/// Seeds on a regular grid over the domain's bounding box, about `elements` of them inside
/// the domain, each moved by a uniform noise in [−d/2, d/2] times the grid spacing per axis
/// (d = `noise`: 0 gives the grid, 1 a point anywhere in its grid cell). Seeds closer to a
/// curved wall than a quarter spacing are dropped: they would give slivers. Ordered slab by
/// slab (z, then y, then x), which keeps neighbours close in memory.
pub fn noisy_grid_seeds(
    domain: &Domain,
    elements: usize,
    noise: f64,
    rng: &mut ChaCha8Rng,
) -> Vec<Vec3> {
    let (lo, hi) = domain.bounds();
    let size = hi - lo;
    let per_cell = domain.volume() / elements.max(1) as f64;
    let a = per_cell.cbrt();
    let n = size.map(|l| ((l / a).round() as usize).max(1));
    let h = Vec3::new(
        size.x / n.x as f64,
        size.y / n.y as f64,
        size.z / n.z as f64,
    );
    let margin = 0.25 * h.min();
    let mut seeds = Vec::with_capacity(n.x * n.y * n.z);
    for k in 0..n.z {
        for j in 0..n.y {
            for i in 0..n.x {
                let centre = lo
                    + Vec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5).component_mul(&h);
                let jitter = Vec3::new(
                    rng.random::<f64>() - 0.5,
                    rng.random::<f64>() - 0.5,
                    rng.random::<f64>() - 0.5,
                );
                let p = centre + jitter.component_mul(&h) * noise;
                if domain.contains(&p) && domain.curved_clearance(&p) >= margin {
                    seeds.push(p);
                }
            }
        }
    }
    seeds
}

/// Seeds at the centres of a random sphere packing (growth and collective rearrangement,
/// [`pack_geometric`]) of the domain's bounding box at solid fraction 0.5, radii uniform in
/// [r̄(1 − δ), r̄(1 + δ)] with δ = `dispersion`, about `elements` of them inside the
/// domain. Centres nearer a curved wall than half their radius are dropped.
pub fn packing_seeds(
    domain: &Domain,
    elements: usize,
    dispersion: f64,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<Vec3>, String> {
    const SOLID_FRACTION: f64 = 0.5;
    let (lo, hi) = domain.bounds();
    let box_volume = (hi - lo).product();
    let count = ((elements as f64) * box_volume / domain.volume()).round() as usize;
    let count = count.max(1);
    // E[r³] for r uniform in r̄[1 − δ, 1 + δ] is r̄³ (1 + δ²).
    let mean_cube = SOLID_FRACTION * box_volume / (count as f64 * 4.0 / 3.0 * std::f64::consts::PI);
    let rbar = (mean_cube / (1.0 + dispersion * dispersion)).cbrt();
    let radii: Vec<f64> = (0..count)
        .map(|_| rbar * (1.0 + dispersion * (2.0 * rng.random::<f64>() - 1.0)))
        .collect();
    if (hi - lo).min() <= 2.0 * rbar * (1.0 + dispersion) {
        return Err(format!(
            "asks for spheres of radius up to {:e} m, too large for the domain's smallest extent {:e} m; ask for more elements",
            rbar * (1.0 + dispersion),
            (hi - lo).min()
        ));
    }
    let (pos, _) = pack_geometric(&radii, lo, hi, rng).map_err(|j| {
        format!(
            "cannot seed the Voronoi cells: {count} spheres in the domain's bounding box jammed at solid fraction {:.3}, below the {SOLID_FRACTION} the seeds are placed at (small samples pack looser along the walls); ask for more elements or use sample.method = \"noisy_grid\"",
            j.reached
        )
    })?;
    let kept: Vec<Vec3> = pos
        .into_iter()
        .zip(&radii)
        .filter(|(p, r)| domain.contains(p) && domain.curved_clearance(p) >= 0.5 * **r)
        .map(|(p, _)| p)
        .collect();
    let order = spatial_order(&kept, 2.0 * rbar);
    Ok(order.into_iter().map(|k| kept[k]).collect())
}

/// The Voronoi cells of `seeds` in `domain`, in the order of the seeds. Fails when a seed
/// lies outside the domain or its cell vanishes.
pub fn tessellate(seeds: &[Vec3], domain: &Domain) -> Result<Vec<VoronoiCell>, String> {
    if seeds.is_empty() {
        return Err("gives no seeds".to_string());
    }
    if let Some(k) = seeds.iter().position(|p| !domain.contains(p)) {
        return Err(format!(
            "seed {k} at {:?} lies outside the domain",
            seeds[k]
        ));
    }
    voro_cells(seeds, domain)?
        .into_iter()
        .enumerate()
        .map(|(k, c)| c.ok_or_else(|| format!("the Voronoi cell of seed {k} vanished")))
        .collect()
}

/// Without the `voronoi` feature (voro++ and its C++ bridge, left out of the FMU, which needs
/// granular samples only) there are no Voronoi samples.
#[cfg(not(feature = "voronoi"))]
fn voro_cells(_seeds: &[Vec3], _domain: &Domain) -> Result<Vec<Option<VoronoiCell>>, String> {
    Err("needs a Voronoi tessellation, which this build of Fractum leaves out (cargo feature `voronoi`)".to_string())
}

/// Each seed's cell from voro++ (None where it vanished), in the order of the seeds.
#[cfg(feature = "voronoi")]
fn voro_cells(seeds: &[Vec3], domain: &Domain) -> Result<Vec<Option<VoronoiCell>>, String> {
    // Tessellate in units of the domain's size, centred where the curved walls are.
    let s = domain.scale();
    let (lo, hi) = domain.bounds();
    let to_unit = |p: &Vec3| -> [f64; 3] { [p.x / s, p.y / s, p.z / s] };
    let per_block = 5.0;
    let blocks = {
        let size = (hi - lo) / s;
        let n = (seeds.len() as f64 / per_block / size.product()).cbrt();
        [0, 1, 2].map(|a| ((size[a] * n).round() as i32).clamp(1, 1 << 12))
    };
    let mut cylinder = match domain {
        Domain::Cylinder { radius, .. } => Some(WallCylinder::new_with_id(
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            radius / s,
            CURVED_WALL_ID,
        )),
        Domain::Disc { diameter, .. } => Some(WallCylinder::new_with_id(
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            0.5 * diameter / s,
            CURVED_WALL_ID,
        )),
        _ => None,
    };
    let mut sphere = match domain {
        Domain::Ball { radius } => Some(WallSphere::new_with_id(
            [0.0, 0.0, 0.0],
            radius / s,
            CURVED_WALL_ID,
        )),
        _ => None,
    };
    let mut container = ContainerStd::new(to_unit(&lo), to_unit(&hi), blocks, [false; 3]);
    if let Some(w) = cylinder.as_mut() {
        container.add_wall(w);
    }
    if let Some(w) = sphere.as_mut() {
        container.add_wall(w);
    }
    for (k, p) in seeds.iter().enumerate() {
        container.put(k as i32, to_unit(p), 0.0);
    }
    let mut cells: Vec<Option<VoronoiCell>> = vec![None; seeds.len()];
    let mut lp = LoopAll::of_container_std(&mut container);
    if lp.start() {
        loop {
            let id = lp.particle_id() as usize;
            let computed: Option<VoroCellNbr> = container.compute_cell(&mut lp);
            if let Some(mut c) = computed {
                cells[id] = Some(cell_from_voro(&mut c, &seeds[id], s)?);
            }
            if !lp.inc() {
                break;
            }
        }
    }
    Ok(cells)
}

#[cfg(feature = "voronoi")]
/// Converts a voro++ cell (computed in units of `s`, vertices relative to its seed).
fn cell_from_voro(c: &mut VoroCellNbr, seed: &Vec3, s: f64) -> Result<VoronoiCell, String> {
    let local = c.vertices_local();
    let vertices: Vec<Vec3> = local
        .chunks_exact(3)
        .map(|v| seed + Vec3::new(v[0], v[1], v[2]) * s)
        .collect();
    let flat = c.face_vertices();
    let ids = c.neighbors();
    let mut faces = Vec::with_capacity(ids.len());
    let mut k = 0;
    while k < flat.len() {
        let n = flat[k] as usize;
        faces.push(
            flat[k + 1..k + 1 + n]
                .iter()
                .map(|&v| v as u32)
                .collect::<Vec<u32>>(),
        );
        k += n + 1;
    }
    if faces.len() != ids.len() {
        return Err("voro++ gave faces and neighbours that do not match".to_string());
    }
    let polyhedron = Polyhedron::from_faces(vertices, &faces, seed);
    let mass = polyhedron.mass_properties();
    let mut cell_faces = Vec::with_capacity(ids.len());
    for (f, &id) in ids.iter().enumerate() {
        let FaceGeometry {
            area,
            normal,
            centroid,
        } = polyhedron.face_geometry(f);
        let neighbour = match id {
            id if id >= 0 => Neighbour::Cell(id as usize),
            CURVED_WALL_ID => Neighbour::Boundary(Boundary::Curved),
            id if (-6..=-1).contains(&id) => Neighbour::Boundary(BOX_FACES[(-1 - id) as usize]),
            other => return Err(format!("voro++ gave an unknown wall id {other}")),
        };
        cell_faces.push(CellFace {
            neighbour,
            area,
            normal,
            centroid,
        });
    }
    Ok(VoronoiCell {
        seed: *seed,
        polyhedron,
        volume: mass.volume,
        centroid: mass.centroid,
        inertia: mass.inertia,
        faces: cell_faces,
    })
}

/// Rigid bodies for `cells` of material `density` (kg/m³), in the same order. Each body's
/// mass is lumped at its seed, the point O_i of the lattice model (the line between two
/// seeds is normal to their shared face and cut by it halfway), with the cell's inertia
/// tensor about that point (parallel axes from the centroid); it is oriented along the
/// principal axes of that tensor, and its polyhedron is given in that principal frame,
/// relative to the seed.
pub fn elements(cells: &[VoronoiCell], density: f64) -> (Bodies, Vec<Polyhedron>) {
    let mut bodies = Bodies::default();
    let mut shapes = Vec::with_capacity(cells.len());
    for c in cells {
        let d = c.centroid - c.seed;
        let about_seed =
            c.inertia + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * c.volume;
        let (moments, q) = principal_axes(&about_seed);
        let shape = c
            .polyhedron
            .mapped(|v| q.inverse_transform_vector(&(v - c.seed)));
        let radius = shape.bounding_radius(&Vec3::zeros());
        bodies.push_polyhedron(c.seed, density * c.volume, moments * density, q, radius);
        shapes.push(shape);
    }
    (bodies, shapes)
}

/// How isotropic the contact (face) normals are: `second_order` is the Frobenius norm of
/// the deviator of ⟨n nᵀ⟩, and `fourth_order` the norm of ⟨n⊗n⊗n⊗n⟩ minus its value for
/// uniformly distributed normals, over the norm of the latter. Both are 0 for isotropic
/// normals; the fourth-order one also sees cubic order (0.816 for a cubic grid), which the
/// second-order one cannot. Each interior face counts once.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Fabric {
    pub faces: usize,
    pub second_order: f64,
    pub fourth_order: f64,
}

pub fn face_normal_fabric(cells: &[VoronoiCell]) -> Fabric {
    // The 15 distinct components of a symmetric 4th-order tensor as exponents (a, b, c) of
    // nx^a ny^b nz^c, with their multiplicities 4!/(a! b! c!).
    let mut exps = Vec::new();
    for a in 0..=4u32 {
        for b in 0..=(4 - a) {
            exps.push((a, b, 4 - a - b));
        }
    }
    let fact = |n: u32| (1..=n).product::<u32>().max(1) as f64;
    let mut m2 = Matrix3::zeros();
    let mut m4 = vec![0.0; exps.len()];
    let mut count = 0usize;
    for (i, cell) in cells.iter().enumerate() {
        for f in &cell.faces {
            if let Neighbour::Cell(j) = f.neighbour {
                if j > i {
                    let n = f.normal;
                    m2 += n * n.transpose();
                    for (k, &(a, b, c)) in exps.iter().enumerate() {
                        m4[k] += n.x.powi(a as i32) * n.y.powi(b as i32) * n.z.powi(c as i32);
                    }
                    count += 1;
                }
            }
        }
    }
    let w = 1.0 / count.max(1) as f64;
    m2 *= w;
    let dev = m2 - Matrix3::identity() * (m2.trace() / 3.0);
    // E[nx^a ny^b nz^c] for uniform unit vectors and a + b + c = 4: (a−1)!!(b−1)!!(c−1)!!/15
    // when all are even, else 0.
    let dfact = |n: u32| match n {
        0 | 1 => 1.0,
        2 => 1.0,
        4 => 3.0,
        _ => 0.0,
    };
    let (mut diff2, mut iso2) = (0.0, 0.0);
    for (k, &(a, b, c)) in exps.iter().enumerate() {
        let mult = fact(4) / (fact(a) * fact(b) * fact(c));
        let iso = if a % 2 == 0 && b % 2 == 0 && c % 2 == 0 {
            dfact(a) * dfact(b) * dfact(c) / 15.0
        } else {
            0.0
        };
        diff2 += mult * (m4[k] * w - iso).powi(2);
        iso2 += mult * iso * iso;
    }
    Fabric {
        faces: count,
        second_order: dev.norm(),
        fourth_order: (diff2 / iso2).sqrt(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::stream;

    fn cube() -> Domain {
        Domain::Box {
            lo: Vec3::zeros(),
            hi: Vec3::repeat(1.0),
        }
    }

    #[test]
    fn regular_grid_gives_cubes_with_six_faces() {
        let mut rng = stream(1, 9);
        let seeds = noisy_grid_seeds(&cube(), 64, 0.0, &mut rng);
        assert_eq!(seeds.len(), 64);
        let cells = tessellate(&seeds, &cube()).unwrap();
        for c in &cells {
            assert!((c.volume - 1.0 / 64.0).abs() < 1e-12);
            assert_eq!(c.faces.len(), 6);
            assert!((c.centroid - c.seed).norm() < 1e-12);
            let i = 1.0 / 64.0 * (2.0 * 0.0625) / 12.0;
            assert!((c.inertia - Matrix3::identity() * i).norm() < 1e-12);
            for f in &c.faces {
                assert!((f.area - 0.0625).abs() < 1e-12);
            }
        }
        // Cell 0 sits in the x-, y-, z- corner.
        let walls: Vec<Boundary> = cells[0]
            .faces
            .iter()
            .filter_map(|f| match f.neighbour {
                Neighbour::Boundary(b) => Some(b),
                _ => None,
            })
            .collect();
        for b in [Boundary::XMin, Boundary::YMin, Boundary::ZMin] {
            assert!(walls.contains(&b), "{walls:?}");
        }
        let fab = face_normal_fabric(&cells);
        assert!(fab.second_order < 1e-12);
        assert!((fab.fourth_order - (2.0f64 / 3.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn random_cells_fill_the_domain_and_agree_on_shared_faces() {
        let mut rng = stream(3, 9);
        let d = Domain::Cylinder {
            length: 1.0,
            radius: 0.2,
        };
        let seeds = noisy_grid_seeds(&d, 800, 0.9, &mut rng);
        let cells = tessellate(&seeds, &d).unwrap();
        let total: f64 = cells.iter().map(|c| c.volume).sum();
        // Tangent planes approximate the curved wall from outside.
        let rel = total / d.volume() - 1.0;
        assert!((0.0..0.05).contains(&rel), "volume off by {rel}");
        for (i, c) in cells.iter().enumerate() {
            assert!(c.volume > 0.0);
            // Closed surface: the vector areas cancel.
            let s: Vec3 = c.faces.iter().map(|f| f.normal * f.area).sum();
            assert!(s.norm() < 1e-10, "cell {i}: {s}");
            for f in &c.faces {
                if let Neighbour::Cell(j) = f.neighbour {
                    let curved = |c: &VoronoiCell| {
                        c.faces
                            .iter()
                            .any(|f| f.neighbour == Neighbour::Boundary(Boundary::Curved))
                    };
                    // Each cell is cut by its own tangent plane, so faces shared by two
                    // cells on the curved wall may differ (or exist on one side only, for a
                    // few millionths of the face area); elsewhere they are one face.
                    if curved(c) || curved(&cells[j]) {
                        continue;
                    }
                    let g = cells[j]
                        .faces
                        .iter()
                        .find(|g| g.neighbour == Neighbour::Cell(i))
                        .expect("neighbours are mutual");
                    assert!((f.area - g.area).abs() < 1e-9 * f.area.max(1e-3));
                    assert!((f.normal + g.normal).norm() < 1e-6);
                    // The face lies halfway between the seeds, normal to their line.
                    let dseed = cells[j].seed - c.seed;
                    assert!((dseed.normalize() - f.normal).norm() < 1e-6);
                    assert!(
                        ((f.centroid - c.seed).dot(&f.normal) - 0.5 * dseed.norm()).abs() < 1e-9
                    );
                }
            }
        }
    }
}
