"""`pip install ./ffi/python` in a fresh virtual environment: `import fractum` works with no
FRACTUM_LIB and away from the repository (YADE's Python: test_yade.py)."""
import os
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

SCRIPT = r"""
import os, sys, fractum
here = os.path.dirname(fractum.__file__)
assert here.startswith(sys.prefix), (here, sys.prefix)
assert os.path.exists(os.path.join(here, "libfractum.so"))
with fractum.Simulation(sys.argv[1], overrides=["sample.elements=300"]) as sim:
    sim.advance(200)
    print("stress", sim.scalar("stress"), "version", fractum.version())
"""


def test_pip_install_bundles_the_library_into_a_fresh_environment(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=300)
    python = str(venv / "bin" / "python")
    subprocess.run(
        [python, "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
         os.path.join(ROOT, "ffi", "python")],
        check=True, cwd=tmp_path, timeout=900,
    )
    env = {k: v for k, v in os.environ.items() if k not in ("FRACTUM_LIB", "PYTHONPATH")}
    p = subprocess.run(
        [python, "-c", SCRIPT, os.path.join(ROOT, "scenes", "dlsm_tensile.toml")],
        capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600,
    )
    assert p.returncode == 0, p.stdout + p.stderr
    # A dlsm bar pulled for 200 steps carries a tensile stress (the wrapper reached the library).
    stress = float(p.stdout.split()[1])
    assert stress > 0, p.stdout
