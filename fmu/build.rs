//! Links the FMU's shared object so that it exports the fmi2 functions only: symbols from the
//! static libraries it links (the cxx bridge, voro++, the Rust runtime) become local, so they
//! cannot clash with a master's own (rustc exports every `#[no_mangle]` function of a cdylib,
//! the cxx bridge's included). zig's linker driver (cargo-zigbuild, for the old-glibc build)
//! refuses `--exclude-libs`: that build keeps them.
fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=RUSTC_LINKER");
    let zig = std::env::var("RUSTC_LINKER").is_ok_and(|l| l.contains("zig"));
    if !zig {
        println!("cargo:rustc-cdylib-link-arg=-Wl,--exclude-libs,ALL");
    }
}
