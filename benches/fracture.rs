//! `cargo bench --bench fracture`: (1) particle-steps per second for 1000 poly-ellipsoids
//! (axis ratios 1 to 2) in a dense packing, on 1 and 2 threads; (2) wall seconds per 1% of
//! axial strain of the SHPB scene (scenes/shpb_sand.toml to 2% strain) on 1 and 2 threads,
//! and the particle count after fracture. Prints, asserts nothing.

use std::path::Path;

fn main() {
    let cache = fractum::bench::default_cache();
    let mut note = |m: &str| eprintln!("{m}");
    println!("| poly-ellipsoids | threads | contacts | steps | wall s | particle-steps/s |");
    println!("|---:|---:|---:|---:|---:|---:|");
    for threads in [1, 2] {
        match fractum::bench::time_poly_ellipsoid_case(1000, threads, 2000, &cache, &mut note) {
            Ok(c) => println!(
                "| {} | {} | {} | {} | {:.3} | {:.3e} |",
                c.bodies,
                c.threads,
                c.contacts,
                c.steps,
                c.seconds,
                c.particle_steps_per_second()
            ),
            Err(e) => eprintln!("error: {e}"),
        }
    }
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/shpb_sand.toml");
    let overrides = [
        "loading.end_strain=0.02".to_string(),
        "output.vtk=0".to_string(),
    ];
    println!();
    println!("| SHPB scene | threads | wall s per 1% strain | grains | bodies at 2% strain |");
    println!("|---|---:|---:|---:|---:|");
    for threads in [1, 2] {
        match fractum::bench::time_shpb(&scene, &overrides, threads) {
            Ok((per_percent, grains, bodies)) => {
                println!("| shpb_sand to 2% | {threads} | {per_percent:.2} | {grains} | {bodies} |")
            }
            Err(e) => eprintln!("error: {e}"),
        }
    }
}
