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
cp fmu/modelDescription.xml "$stage/"
cp scenes/shpb_sand.toml "$stage/resources/"
rm -f dist/.Fractum.fmu.tmp
(cd "$stage" && python3 -m zipfile -c "$root/dist/.Fractum.fmu.tmp" modelDescription.xml binaries resources)
mv dist/.Fractum.fmu.tmp dist/Fractum.fmu
echo "packed dist/Fractum.fmu"
