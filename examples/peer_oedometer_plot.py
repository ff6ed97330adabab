#!/usr/bin/env python3
"""Stress-strain of the oedometer cross-check in Fractum, LAMMPS and YADE (one plot) and the
figures of docs/validation.md's table.

Usage: FRACTUM_PEER_OUT=out/peer .venv/bin/python -m pytest -q tests/python/test_peer_codes.py
       .venv/bin/python examples/peer_oedometer_plot.py out/peer   -> docs/img/oedometer_three_codes.svg
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "python"))
from test_peer_codes import oedometer_figures, read_series  # noqa: E402

base = sys.argv[1] if len(sys.argv) > 1 else "out/peer"
series = {
    "Fractum": read_series(os.path.join(base, "fractum", "series.csv")),
    "LAMMPS 2025": read_series(os.path.join(base, "lammps", "series_lammps.csv")),
    "YADE 2023.02a": read_series(os.path.join(base, "yade", "series_yade.csv")),
}
end = min(s["axial_strain"][-1] for s in series.values())
print(f"| code | secant 0–{100 * end:.3f}% (GPa) | tangent 0.4–0.6% (GPa) | K0 at {100 * end:.3f}% | final axial stress (MPa) |")
print("|---|---:|---:|---:|---:|")
fig, ax = plt.subplots(figsize=(6, 4.2))
for (name, s), style in zip(series.items(), ("-", "--", ":")):
    sec, tan, k0 = oedometer_figures(s, end)
    print(f"| {name} | {sec / 1e9:.4f} | {tan / 1e9:.4f} | {k0:.4f} | {s['stress_driven'][-1] / 1e6:.4f} |")
    lat = 0.5 * (s["stress_lateral_x"] + s["stress_lateral_y"])
    ax.plot(100 * s["axial_strain"], s["stress_driven"] / 1e6, style, label=f"{name}: axial")
    ax.plot(100 * s["axial_strain"], lat / 1e6, style, label=f"{name}: lateral", alpha=0.6)
ax.set_xlabel("axial strain (%)")
ax.set_ylabel("stress (MPa)")
ax.set_title("Oedometer, 1000 Hertz–Mindlin spheres, one exported packing")
ax.legend(fontsize=8)
ax.grid(alpha=0.3)
fig.tight_layout()
out = os.path.join(os.path.dirname(__file__), "..", "docs", "img", "oedometer_three_codes.svg")
fig.savefig(out)
print("wrote", os.path.normpath(out))
