//! Throughput of the dlsm model: element-steps per second on a Voronoi box, for
//! `cargo bench --bench dlsm_throughput`. Prints figures, asserts nothing.

use std::path::Path;
use std::time::Instant;

use super::DlsmRun;
use crate::bench::Timed;
use crate::error::Result;
use crate::scene::Scene;

/// The benchmark scene: a 1 m cube of `elements` cells (noisy grid, d = 0.9), E = 20 GPa,
/// ν = 0.25, the cohesive lattice alone (no effect, no loading), Tchamwa–Wielgosz φ = 2.
fn scene_text(elements: usize) -> String {
    format!(
        r#"
name = "dlsm_bench_{elements}"
seed = 7
effects = []
[model]
kind = "dlsm"
[material]
young = 20e9
poisson = 0.25
density = 1000.0
[sample]
kind = "voronoi_box"
length = 1.0
elements = {elements}
method = "noisy_grid"
noise = 0.9
[loading]
kind = "none"
end_time = 1.0
[time]
safety = 0.33
integrator = "tchamwa_wielgosz"
phi = 2.0
[output]
every = 1000000000
"#
    )
}

/// One timed case.
/// Times `steps` steps (after 20 warm-up steps) for every element count and thread count.
pub fn run(elements: &[usize], threads: &[usize], steps: u64) -> Result<Vec<Timed>> {
    let mut cases = Vec::new();
    for &n in elements {
        let scene = Scene::from_toml(&scene_text(n), "dlsm_bench", Path::new("."), &[])?;
        for &t in threads {
            let mut run = DlsmRun::new(scene.clone(), t, &mut |_| {})?;
            // A small random shake so that the lattice is strained and moving.
            for (k, v) in run.model.state.bodies.vel.iter_mut().enumerate() {
                *v = crate::state::Vec3::new(
                    ((k * 7919) % 101) as f64 - 50.0,
                    ((k * 104729) % 103) as f64 - 51.0,
                    ((k * 1299709) % 107) as f64 - 53.0,
                ) * 1e-4;
            }
            run.advance(20)?;
            let start = Instant::now();
            run.advance(steps)?;
            cases.push(Timed {
                case: format!("lattice of {n} elements"),
                bodies: run.model.state.bodies.len(),
                contacts: Some(run.model.bonds.contacts()),
                threads: t,
                steps,
                seconds: start.elapsed().as_secs_f64(),
            });
        }
    }
    Ok(cases)
}
