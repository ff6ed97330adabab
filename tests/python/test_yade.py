"""The ctypes wrapper inside YADE's Python (Debian's yade, headless: yade -n -x)."""
import os
import shutil
import subprocess

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def test_wrapper_runs_inside_yade():
    yade = shutil.which("yade")
    assert yade, "Debian's yade is installed by make test"
    env = dict(os.environ, FRACTUM_ROOT=ROOT)
    p = subprocess.run(
        [yade, "-n", "-x", "-j1", os.path.join(ROOT, "tests", "python", "yade_wrapper.py")],
        capture_output=True, text=True, timeout=600, env=env, cwd=ROOT,
    )
    out = p.stdout + p.stderr
    assert p.returncode == 0, out
    assert "yade: ok" in out and "986 Fractum grains as YADE spheres" in out, out
