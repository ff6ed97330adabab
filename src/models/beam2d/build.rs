//! Building a beam2d sample: the lattice, the beams between its polygons, the force pipeline
//! and the critical step.

use super::*;

/// The lattice a beam2d scene describes.
pub(super) fn lattice(scene: &Scene, cfg: &Beam2dScene) -> Result<PolygonSample> {
    let p = &cfg.sample;
    let spec = LatticeSpec {
        spacing: p.spacing,
        disorder: p.disorder,
        shape: p.shape,
        thickness: p.thickness,
        density: cfg.material.density,
    };
    let mut rng = crate::sample::stream(scene.seed, STREAM_LATTICE);
    vectorizable_random_lattice(&spec, &mut rng).map_err(|m| scene.key_error("sample", m))
}

/// The force pipeline of a beam2d scene on its polygons and beams.
pub(super) fn polygon_pipeline(
    scene: &Scene,
    cfg: &Beam2dScene,
    st: &Beam2dState,
) -> PolygonPipeline {
    let skin = cfg.neighbor.skin.unwrap_or(0.3 * st.info.spacing);
    PolygonPipeline::build(scene, cfg, &st.polygons, &st.beams, skin)
}

/// The beams over the sample's shared sides (only with the `beams` effect); none to a free
/// projectile.
pub(super) fn make_beams(
    cfg: &Beam2dScene,
    sample: &PolygonSample,
    loading: &Beam2dLoading,
) -> Beams {
    let mut beams = Beams::default();
    // Present exactly with the `beams` effect.
    let Some(material) = cfg.material.beams else {
        return beams;
    };
    let young = material.young;
    let t = sample.info.thickness;
    let p = &sample.polygons;
    let loose = loading.as_loading().loose_polygon();
    for s in &sample.sides {
        let (i, j) = (s.i as usize, s.j as usize);
        if loose.is_some_and(|k| k == i || k == j) {
            continue;
        }
        beams.push([i, j], [p.centre(i), p.centre(j)], s.length, t, young);
    }
    beams
}

/// Velocity Verlet's stability limit 2/ω for the stiffest polygon, with
/// `ω² = 2 Σ k / m` over its beams (axial plus shear stiffness) and contacts across its sides
/// (`Y t S / Lc`), and likewise for rotation.
pub(super) fn critical_time_step(
    scene: &Scene,
    cfg: &Beam2dScene,
    sample: &PolygonSample,
    beams: &Beams,
) -> f64 {
    let p = &sample.polygons;
    let n = p.len();
    let (mut kt, mut kr) = (vec![0.0; n], vec![0.0; n]);
    for b in 0..beams.len() {
        let l = beams.rest_length[b];
        // β l0² = 2 (bend_own + bend_cross): the shear stiffness β.
        let beta = 2.0 * (beams.bend_own[b] + beams.bend_cross[b]) / (l * l);
        let rot = beams.bend_own[b] + beams.bend_cross[b].abs();
        for k in [beams.i[b] as usize, beams.j[b] as usize] {
            kt[k] += beams.alpha[b] + beta;
            kr[k] += rot;
        }
    }
    if scene.has_effect(EffectKind::Contact) {
        let yt = cfg.material.young * sample.info.thickness;
        for s in &sample.sides {
            let (i, j) = (s.i as usize, s.j as usize);
            let k = yt * s.length
                / characteristic_length(p.equivalent_diameter[i], p.equivalent_diameter[j]);
            for m in [i, j] {
                kt[m] += k;
                kr[m] += k * s.length * s.length / 12.0;
            }
        }
    }
    let mut omega: f64 = 0.0;
    for k in 0..n {
        omega = omega
            .max((2.0 * kt[k] / p.mass[k]).sqrt())
            .max((2.0 * kr[k] / p.inertia[k]).sqrt());
    }
    if omega > 0.0 {
        2.0 / omega
    } else {
        f64::INFINITY
    }
}
