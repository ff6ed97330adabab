//! Prints the damping coefficient c(e) of the exact Hertz restitution mapping next to the
//! linear-spring closed form 2·sqrt(5/6)·β and the restitution that closed form really gives.
use fractum::contact::restitution::{damping_for_restitution, restitution_of};

fn main() {
    println!("| e requested | c (exact) | c closed form | e given by closed form |");
    println!("|---:|---:|---:|---:|");
    for e in [0.1_f64, 0.3, 0.5, 0.7, 0.9] {
        let beta = -e.ln() / (e.ln().powi(2) + std::f64::consts::PI.powi(2)).sqrt();
        let closed = 2.0 * (5.0_f64 / 6.0).sqrt() * beta;
        println!(
            "| {e} | {:.5} | {:.5} | {:.4} |",
            damping_for_restitution(e),
            closed,
            restitution_of(closed)
        );
    }
}
