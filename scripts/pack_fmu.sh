#!/usr/bin/env bash
# Builds the FMI 2.0 co-simulation FMU and packs it into dist/Fractum.fmu:
# modelDescription.xml, binaries/linux64/fractum_shpb.so, resources/shpb_sand.toml (the paper's
# silica sand) and resources/mason_sand_shpb.toml (the calibrated Mason sand, with its grains).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
target=${CARGO_TARGET_DIR:-$root/target}
# A portable binary, always: linked by zig against glibc 2.17 (RHEL 7 and later; the system
# linker's build needs the build machine's glibc, 2.35 here) with libc++ inside. Installed here
# when missing, as make test does: libclang-dev (fmi-sys's bindgen) with apt-get, ziglang and
# cargo-zigbuild from PyPI into .venv. Where they cannot be had the script fails: a binary tied
# to this machine's glibc was packed before, with a warning only. The binary exports the 34
# fmi2 functions only (fmu/build.rs).
source scripts/setup.sh
need_debian_packages libclang-dev binutils
need_python_packages ziglang cargo-zigbuild
PATH="$root/.venv/bin:$PATH"
command -v cargo-zigbuild >/dev/null && command -v python-zig >/dev/null || {
    echo "pack_fmu.sh: cargo-zigbuild and zig are needed for the portable binary (pip install ziglang cargo-zigbuild)" >&2
    exit 1
}
# From fmu/: zig reports its library folder relative to the working directory when that
# holds it (the repository holds .venv), and fmi-sys's bindgen, run from elsewhere, then
# missed every header ('stddef.h' file not found).
(cd fmu && cargo zigbuild --release -p fractum-fmu --target x86_64-unknown-linux-gnu.2.17 --target-dir "$target/zig")
so="$target/zig/x86_64-unknown-linux-gnu/release/libfractum_shpb.so"
# The promise checked: no symbol from a glibc newer than 2.17.
newest=$(objdump -T "$so" | grep -o 'GLIBC_[0-9][0-9.]*' | sed 's/GLIBC_//' | sort -t. -k1,1n -k2,2n -k3,3n | tail -1)
if [ -n "$newest" ] && [ "$(printf '%s\n2.17\n' "$newest" | sort -t. -k1,1n -k2,2n -k3,3n | tail -1)" != "2.17" ]; then
    echo "pack_fmu.sh: $so needs glibc $newest, above the 2.17 the FMU promises" >&2
    exit 1
fi
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/binaries/linux64" "$stage/resources" dist
# Stripped: 40 MB of debug information unzipped on every instantiation otherwise.
strip --strip-all -o "$stage/binaries/linux64/fractum_shpb.so" "$so"
# The version from the crate, the date from the commit (not the clock: the same commit packs
# the same description).
version=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -1)
date=$(TZ=UTC git log -1 --format=%cd --date=format-local:%Y-%m-%dT%H:%M:%SZ 2>/dev/null || echo 1970-01-01T00:00:00Z)
sed -e "s/@VERSION@/$version/g" -e "s/@DATE@/$date/g" fmu/modelDescription.xml >"$stage/modelDescription.xml"
cp scenes/shpb_sand.toml "$stage/resources/"
# The calibrated Mason sand (parameter scene = "mason_sand_shpb.toml"), with the grain assembly
# it draws from beside it: inside the FMU the file sits in resources/mason_sand_shpb/, not in the
# repository's data/.
mkdir -p "$stage/resources/mason_sand_shpb"
cp data/mason_sand_shpb/grains_mason_sand_ellipsoids.csv data/mason_sand_shpb/README.md "$stage/resources/mason_sand_shpb/"
sed 's|"../data/mason_sand_shpb/|"mason_sand_shpb/|' scenes/mason_sand_shpb.toml >"$stage/resources/mason_sand_shpb.toml"
grep -q '"mason_sand_shpb/grains_mason_sand_ellipsoids.csv"' "$stage/resources/mason_sand_shpb.toml" || {
    echo "pack_fmu.sh: scenes/mason_sand_shpb.toml no longer names ../data/mason_sand_shpb/grains_mason_sand_ellipsoids.csv" >&2
    exit 1
}
rm -f dist/.Fractum.fmu.tmp
(cd "$stage" && python3 -m zipfile -c "$root/dist/.Fractum.fmu.tmp" modelDescription.xml binaries resources)
mv dist/.Fractum.fmu.tmp dist/Fractum.fmu
echo "packed dist/Fractum.fmu"
