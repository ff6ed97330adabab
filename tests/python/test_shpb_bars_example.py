"""examples/shpb_bars.py: the FMU between two 1D bars (a short run, no plot)."""
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def test_bars_launch_the_striker_pulse_and_load_the_specimen(tmp_path):
    csv = tmp_path / "bars.csv"
    p = subprocess.run(
        [sys.executable, os.path.join(ROOT, "examples", "shpb_bars.py"), "--bar-length", "1.0",
         "--duration", "3e-4", "--png", "", "--csv", str(csv)],
        capture_output=True, text=True, timeout=600,
    )
    assert p.returncode == 0, p.stderr
    d = np.genfromtxt(csv, delimiter=",", names=True)
    rho, young, speed = 7850.0, 200e9, 6.0
    c = np.sqrt(young / rho)
    # The incident pulse: particle velocity speed / 2, stress rho c speed / 2 (118.9 MPa).
    assert abs(d["incident"].max() / (rho * c * speed / 2) - 1) < 1e-12
    # Nothing reaches the specimen before bar-length / c (198 us) ...
    before = d["time"] < 1.0 / c
    assert np.all(d["strain"][before] == 0.0)
    # ... and then it is compressed, the incident face first.
    assert d["strain"][-1] > 0.02
    assert d["stress_incident"][-1] > 1e6
    assert np.all(np.isfinite(d["stress_transmitted"]))
