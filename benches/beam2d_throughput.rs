//! `cargo bench --bench beam2d_throughput`: polygon-steps per second of whole runs of
//! scenes/explosion_disc.toml and scenes/impact_block.toml (seed 1, to their stop after 300
//! steps without a break) on 1 and 2 threads; then what the time step costs: the energy error
//! of the beams-only explosion after 2 ms against the time step and the wall time, for Gear's
//! predictor-corrector and velocity Verlet. Prints tables, asserts nothing.

use std::path::PathBuf;
use std::time::Instant;

use fractum::Scene;
use fractum::bench::{Timed, table};
use fractum::models::beam2d::Beam2dRun;
use fractum::models::beam2d::bench::time_beam2d_scene;

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn main() {
    let mut cases: Vec<Timed> = Vec::new();
    for file in ["explosion_disc.toml", "impact_block.toml"] {
        for threads in [1, 2] {
            match time_beam2d_scene(&scenes().join(file), &[], threads) {
                Ok(c) => {
                    eprintln!(
                        "{} on {} thread(s): {:.3e} polygon-steps/s",
                        c.case,
                        c.threads,
                        c.body_steps_per_second()
                    );
                    cases.push(c);
                }
                Err(e) => eprintln!("error: {e}"),
            }
        }
    }
    println!("{}", table("polygon", &cases));
    println!("{}", accuracy_table());
}

/// Energy error |E(2 ms) − E0| / E0 of the beams-only explosion (no contacts, damping or
/// breaking: the beams have an energy, so it is conserved) against the time step.
fn accuracy_table() -> String {
    let mut s = String::from(
        "| integrator | dt (s) | steps | energy error | wall s |\n|---|---:|---:|---:|---:|\n",
    );
    for integrator in ["gear5", "velocity_verlet"] {
        for dt in [4e-6, 2e-6, 1e-6, 5e-7, 2.5e-7] {
            let overrides: Vec<String> = [
                "effects=[\"beams\"]".to_string(),
                "loading.quiet_steps=100000000".into(),
                "loading.end_time=0.002".into(),
                format!("time.dt={dt:e}"),
                format!("time.integrator=\"{integrator}\""),
            ]
            .into();
            let scene = match Scene::load(&scenes().join("explosion_disc.toml"), &overrides) {
                Ok(s) => s,
                Err(e) => return format!("error: {e}"),
            };
            let Ok(mut run) = Beam2dRun::new(scene, 1, &mut |_| {}) else {
                return "error: the run could not be set up".into();
            };
            let e0 = run.model.state.polygons.kinetic_energy() + run.model.beam_energy();
            let start = Instant::now();
            let ok = (|| {
                while !run.finished() {
                    run.advance(1000)?;
                }
                Ok::<(), fractum::Error>(())
            })();
            let wall = start.elapsed().as_secs_f64();
            let error = match ok {
                Ok(()) => format!(
                    "{:.2e}",
                    ((run.model.state.polygons.kinetic_energy() + run.model.beam_energy()) / e0
                        - 1.0)
                        .abs()
                ),
                Err(_) => "unstable".into(),
            };
            s.push_str(&format!(
                "| {integrator} | {dt:e} | {} | {error} | {wall:.3} |\n",
                run.clock.step
            ));
        }
    }
    s
}
