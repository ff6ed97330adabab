//! The Voronoi sample a dlsm scene describes: domain, seeds, cells, elements and bonds.

use serde::{Deserialize, Serialize};

use super::scene::{DlsmScene, LoadingSpec, SampleShape, Seeds};
use crate::bond::dlsm::DlsmBonds;
use crate::error::Result;
use crate::sample::stream;
use crate::sample::voronoi::{
    Boundary, Domain, Fabric, Neighbour, elements, face_normal_fabric, noisy_grid_seeds,
    packing_seeds, tessellate,
};
use crate::scene::Scene;
use crate::shape::polyhedron::Polyhedron;
use crate::state::{Bodies, Vec3};

/// The random stream of Voronoi seeds.
const STREAM_SEEDS: u64 = 4;

/// Default noise of the noisy grid: the paper's "correct level of geometrical isotropy".
pub const DEFAULT_NOISE: f64 = 0.9;
/// Default radius dispersion of the packing method.
pub const DEFAULT_DISPERSION: f64 = 0.25;

/// A face of an element on the domain's boundary.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct BoundaryFace {
    pub element: u32,
    pub boundary: Boundary,
    pub area: f64,
    pub centroid: Vec3,
}

/// What was made, for summary.json.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DlsmSampleInfo {
    pub kind: String,
    pub method: String,
    /// Noise d (noisy grid) or radius dispersion δ (packing).
    pub randomness: f64,
    pub elements: usize,
    pub contacts: usize,
    /// Total volume of the cells (m³) and that of the exact domain.
    pub volume: f64,
    pub domain_volume: f64,
    /// Cube root of the mean cell volume (m).
    pub element_size: f64,
    pub mean_neighbours: f64,
    pub fabric: Fabric,
}

pub struct DlsmSample {
    pub domain: Domain,
    pub bodies: Bodies,
    /// Element shapes in their principal frames, relative to the centroid.
    pub shapes: Vec<Polyhedron>,
    /// Initial seeds (m).
    pub seeds: Vec<Vec3>,
    pub bonds: DlsmBonds,
    pub boundary: Vec<BoundaryFace>,
    pub info: DlsmSampleInfo,
}

/// The domain of a Voronoi sample.
pub fn domain(cfg: &DlsmScene) -> Domain {
    match cfg.sample.shape {
        SampleShape::Cylinder { length, radius } => Domain::Cylinder {
            length: length + clamp_grip(cfg, length, radius),
            radius,
        },
        SampleShape::Disc {
            diameter,
            thickness,
        } => Domain::Disc {
            diameter,
            thickness,
        },
        SampleShape::Ball { radius } => Domain::Ball { radius },
        SampleShape::Box { size } => Domain::Box {
            lo: Vec3::zeros(),
            hi: Vec3::from(size),
        },
    }
}

/// A clamped cylinder (free vibration) is held by its elements on x−, whose seeds lie about
/// half an element inside: the cylinder is made this much longer (half the mean element
/// size) and then shifted so that the held seeds sit on x = 0, where the clamped section of
/// a bar of length `sample.length` is.
fn clamp_grip(cfg: &DlsmScene, length: f64, radius: f64) -> f64 {
    if !matches!(cfg.loading, LoadingSpec::FreeVibration(_)) {
        return 0.0;
    }
    let n = cfg.sample.elements as f64;
    0.5 * (std::f64::consts::PI * radius * radius * length / n).cbrt()
}

/// Builds the sample of a dlsm scene.
pub fn build(
    scene: &Scene,
    cfg: &DlsmScene,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<DlsmSample> {
    let p = &cfg.sample;
    let domain = domain(cfg);
    let n = p.elements;
    let mut rng = stream(scene.seed, STREAM_SEEDS);
    let (seeds, randomness) = match p.seeds {
        Seeds::Grid => (noisy_grid_seeds(&domain, n, 0.0, &mut rng), 0.0),
        Seeds::NoisyGrid { noise: d } => (noisy_grid_seeds(&domain, n, d, &mut rng), d),
        Seeds::Packing {
            radius_dispersion: delta,
        } => {
            progress(&format!(
                "packing about {n} spheres (radius dispersion {delta}) for the Voronoi seeds"
            ));
            let seeds = packing_seeds(&domain, n, delta, &mut rng)
                .map_err(|m| scene.key_error("sample.elements", format!("= {n} {m}")))?;
            (seeds, delta)
        }
    };
    if seeds.len() < 8 {
        return Err(scene.key_error(
            "sample.elements",
            format!(
                "= {n} gives {} seeds in the domain; ask for more elements",
                seeds.len()
            ),
        ));
    }
    progress(&format!("tessellating {} Voronoi cells", seeds.len()));
    let mut cells = tessellate(&seeds, &domain)
        .map_err(|m| scene.key_error("sample", format!("cannot be tessellated: {m}")))?;
    let mut seeds = seeds;
    if let LoadingSpec::FreeVibration(_) = cfg.loading {
        let held: Vec<f64> = cells
            .iter()
            .filter(|c| {
                c.faces
                    .iter()
                    .any(|f| f.neighbour == Neighbour::Boundary(Boundary::XMin))
            })
            .map(|c| c.seed.x)
            .collect();
        let shift = Vec3::new(
            -held.iter().sum::<f64>() / held.len().max(1) as f64,
            0.0,
            0.0,
        );
        for c in &mut cells {
            c.translate(&shift);
        }
        for p in &mut seeds {
            *p += shift;
        }
    }
    let m = &cfg.material;
    let (bodies, shapes) = elements(&cells, m.density);
    let mut bonds = DlsmBonds::from_cells(&cells, &bodies, m.young, m.poisson);
    bonds.strain_measure = m.strain_measure.unwrap_or_default();
    let mut boundary = Vec::new();
    for (i, c) in cells.iter().enumerate() {
        for f in &c.faces {
            if let Neighbour::Boundary(b) = f.neighbour {
                boundary.push(BoundaryFace {
                    element: i as u32,
                    boundary: b,
                    area: f.area,
                    centroid: f.centroid,
                });
            }
        }
    }
    let volume: f64 = cells.iter().map(|c| c.volume).sum();
    let info = DlsmSampleInfo {
        kind: p.kind().as_str().to_string(),
        method: p.seeds.method().as_str().to_string(),
        randomness,
        elements: cells.len(),
        contacts: bonds.contacts(),
        volume,
        domain_volume: domain.volume(),
        element_size: (volume / cells.len() as f64).cbrt(),
        mean_neighbours: 2.0 * bonds.contacts() as f64 / cells.len() as f64,
        fabric: face_normal_fabric(&cells),
    };
    Ok(DlsmSample {
        domain,
        bodies,
        shapes,
        seeds,
        bonds,
        boundary,
        info,
    })
}

impl DlsmSample {
    /// The elements with a face on `b`, in index order.
    pub fn elements_on(&self, b: Boundary) -> Vec<u32> {
        let mut v: Vec<u32> = self
            .boundary
            .iter()
            .filter(|f| f.boundary == b)
            .map(|f| f.element)
            .collect();
        v.dedup();
        v
    }
}
