//! Links the FMU's shared object so that it exports the fmi2 functions only: rustc exports every
//! `#[no_mangle]` function of a cdylib's dependencies, which here is fmi-sys's importer-side
//! `callback_log`; `--exclude-libs` makes it local. zig's linker driver (cargo-zigbuild, the
//! old-glibc build of `make fmu`) refuses that flag, so that build exports `callback_log` too.
//! (The FMU depends on fractum without its `voronoi` feature: no voro++, no cxx bridge.)
fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=RUSTC_LINKER");
    let zig = std::env::var("RUSTC_LINKER").is_ok_and(|l| l.contains("zig"));
    if !zig {
        println!("cargo:rustc-cdylib-link-arg=-Wl,--exclude-libs,ALL");
    }
}
