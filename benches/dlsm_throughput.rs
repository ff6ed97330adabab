//! `cargo bench --bench dlsm_throughput`: element-steps per second of the dlsm model on a
//! 20,000-element Voronoi cube with 1 and 2 threads. Prints, asserts nothing.

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![20_000]
    } else {
        sizes
    };
    match fractum::models::dlsm::bench::run(&sizes, &[1, 2], 500) {
        Ok(cases) => println!("{}", fractum::bench::table("element", &cases)),
        Err(e) => eprintln!("error: {e}"),
    }
}
