//! `cargo bench --bench frequency_bound`: what sets the step of a fracture run. Runs the main
//! job (scenes/shpb_sand.toml, one thread) to `FRACTUM_BOUND_STRAIN` (default 0.1) and prints,
//! every 2000 steps, the bound on the highest contact frequency that the step adapts to
//! (`records_max_frequency`) against the highest frequency computed by power iteration over
//! the same contacts (`records_highest_frequency`, 300 iterations, approaching from below), the
//! body that moves most in that mode and how much of its motion is translation. Asserts
//! nothing (docs/performance.md: "What sets the step after splits").

use std::path::Path;

use fractum::contact::records::{
    records_highest_frequency, records_max_frequency, tangential_ratio,
};
use fractum::models::granular::Simulation;
use fractum::shape::Shape;
use fractum::{Run, Scene};

fn main() {
    let strain: f64 = std::env::var("FRACTUM_BOUND_STRAIN")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.1);
    let set = vec![
        format!("loading.end_strain={strain}"),
        "output.vtk=0".to_string(),
    ];
    let scene = Scene::load(Path::new("scenes/shpb_sand.toml"), &set).unwrap();
    let mut sim = Simulation::new(scene, 1, &mut |_| {}).unwrap();
    // The Mindlin tangential stiffness over the normal, as the run's own bound reads it.
    let k = fractum::models::granular::contact_params(&sim.scene, &sim.model.cfg, None);
    let t = k.mindlin.map_or(0.0, |m| {
        tangential_ratio(8.0 * m.g_eff, 2.0 * k.hertz.e_eff)
    });
    println!(
        "| step | bodies | dt (ns) | bound ω (rad/s) | computed ω | bound / computed | bound ω dt | computed ω dt | mode body: shape, translation share |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---|");
    while !sim.finished() {
        sim.advance(2000).unwrap();
        let Some(records) = sim.model.pipeline.records() else {
            continue;
        };
        let b = &sim.model.state.bodies;
        let bound = records_max_frequency(&records.list, b, t);
        let (computed, at, lin) = records_highest_frequency(&records.list, b, t, 300);
        let shape = match &b.shape[at] {
            Shape::PolyEllipsoid { pe, .. } => {
                let s = pe.semi.map(|x| (x * 1e6).round());
                format!("poly-ellipsoid {s:?} µm")
            }
            _ => format!("sphere r {:.0} µm", b.radius[at] * 1e6),
        };
        let dt = sim.dt();
        println!(
            "| {} | {} | {:.2} | {bound:.3e} | {computed:.3e} | {:.2} | {:.2} | {:.2} | {shape}, {lin:.2} |",
            sim.clock.step,
            b.len(),
            dt * 1e9,
            bound / computed,
            bound * dt,
            computed * dt
        );
    }
}
