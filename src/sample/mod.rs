//! Sample generators: random packings, lattices and packings read from files.
//!
//! Every generator gives bodies at rest and the walls of their container. Randomness comes
//! from the scene's seed only, one ChaCha8 stream per purpose, so a scene always gives the
//! same sample.

mod compaction;
mod import;
mod lattice;
// beam2d: the vectorizable random lattice of Voronoi polygons.
pub mod lattice2d;
mod random_pack;
pub mod voronoi;

use nalgebra::UnitQuaternion;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::scene::{GrainShape, Orientations, SampleKind, Scene};
use crate::shape::{PolyEllipsoid, sphere_volume};
use crate::state::{Bodies, Vec3, Walls};

pub use compaction::{CompactionReport, compact_to_pressure};
pub use import::{read_lammps_data, read_text_packing};
pub use lattice::{hcp_positions, simple_cubic_positions};
pub use random_pack::{PackReport, pack_geometric};

/// What a generator made, for the summary.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct SampleInfo {
    pub kind: String,
    pub count: usize,
    /// Box edge lengths at the start of loading (m).
    pub box_size: [f64; 3],
    /// Solid fraction at the start of loading.
    pub solid_fraction: f64,
    /// Steps of dynamic compaction (0 when none was needed).
    pub compaction_steps: u64,
}

/// Bodies, their container and what was made.
pub struct Sample {
    pub bodies: Bodies,
    pub walls: Walls,
    pub info: SampleInfo,
}

/// Random-number streams, one per purpose, all from the scene seed.
pub(crate) fn stream(seed: u64, purpose: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(purpose);
    rng
}

const STREAM_RADII: u64 = 1;
const STREAM_POSITIONS: u64 = 2;
const STREAM_ORIENTATIONS: u64 = 3;
const STREAM_SHAPES: u64 = 4;

/// `kind = "single"`: one grain of `semi_axes`, its shape frame aligned with the box (or
/// turned at random with `orientations = "random"`), resting on the bottom face, the top face
/// touching it, centred in the box's base.
fn single_grain(scene: &Scene, orient: &mut ChaCha8Rng) -> Result<(Bodies, Walls)> {
    let spec = &scene.sample;
    let semi = spec.semi_axes.expect("validated");
    let pe = PolyEllipsoid::new(semi).map_err(|m| scene.key_error("sample.semi_axes", m))?;
    let q = match spec.orientations.unwrap_or(Orientations::Aligned) {
        Orientations::Random => random_orientation(orient),
        Orientations::Aligned => UnitQuaternion::identity(),
    };
    let bx = spec.box_size.expect("validated");
    // Extent of the grain along z about its octant origin.
    let up = pe.support_value(&(q.inverse() * Vec3::z()));
    let down = pe.support_value(&(q.inverse() * -Vec3::z()));
    let origin = Vec3::new(0.5 * bx[0], 0.5 * bx[1], down);
    let mut b = Bodies::default();
    let rho = scene.material.density;
    if semi.iter().all(|&s| s == semi[0]) {
        b.push_sphere(origin, semi[0], rho, q);
    } else {
        b.push_poly_ellipsoid(pe, rho * pe.volume(), origin + q * pe.centroid(), q);
    }
    let hi = Vec3::new(bx[0], bx[1], up + down);
    Ok((b, Walls::new_box(Vec3::zeros(), hi)))
}

/// `shape = "poly_ellipsoid"`: each packed sphere of radius r becomes a poly-ellipsoid inside
/// it, its six semi-axes drawn uniformly in [r / aspect_ratio_max, r] (so that each axis ratio
/// lies between 1 and the maximum), its octant origin at the sphere's centre and its shape
/// frame the sphere's orientation.
fn poly_ellipsoids_in_spheres(scene: &Scene, spheres: &Bodies) -> Bodies {
    let aspect = scene.sample.aspect_ratio_max.unwrap_or(2.0);
    let mut rng = stream(scene.seed, STREAM_SHAPES);
    let rho = scene.material.density;
    let mut b = Bodies::default();
    for i in 0..spheres.len() {
        let r = spheres.radius[i];
        let semi = [(); 6].map(|_| r * (1.0 / aspect + (1.0 - 1.0 / aspect) * rng.random::<f64>()));
        let pe = PolyEllipsoid::new(semi).expect("positive semi-axes");
        let q = spheres.orientation[i];
        b.push_poly_ellipsoid(pe, rho * pe.volume(), spheres.pos[i] + q * pe.centroid(), q);
    }
    b
}

/// Builds the sample a scene describes. `progress` receives one-line notes on long stages.
pub fn build(scene: &Scene, progress: &mut (dyn FnMut(&str) + Send)) -> Result<Sample> {
    let spec = &scene.sample;
    let rho = scene.material.density;
    let mut orient = stream(scene.seed, STREAM_ORIENTATIONS);
    let (mut bodies, mut walls) = match spec.kind {
        SampleKind::Random => random_sample(scene, progress)?,
        SampleKind::SimpleCubic | SampleKind::Hcp => {
            let r = spec.radius_mean.expect("validated");
            let layers = spec.layers.expect("validated");
            let (pos, size) = if spec.kind == SampleKind::Hcp {
                hcp_positions(r, layers)
            } else {
                simple_cubic_positions(r, layers)
            };
            let mut b = Bodies::default();
            for p in pos {
                b.push_sphere(p, r, rho, UnitQuaternion::identity());
            }
            (b, Walls::new_box(Vec3::zeros(), size))
        }
        SampleKind::Text | SampleKind::LammpsData | SampleKind::YadeText => {
            let file = spec.file.as_deref().expect("validated");
            let path = scene.resolve(file);
            let packing = if spec.kind == SampleKind::LammpsData {
                read_lammps_data(&path)
            } else {
                read_text_packing(&path)
            }
            .map_err(|m| scene.key_error("sample.file", format!("= \"{file}\": {m}")))?;
            let mut b = Bodies::default();
            for (p, r) in packing.spheres {
                b.push_sphere(p, r, rho, UnitQuaternion::identity());
            }
            for (i, v) in packing.velocities {
                if i < b.len() {
                    b.vel[i] = v;
                }
            }
            // The file's own box first (docs/scenes.md): it is exact data, `box` a fallback.
            let (lo, hi) = match (packing.bounds, spec.box_size) {
                (Some(bounds), _) => bounds,
                (None, Some(size)) => (Vec3::zeros(), Vec3::from(size)),
                (None, None) => bounding_box(&b),
            };
            (b, Walls::new_box(lo, hi))
        }
        SampleKind::Single => single_grain(scene, &mut orient)?,
        SampleKind::VectorizableRandomLattice => {
            return Err(scene.key_error(
                "sample.kind",
                "= \"vectorizable_random_lattice\" makes 2D polygons for model.kind = \"beam2d\"; this builds sphere packings only",
            ));
        }
        SampleKind::VoronoiBox
        | SampleKind::VoronoiCylinder
        | SampleKind::VoronoiDisc
        | SampleKind::VoronoiBall => {
            return Err(scene.key_error(
                "sample.kind",
                format!(
                    "= \"{}\" is a dlsm sample, built by model.kind = \"dlsm\"",
                    spec.kind.as_str()
                ),
            ));
        }
    };
    let default_orientations = if spec.kind == SampleKind::Random {
        Orientations::Random
    } else {
        Orientations::Aligned
    };
    if spec.kind != SampleKind::Single
        && spec.orientations.unwrap_or(default_orientations) == Orientations::Random
    {
        for q in &mut bodies.orientation {
            *q = random_orientation(&mut orient);
        }
    }
    if spec.shape == Some(GrainShape::PolyEllipsoid) {
        bodies = poly_ellipsoids_in_spheres(scene, &bodies);
    }
    let mut compaction_steps = 0;
    if let Some(p) = spec.pressure {
        let mu = spec.compaction_friction.unwrap_or(scene.material.friction);
        let report = compact_to_pressure(&mut bodies, &mut walls, scene, p, mu, progress)?;
        compaction_steps = report.steps;
    }
    let size = walls.box_size();
    let info = SampleInfo {
        kind: spec.kind.as_str().to_string(),
        count: bodies.len(),
        box_size: size.into(),
        solid_fraction: bodies.solid_volume() / (size.x * size.y * size.z),
        compaction_steps,
    };
    Ok(Sample {
        bodies,
        walls,
        info,
    })
}

/// Radii from a normal distribution truncated to [min, max] by rejection.
pub fn truncated_normal_radii(
    rng: &mut ChaCha8Rng,
    mean: f64,
    sd: f64,
    min: f64,
    max: f64,
    mut keep_going: impl FnMut(usize, f64) -> bool,
) -> Vec<f64> {
    let mut radii = Vec::new();
    let mut volume = 0.0;
    let normal = (sd > 0.0).then(|| Normal::new(mean, sd).expect("sd > 0 is finite"));
    while keep_going(radii.len(), volume) {
        let r = match &normal {
            None => mean,
            Some(d) => loop {
                let r = d.sample(rng);
                if r >= min && r <= max {
                    break r;
                }
            },
        };
        volume += sphere_volume(r);
        radii.push(r);
    }
    radii
}

/// The radius bounds of a random sample: the scene's, or mean ± 3 sd (at least 1% of the
/// mean).
pub fn radius_bounds(scene: &Scene) -> (f64, f64, f64, f64) {
    let s = &scene.sample;
    let mean = s.radius_mean.expect("validated");
    let sd = s.radius_sd.unwrap_or(0.0);
    let min = s.radius_min.unwrap_or((mean - 3.0 * sd).max(0.01 * mean));
    let max = s.radius_max.unwrap_or(mean + 3.0 * sd);
    (mean, sd, min, max)
}

fn random_sample(
    scene: &Scene,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<(Bodies, Walls)> {
    let s = &scene.sample;
    let (mean, sd, min, max) = radius_bounds(scene);
    let mut size = Vec3::from(s.box_size.expect("validated"));
    let box_volume = size.x * size.y * size.z;
    let mut rng = stream(scene.seed, STREAM_RADII);
    let radii = match (s.count, s.solid_fraction) {
        (Some(n), _) => truncated_normal_radii(&mut rng, mean, sd, min, max, |k, _| k < n),
        (None, Some(phi)) => {
            truncated_normal_radii(&mut rng, mean, sd, min, max, |_, v| v < phi * box_volume)
        }
        (None, None) => unreachable!("validated: count or solid_fraction"),
    };
    let solid: f64 = radii.iter().map(|&r| sphere_volume(r)).sum();
    if let (Some(_), Some(phi)) = (s.count, s.solid_fraction) {
        // Both a count and a fraction: keep the box's shape, scale it to the fraction.
        size *= (solid / phi / box_volume).cbrt();
    }
    let phi = solid / (size.x * size.y * size.z);
    if phi > 0.65 {
        return Err(scene.key_error(
            "sample.count",
            format!(
                "gives a solid fraction of {phi:.3} in the box, above the 0.65 a random packing can reach; lower sample.count or enlarge sample.box"
            ),
        ));
    }
    let rmax = radii.iter().copied().fold(0.0, f64::max);
    if (0..3).any(|a| size[a] <= 2.0 * rmax) {
        return Err(scene.key_error(
            "sample.box",
            format!(
                "is too small for the largest sphere (radius {rmax:e} m): each edge must exceed its diameter"
            ),
        ));
    }
    progress(&format!(
        "packing {} spheres at solid fraction {phi:.3}",
        radii.len()
    ));
    let mut prng = stream(scene.seed, STREAM_POSITIONS);
    let (pos, report) = pack_geometric(&radii, Vec3::zeros(), size, &mut prng)
        .map_err(|m| scene.key_error("sample.solid_fraction", m))?;
    progress(&format!(
        "packed in {} relaxation sweeps, largest overlap {:.2e} of a radius",
        report.sweeps, report.max_overlap
    ));
    let mut b = Bodies::default();
    for (p, r) in pos.into_iter().zip(radii) {
        b.push_sphere(p, r, scene.material.density, UnitQuaternion::identity());
    }
    // Random indices would scatter neighbours over memory: number the spheres by position.
    let order = b.spatial_order(2.0 * rmax);
    b.reorder(&order);
    Ok((b, Walls::new_box(Vec3::zeros(), size)))
}

/// A uniformly distributed rotation (Shoemake's method).
pub fn random_orientation(rng: &mut ChaCha8Rng) -> UnitQuaternion<f64> {
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let tau = std::f64::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let q = nalgebra::Quaternion::new(
        b * (tau * u3).cos(),
        a * (tau * u2).sin(),
        a * (tau * u2).cos(),
        b * (tau * u3).sin(),
    );
    UnitQuaternion::from_quaternion(q)
}

fn bounding_box(b: &Bodies) -> (Vec3, Vec3) {
    let mut lo = Vec3::repeat(f64::INFINITY);
    let mut hi = Vec3::repeat(f64::NEG_INFINITY);
    for (p, &r) in b.pos.iter().zip(&b.radius) {
        lo = lo.inf(&(p - Vec3::repeat(r)));
        hi = hi.sup(&(p + Vec3::repeat(r)));
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn truncated_normal_stays_in_bounds_with_right_mean() {
        let mut rng = stream(7, STREAM_RADII);
        let r =
            truncated_normal_radii(&mut rng, 0.3e-3, 0.05e-3, 0.1e-3, 0.45e-3, |k, _| k < 20000);
        assert!(r.iter().all(|&x| (0.1e-3..=0.45e-3).contains(&x)));
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        // Symmetric truncation at +-3 sd keeps the mean; 20000 draws: sd of mean 3.5e-7.
        assert!((mean - 0.3e-3).abs() < 1.5e-6, "{mean}");
        let var = r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / r.len() as f64;
        assert!((var.sqrt() - 0.05e-3).abs() < 2e-6);
    }
}
