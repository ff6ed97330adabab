import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "ffi", "python"))


def pytest_configure(config):
    config.addinivalue_line(
        "markers",
        "releases: the LAMMPS plugin tests that also run against the older stable LAMMPS "
        "releases, each in its own venv (scripts/test.sh)")
