//! What the C-host tests share: the repository, the freshly built libfractum.so and fractum
//! binary of this test's profile, and compiling a C or C++ host against them.

#![allow(dead_code)] // each test file uses its own part

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The profile folder (target/release or target/debug) holding libfractum.so and the
/// `fractum` program, both built from the current sources. `cargo test` builds neither for
/// this crate's integration tests (the library is a cdylib, the program another package's),
/// so they are built here, once per test binary: a no-op when they are current, and never a
/// stale library or program next to fresh sources.
pub fn profile_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let exe = std::env::current_exe().unwrap();
        let profile_dir = exe.parent().unwrap().parent().unwrap().to_path_buf();
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
        let mut build = Command::new(cargo);
        build.args([
            "build",
            "-p",
            "fractum-ffi",
            "--lib",
            "-p",
            "fractum",
            "--bin",
            "fractum",
        ]);
        if profile_dir.file_name().is_some_and(|n| n == "release") {
            build.arg("--release");
        }
        let status = build.current_dir(repo()).status().expect("cargo runs");
        assert!(status.success(), "cargo builds libfractum.so and fractum");
        for file in ["libfractum.so", "fractum"] {
            let path = profile_dir.join(file);
            assert!(path.exists(), "{} was built", path.display());
        }
        profile_dir
    })
}

/// The `fractum` program built from the current sources.
pub fn fractum_bin() -> PathBuf {
    profile_dir().join("fractum")
}

/// Compiles `source` (relative to the repository) with `compiler` and `-Wall -Wextra
/// -Werror` against include/fractum.h and libfractum.so; returns the executable.
pub fn compile(compiler: &str, source: &str, std: &str) -> PathBuf {
    let out =
        PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(Path::new(source).file_stem().unwrap());
    let lib = profile_dir();
    let status = Command::new(compiler)
        .args([std, "-Wall", "-Wextra", "-Werror", "-I"])
        .arg(repo().join("include"))
        .arg(repo().join(source))
        .arg("-L")
        .arg(lib)
        .arg("-lfractum")
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap_or_else(|e| panic!("{compiler} runs: {e}"));
    assert!(status.success(), "{compiler} compiles {source}");
    out
}
