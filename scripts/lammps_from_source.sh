#!/usr/bin/env bash
# Builds LAMMPS from a source tree (packages GRANULAR and PLUGIN, shared libraries, the MPI of
# `mpicxx`: Debian's OpenMPI with libopenmpi-dev), installs it, and builds the Fractum plugin
# against that install by the CMake route (lammps/CMakeLists.txt), the way a cluster user
# builds both. Usage:
#
#   scripts/lammps_from_source.sh LAMMPS_SOURCE [WORK] [--check]
#
# LAMMPS_SOURCE: the LAMMPS tree (with cmake/ and src/). WORK (default
# ${CARGO_TARGET_DIR:-target}/lammps-from-source): WORK/build (LAMMPS's build), WORK/install
# (its prefix: bin/lmp, lib/liblammps.so, lib/cmake/LAMMPS), WORK/plugin (fractumplugin.so and
# libfractum.so). --check then crushes the grain of scenes/crush_grain.toml (the platen 100
# times faster, as the plugin's tests do) with that lmp and the plugin on 1 and 2 ranks under
# that MPI's mpiexec, and compares the final atoms, tags and positions.
# Environment: JOBS (parallel jobs, default 2), MPICXX (the MPI compiler wrapper, default
# mpicxx), MPIEXEC (default mpiexec), CXX (the C++ compiler, CMake's default otherwise),
# LAMMPS_SIZES (smallbig, bigbig, smallsmall; default smallbig), LAMMPS_CMAKE_ARGS (more
# arguments for LAMMPS's cmake, split on spaces).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

check=0
args=()
for a in "$@"; do
    case "$a" in
        --check) check=1 ;;
        *) args+=("$a") ;;
    esac
done
[ ${#args[@]} -ge 1 ] || { sed -n '2,20p' "$0" >&2; exit 2; }
src=$(cd "${args[0]}" && pwd)
[ -f "$src/cmake/CMakeLists.txt" ] && [ -f "$src/src/version.h" ] ||
    { echo "$src is not a LAMMPS source tree (no cmake/CMakeLists.txt, src/version.h)" >&2; exit 1; }
work="${args[1]:-${CARGO_TARGET_DIR:-$root/target}/lammps-from-source}"
mkdir -p "$work"
work=$(cd "$work" && pwd)
jobs="${JOBS:-2}"
mpicxx=$(command -v "${MPICXX:-mpicxx}") || { echo "no MPI compiler wrapper ${MPICXX:-mpicxx}" >&2; exit 1; }
compiler=()
[ -n "${CXX:-}" ] && compiler=(-D CMAKE_CXX_COMPILER="$CXX")
read -r -a more <<<"${LAMMPS_CMAKE_ARGS:-}"

echo "== LAMMPS $(sed -n 's/#define LAMMPS_VERSION "\(.*\)"/\1/p' "$src/src/version.h") from $src"
t0=$(date +%s)
cmake -S "$src/cmake" -B "$work/build" "${compiler[@]}" \
    -D CMAKE_BUILD_TYPE=Release \
    -D CMAKE_INSTALL_PREFIX="$work/install" \
    -D CMAKE_INSTALL_RPATH="$work/install/lib" \
    -D BUILD_SHARED_LIBS=on \
    -D BUILD_MPI=on -D MPI_CXX_COMPILER="$mpicxx" \
    -D BUILD_OMP=off \
    -D LAMMPS_SIZES="${LAMMPS_SIZES:-smallbig}" \
    -D PKG_GRANULAR=on -D PKG_PLUGIN=on \
    "${more[@]}"
cmake --build "$work/build" --parallel "$jobs"
cmake --install "$work/build"
t1=$(date +%s)
echo "== LAMMPS built and installed in $work/install in $((t1 - t0)) s"

# The plugin against that install: its CMake package gives the integer sizes and the MPI (the
# same wrapper), its lmp the release, its library the string ABI. The tree's headers come
# first: an install may lack some (the 29 Aug 2024 development state installs fmt/format.h
# without the fmt/base.h it includes).
cmake -S "$root/lammps" -B "$work/plugin" "${compiler[@]}" \
    -D LAMMPS_DIR="$work/install/lib/cmake/LAMMPS" \
    -D LAMMPS_SOURCE_DIR="$src/src" \
    -D MPI_CXX_COMPILER="$mpicxx"
cmake --build "$work/plugin" --parallel "$jobs"
t2=$(date +%s)
echo "== $(cat "$work/plugin/fractumplugin.txt")"
echo "== plugin built in $((t2 - t1)) s: load it with"
echo "   $work/install/bin/lmp ... (plugin load $work/plugin/fractumplugin.so)"

[ "$check" = 1 ] || exit 0

# The crush of one grain on 1 and 2 ranks: the same atoms (tags, masses, radii, parents) and
# positions. mpiexec as root needs Open MPI's consent; --oversubscribe lets 2 ranks run on a
# machine with fewer free slots.
target="${CARGO_TARGET_DIR:-$root/target}"
fractum="${FRACTUM_BIN:-$target/release/fractum}"
[ -x "$fractum" ] || (cd "$root" && cargo build --release --bin fractum)
case="$work/crush"
rm -rf "$case"
"$fractum" export lammps "$root/scenes/crush_grain.toml" "$case" --plugin \
    --set loading.speed=0.6 --set loading.end_displacement=0.13e-3 --quiet
python3 - "$case" <<'PY'
import sys, os
folder = sys.argv[1]
lines = open(os.path.join(folder, "in.fractum")).read().splitlines()
at = next(k for k, l in enumerate(lines) if l.startswith("run "))
after = ['print "FRACTURE $(f_fracture[1]) $(atoms)"',
         "write_dump all custom final.dump id mass radius x y z vx vy vz d2_fr_grain[5] "
         "modify format float %.17g"]
open(os.path.join(folder, "in.test"), "w").write("\n".join(lines[:at + 1] + after) + "\n")
PY
mpiexec="${MPIEXEC:-mpiexec}"
mpiflags=(--oversubscribe)
[ "$(id -u)" = 0 ] && mpiflags+=(--allow-run-as-root)
"$mpiexec" --version 2>&1 | grep -qi "open mpi\|open-mpi\|openrte" || mpiflags=()
for ranks in 1 2; do
    s=$(date +%s)
    (cd "$case" && OMP_NUM_THREADS=1 "$mpiexec" "${mpiflags[@]}" -np "$ranks" \
        "$work/install/bin/lmp" -in in.test -log "log.$ranks" -echo none -nocite \
        -var plugin "$work/plugin/fractumplugin.so" > "screen.$ranks" 2>&1) ||
        { tail -20 "$case/screen.$ranks" >&2; exit 1; }
    e=$(date +%s)
    mv "$case/final.dump" "$case/final.$ranks.dump"
    echo "== $ranks rank(s): $(grep '^FRACTURE ' "$case/screen.$ranks") (splits, atoms), $((e - s)) s"
done
python3 - "$case" <<'PY'
import sys, os
folder = sys.argv[1]
def read(ranks):
    lines = open(os.path.join(folder, f"final.{ranks}.dump")).read().splitlines()
    at = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    return sorted(([float(v) for v in l.split()] for l in lines[at + 1:]), key=lambda r: r[0])
one, two = read(1), read(2)
same_atoms = len(one) == len(two) and all(
    [a[i] for i in (0, 1, 2, 9)] == [b[i] for i in (0, 1, 2, 9)] for a, b in zip(one, two))
dx = max(abs(a[i] - b[i]) for a, b in zip(one, two) for i in (3, 4, 5))
dv = max(abs(a[i] - b[i]) for a, b in zip(one, two) for i in (6, 7, 8))
box = 2e-3
print(f"== 1 against 2 ranks: {len(one)} and {len(two)} atoms, tags/masses/radii/parents "
      f"{'the same' if same_atoms else 'DIFFER'}, largest position difference {dx:.3g} m "
      f"({dx / box:.3g} of the box), largest velocity difference {dv:.3g} m/s")
sys.exit(0 if same_atoms and dx <= 1e-10 * box else 1)
PY
