#!/usr/bin/env bash
# Makes tests/data/mason_sand_sample/: the jammed sample scenes/mason_sand_shpb.toml prepares
# (seed 1, the 3 mm cube), as the sample cache keeps it, for the FMU's test of its Mason sand
# variant, which would otherwise prepare it (about a quarter of an hour on one core). Run it
# after any change to the scene's [sample], [material] or [neighbor] tables, to the grain
# file, to the crate's version or to fractum::sample::PREPARATION_REVISION.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --bin fractum
dir=tests/data/mason_sand_sample
rm -rf "$dir" && mkdir -p "$dir"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
FRACTUM_SAMPLE_CACHE="$PWD/$dir" "${CARGO_TARGET_DIR:-target}/release/fractum" run \
    scenes/mason_sand_shpb.toml --set loading.end_strain=0.0001 \
    --set 'output.report_strains=[0.0001]' --out "$out/run"
ls -l "$dir"
