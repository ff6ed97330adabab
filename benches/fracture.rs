//! `cargo bench --bench fracture`: (1) particle-steps per second for 1000 poly-ellipsoids
//! (axis ratios 1 to 2) in a dense packing (compacted to 100 kPa), on 1 and 2 threads; (2) wall seconds per 1% of
//! axial strain of the SHPB scene (scenes/shpb_sand.toml to 2% strain) on 1 and 2 threads,
//! and the particle count after fracture. Prints, asserts nothing.

use std::path::Path;

fn main() {
    let mut note = |m: &str| eprintln!("{m}");
    let mut cases = Vec::new();
    match fractum::models::granular::bench::dense_poly_ellipsoids(1000, &mut note) {
        Ok((scene, sample)) => {
            for threads in [1, 2] {
                match fractum::models::granular::bench::time_poly_ellipsoid_case(
                    &scene, &sample, threads, 2000,
                ) {
                    Ok(c) => cases.push(c),
                    Err(e) => eprintln!("error: {e}"),
                }
            }
        }
        Err(e) => eprintln!("error: {e}"),
    }
    println!(
        "poly-ellipsoids, axis ratios 1 to 2:\n{}",
        fractum::bench::table("particle", &cases)
    );
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/shpb_sand.toml");
    let overrides = [
        "loading.end_strain=0.02".to_string(),
        "output.vtk=0".to_string(),
    ];
    println!();
    println!("| SHPB scene | threads | wall s per 1% strain | grains | bodies at 2% strain |");
    println!("|---|---:|---:|---:|---:|");
    for threads in [1, 2] {
        match fractum::models::granular::bench::time_shpb(&scene, &overrides, threads) {
            Ok((per_percent, grains, bodies)) => {
                println!("| shpb_sand to 2% | {threads} | {per_percent:.2} | {grains} | {bodies} |")
            }
            Err(e) => eprintln!("error: {e}"),
        }
    }
}
