#!/usr/bin/env bash
# Builds the FMI 2.0 co-simulation FMU and packs it into dist/Fractum.fmu:
# modelDescription.xml, binaries/linux64/fractum_shpb.so, resources/shpb_sand.toml.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
cargo build --release -p fractum-fmu
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/binaries/linux64" "$stage/resources" dist
cp "${CARGO_TARGET_DIR:-target}/release/libfractum_shpb.so" "$stage/binaries/linux64/fractum_shpb.so"
# The version from the crate, the date from the commit (not the clock: the same commit packs
# the same description).
version=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -1)
date=$(TZ=UTC git log -1 --format=%cd --date=format-local:%Y-%m-%dT%H:%M:%SZ 2>/dev/null || echo 1970-01-01T00:00:00Z)
sed -e "s/@VERSION@/$version/g" -e "s/@DATE@/$date/g" fmu/modelDescription.xml >"$stage/modelDescription.xml"
cp scenes/shpb_sand.toml "$stage/resources/"
rm -f dist/.Fractum.fmu.tmp
(cd "$stage" && python3 -m zipfile -c "$root/dist/.Fractum.fmu.tmp" modelDescription.xml binaries resources)
mv dist/.Fractum.fmu.tmp dist/Fractum.fmu
echo "packed dist/Fractum.fmu"
