//! `cargo bench --bench throughput`: particle-steps per second on dense 1000- and 8000-sphere
//! packings with 1 and 2 threads (the same code as `fractum bench`). Prints, asserts nothing.

fn main() {
    let cache = fractum::models::granular::bench::default_cache();
    let mut note = |m: &str| eprintln!("{m}");
    match fractum::models::granular::bench::run(&[1000, 8000], &[1, 2], 3000, &cache, &mut note) {
        Ok(cases) => println!("{}", fractum::bench::table("particle", &cases)),
        Err(e) => eprintln!("error: {e}"),
    }
}
