//! The C and C++ example hosts (ffi/examples/) compile with gcc and g++ against
//! include/fractum.h and libfractum.so, run the SHPB scene and pass their own checks:
//! stress rising with strain, exact landing on requested times, bit-for-bit replay from a
//! saved state, reset, and refusal of null pointers, freed and forged handles, short buffers
//! and bad input.

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The folder holding libfractum.so for this test's profile. `cargo test` builds no cdylib
/// for integration tests, so on a clean tree the library is built here first.
fn lib_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().unwrap().parent().unwrap().to_path_buf();
    let lib = profile_dir.join("libfractum.so");
    if !lib.exists() {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
        let mut build = Command::new(cargo);
        build.args(["build", "-p", "fractum-ffi", "--lib"]);
        if profile_dir.file_name().is_some_and(|n| n == "release") {
            build.arg("--release");
        }
        let status = build.current_dir(repo()).status().expect("cargo runs");
        assert!(status.success(), "cargo builds libfractum.so");
    }
    assert!(lib.exists(), "{} was built", lib.display());
    profile_dir
}

fn compile_and_run(compiler: &str, source: &str, std: &str) -> String {
    let out =
        PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(Path::new(source).file_stem().unwrap());
    let lib = lib_dir();
    let status = Command::new(compiler)
        .args([std, "-Wall", "-Wextra", "-Werror", "-I"])
        .arg(repo().join("include"))
        .arg(repo().join(source))
        .arg("-L")
        .arg(&lib)
        .arg("-lfractum")
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap_or_else(|e| panic!("{compiler} runs: {e}"));
    assert!(status.success(), "{compiler} compiles {source}");
    let run = Command::new(&out)
        .arg("scenes/shpb_sand.toml")
        .current_dir(repo())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout).to_string();
    assert!(
        run.status.success(),
        "{source} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    stdout
}

#[test]
fn c_host_runs_the_shpb_scene() {
    let out = compile_and_run("gcc", "ffi/examples/host.c", "-std=c11");
    assert!(out.contains("host.c: ok"), "{out}");
}

#[test]
fn cpp_host_runs_the_shpb_scene() {
    let out = compile_and_run("g++", "ffi/examples/host.cpp", "-std=c++17");
    assert!(out.contains("host.cpp: ok"), "{out}");
}
