//! Sample generators: random packings, lattices, Voronoi tessellations and packings read
//! from files. Each model's `sample` module turns its scene's keys into calls of these.
//!
//! Every generator gives bodies at rest and the walls of their container. Randomness comes
//! from the scene's seed only, one ChaCha8 stream per purpose, so a scene always gives the
//! same sample.

mod compaction;
mod import;
mod jammed;
mod lattice;
// beam2d: the vectorizable random lattice of Voronoi polygons.
pub mod lattice2d;
mod random_pack;
pub mod voronoi;

use nalgebra::UnitQuaternion;
use rand::distr::OpenClosed01;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

use crate::shape::sphere_volume;
use crate::state::{Bodies, Vec3, Walls};

pub use compaction::{
    CompactionReport, CompactionSpec, FractionJammed, FractionSpec, PREPARATION_PART_ROWS,
    compact_to_fraction, compact_to_pressure,
};
pub use import::{
    ELLIPSOID_COLUMNS, EllipsoidGrain, GRAIN_ASPECT_MAX, check_assembly_overlaps,
    read_ellipsoid_assembly, read_lammps_data, read_text_packing,
};
pub use jammed::{
    FRACTION_TOLERANCE, JAM_PER_MODULUS, JammedReport, JammedShort, JammedSpec, compact_jammed,
};
pub use lattice::{hcp_positions, simple_cubic_positions};

pub use random_pack::{PackReport, pack_geometric, pack_geometric_in_sleeve};

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

/// The revision of the preparations (placement, compaction, the jammed protocol): raised with
/// every change that changes the samples they make, so that samples kept by a cache
/// (`FRACTUM_SAMPLE_CACHE`) are made again rather than read back from an older protocol.
pub const PREPARATION_REVISION: u32 = 6;

/// Random-number streams, one per purpose, all from the scene seed.
pub(crate) fn stream(seed: u64, purpose: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(purpose);
    rng
}

/// Counters of [`uniforms`] run below this: 2³⁶ windows of 2³² words fill ChaCha's 68-bit
/// word position.
pub const UNIFORM_COUNTERS: u64 = 1 << 36;

/// At most this many variates per (seed, key, counter) window: 2³¹, two 32-bit words each.
pub const UNIFORMS_PER_COUNTER: usize = 1 << 31;

/// Fills `out` with uniform variates in (0, 1] (53 random bits each, `rand`'s `OpenClosed01`)
/// from the ChaCha8 generator of `seed` (seeded as the scene's streams are) on stream `key`,
/// from word `counter × 2³²` on. The same (seed, key, counter) always gives the same numbers,
/// whoever draws them: a host can key a grain's draws by its identity and count them by its
/// splits, independently of how the grains are spread over processes.
///
/// # Panics
/// When `counter >= UNIFORM_COUNTERS` or `out` is longer than `UNIFORMS_PER_COUNTER`.
pub fn uniforms(seed: u64, key: u64, counter: u64, out: &mut [f64]) {
    assert!(
        counter < UNIFORM_COUNTERS && out.len() <= UNIFORMS_PER_COUNTER,
        "uniforms: counter {counter} or count {} out of range",
        out.len()
    );
    let mut rng = stream(seed, key);
    rng.set_word_pos(u128::from(counter) << 32);
    for x in out {
        *x = rng.sample(OpenClosed01);
    }
}

pub(crate) const STREAM_RADII: u64 = 1;
pub(crate) const STREAM_POSITIONS: u64 = 2;
pub(crate) const STREAM_ORIENTATIONS: u64 = 3;
pub(crate) const STREAM_SHAPES: u64 = 4;

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

pub(crate) fn bounding_box(b: &Bodies) -> (Vec3, Vec3) {
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
