"""The ctypes wrapper inside YADE's Python (Debian's yade, headless: yade -n -x)."""
import os
import re
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
    # 986 grains at the start; some break by 2e-5 s, each piece a YADE sphere.
    m = re.search(r"yade: (\d+) Fractum grains as YADE spheres", out)
    assert "yade: ok" in out and m and int(m.group(1)) >= 986, out
