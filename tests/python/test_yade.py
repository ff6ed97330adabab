"""The ctypes wrapper inside YADE's Python (Debian's yade, headless: yade -n -x)."""
import os
import re
import shutil
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def test_installed_package_runs_inside_yade(tmp_path):
    # `pip install ./ffi/python` bundles libfractum.so; YADE's Python
    # imports it from where it was installed, with no FRACTUM_LIB (YADE's python3 is Debian's,
    # which refuses pip into itself: --target and PYTHONPATH; numpy comes with yade).
    yade = shutil.which("yade")
    assert yade, "Debian's yade is installed by make test"
    site = tmp_path / "site"
    pip = [sys.executable, "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]
    subprocess.run(pip + ["--no-deps", "--target", str(site), os.path.join(ROOT, "ffi", "python")],
                   check=True, cwd=tmp_path, timeout=900)
    env = {k: v for k, v in os.environ.items() if k != "FRACTUM_LIB"}
    env.update(FRACTUM_ROOT=ROOT, PYTHONPATH=str(site))
    p = subprocess.run(
        [yade, "-n", "-x", "-j1", os.path.join(ROOT, "tests", "python", "yade_wrapper.py")],
        capture_output=True, text=True, timeout=600, env=env, cwd=ROOT,
    )
    out = p.stdout + p.stderr
    assert p.returncode == 0, out
    assert "yade: fractum from %s" % (site / "fractum") in out, out
    # 986 grains at the start; some break by 2e-5 s, each piece a YADE sphere.
    m = re.search(r"yade: (\d+) Fractum grains as YADE spheres", out)
    assert "yade: ok" in out and m and int(m.group(1)) >= 986, out
