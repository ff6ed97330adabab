//! `fractum explain` for a beam2d scene.

use std::fmt::Write as _;

use super::pipeline::PolygonPipeline;
use super::scene::{Beam2dScene, EFFECTS};
use crate::bond::beam2d::Beams;
use crate::error::Result;
use crate::explain::write_pipeline;
use crate::sample::lattice2d::LatticeShape;
use crate::scene::{IntegratorKind, Scene};
use crate::state::polygons::Polygons;

/// `fractum explain` for a beam2d scene: what it builds, without building the lattice.
pub fn explain(scene: &Scene, cfg: &Beam2dScene) -> Result<String> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "scene {} (\"{}\"), seed {}",
        scene.source.label, scene.name, scene.seed
    );
    let _ = writeln!(
        s,
        "model: beam2d, rigid Voronoi polygons with overlap repulsion and breakable beams (2D, plane stress)"
    );
    let p = &cfg.sample;
    let spacing = p.spacing;
    let outline = match p.shape {
        LatticeShape::Rectangle(c) => {
            format!(
                "a {} x {} m rectangle ({} x {} squares)",
                c[0] as f64 * spacing,
                c[1] as f64 * spacing,
                c[0],
                c[1]
            )
        }
        LatticeShape::Disc(d) => format!(
            "a disc of diameter {} m (about {:.0} polygons)",
            d,
            std::f64::consts::PI / 4.0 * (d / spacing).powi(2)
        ),
    };
    let _ = writeln!(
        s,
        "sample: vectorizable random lattice, spacing {spacing:e} m, disorder {:e} m, cut to {outline}, thickness {:e} m",
        p.disorder, p.thickness
    );
    let pipeline = PolygonPipeline::build(scene, cfg, &Polygons::default(), &Beams::default(), 0.0);
    write_pipeline(
        &mut s,
        scene,
        &pipeline.describe(),
        &EFFECTS,
        "polygons move freely",
    );
    let _ = writeln!(
        s,
        "loading: {}",
        super::loading::Beam2dLoading::describe(&cfg.loading)
    );
    let dt = scene
        .time
        .describe_step("the estimated stability limit 2/omega of the stiffest polygon");
    let integrator = match scene.time.integrator {
        IntegratorKind::Gear5 => "Gear fifth-order predictor-corrector",
        _ => "velocity Verlet",
    };
    crate::explain::write_integrator(&mut s, integrator, &dt);
    crate::explain::write_outputs(
        &mut s,
        scene,
        Some("polygons, beams, broken_beams"),
        "summary.json, fragments.csv and fragment_histogram.csv",
    );
    Ok(s)
}
