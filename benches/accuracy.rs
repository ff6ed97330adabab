//! `cargo bench --bench accuracy [-- CASE...]`: what accuracy costs, the full sweep of
//! `fractum bench accuracy` (docs/accuracy.md) into out/accuracy/: every validation case with
//! a reference over its resolution and time step, on 1 and 2 threads. The sweep lives in the
//! library (`fractum::accuracy`, the cases in `models/*/accuracy.rs`); this runs the built
//! binary. Takes hours on two cores (the SHPB ensembles most of it); asserts nothing.

use std::process::{Command, ExitCode};

fn main() -> ExitCode {
    // cargo passes `--bench`; the rest are case names.
    let names: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let status = Command::new(env!("CARGO_BIN_EXE_fractum"))
        .args(["bench", "accuracy", "--out", "out/accuracy"])
        .args(&names)
        .status()
        .expect("the fractum binary runs");
    if status.success() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
