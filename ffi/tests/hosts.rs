//! The C and C++ example hosts (ffi/examples/) compile with gcc and g++ against
//! include/fractum.h and libfractum.so and pass their own checks. On the SHPB scene: stress
//! rising with strain, exact landing on requested times, bit-for-bit replay from a saved
//! state, reset, and refusal of null pointers, freed and forged handles, short buffers and bad
//! input. The C host also drives a dlsm and a beam2d scene through the generic calls, the C++
//! host a beam2d scene to its end, and both check that the SHPB-only calls are refused on
//! them with FRACTUM_ERR_MODEL.

mod common;

use std::process::Command;

fn compile_and_run(compiler: &str, source: &str, std: &str) -> String {
    let exe = common::compile(compiler, source, std);
    let run = Command::new(&exe)
        .arg("scenes/shpb_sand.toml")
        .current_dir(common::repo())
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
fn c_host_runs_the_shpb_scene_and_the_other_models() {
    let out = compile_and_run("gcc", "ffi/examples/host.c", "-std=c11");
    assert!(out.contains("host.c: ok"), "{out}");
    assert!(out.contains("dlsm: 300 bodies"), "{out}");
    assert!(out.contains("beam2d: 96 bodies"), "{out}");
}

#[test]
fn cpp_host_runs_the_shpb_scene_and_a_beam2d_one() {
    let out = compile_and_run("g++", "ffi/examples/host.cpp", "-std=c++17");
    assert!(out.contains("host.cpp: ok"), "{out}");
    assert!(out.contains("beam2d: stress"), "{out}");
}
