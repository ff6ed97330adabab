//! Links the FMU's shared object so that it exports the fmi2 functions only: rustc exports every
//! `#[no_mangle]` function of a cdylib's dependencies, which here is fmi-sys's importer-side
//! `callback_log`. The system linker hides it with `--exclude-libs`; zig's linker driver
//! (cargo-zigbuild, the old-glibc build of `make fmu`) refuses that flag but takes a version
//! script, exports.map (`fmi2*` global, the rest local), which replaces rustc's own list.
//! (The FMU depends on fractum without its `voronoi` feature: no voro++, no cxx bridge.)
fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=RUSTC_LINKER");
    let zig = std::env::var("RUSTC_LINKER").is_ok_and(|l| l.contains("zig"));
    if !zig {
        println!("cargo:rustc-cdylib-link-arg=-Wl,--exclude-libs,ALL");
    } else {
        let dir = std::env::var("CARGO_MANIFEST_DIR").unwrap();
        println!("cargo:rerun-if-changed=exports.map");
        println!("cargo:rustc-cdylib-link-arg=-Wl,--version-script={dir}/exports.map");
    }
}
