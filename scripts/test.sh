#!/usr/bin/env bash
# The whole test suite, as CI runs it on a clean clone. It installs what it needs itself.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n== %s\n' "$*"; }

step "formatting"
cargo fmt --all -- --check

step "lints"
cargo clippy --workspace --all-targets --release -- -D warnings

step "Rust unit and integration tests (optimised: they are physics runs)"
cargo test --workspace --release

step "all tests passed"
