#!/usr/bin/env bash
# The whole test suite, as CI runs it on a clean clone. It installs what it needs itself:
# Python packages go into a local virtual environment, .venv/.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n== %s\n' "$*"; }

step "formatting"
cargo fmt --all -- --check

step "lints"
cargo clippy --workspace --all-targets --release -- -D warnings

step "Rust unit and integration tests (optimised: they are physics runs)"
cargo test --workspace --release

step "Python environment (.venv: numpy, pytest)"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check numpy pytest

step "Python tests (tests/python)"
cargo build --release -p fractum-ffi
FRACTUM_LIB="$PWD/target/release/libfractum.so" .venv/bin/python -m pytest -q tests/python

step "all tests passed"
