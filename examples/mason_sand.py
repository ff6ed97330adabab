#!/usr/bin/env python3
"""The granular model against six measured SHPB records of dry Mason sand (docs/validation.md,
"Against the experiments"; data in data/mason_sand_shpb/, sources in docs/references.md).

Usage:
  python3 examples/mason_sand.py calibrate [--jobs 3]     the calibration at 1520 kg/m3
  python3 examples/mason_sand.py predict   [--jobs 3]     the blind predictions, 4 densities
  python3 examples/mason_sand.py report    [--plots DIR]  tables (markdown) and plots

Every run is scenes/mason_sand_shpb.toml with `--set` overrides, `fractum run --threads 1`,
`--jobs` at a time, into target/mason_sand/NAME_seedN/; a finished run (its summary.json
exists) is not run again (delete the folder after changing the physics).

The calibration, stated before any run was compared (docs/validation.md):
- Data: the six records' axial (one-wave, transmitted-face) stress on the loading branch,
  linearly interpolated at the strains 0.03, 0.04, ..., 0.25; the target at each strain is the
  mean of the records that reach it (test 030 ends before 0.25).
- Simulation: the stress on the face opposite the driven one (series.csv `stress_opposite`),
  interpolated at the same strains, averaged over seeds 1, 2, 3.
- Objective: J = mean over those strains of ln(sim / target)^2 (every strain weighs by its
  relative error: the stress spans a factor of 15 over the window). sqrt(J) is the RMS
  relative (log) error.
- Parameters (four): Young's modulus E, the contact tensile strength at the reference radius
  (fracture.reference_strength), Hoek-Brown's sigma_c, the grains' friction (material.friction).
  Everything else stays as scenes/mason_sand_shpb.toml has it (wall friction 0.5, Weibull
  modulus 1, m_i 20.56, nu 0.18).
- Method: coordinate search in log space from the start point (E 29 GPa, the FEM-DEM study's;
  reference strength 3 GPa, sigma_c 592 MPa, friction 0.5, the paper's silica values): each
  parameter in turn is tried at x2 and x0.5 of its current value (friction +-0.2), keeping the
  best point whenever J falls; after a full round without a gain the factors are square-rooted
  (x1.41); stopped when the budget of evaluations (`--budget`, default 12) is spent. Physical
  bounds: E in [5, 100] GPa, reference strength in [0.1, 30] GPa, sigma_c in [50, 2000] MPa,
  friction in [0.1, 0.9].
"""
import argparse
import csv
import json
import math
import os
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
TARGET = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
FRACTUM = os.environ.get("FRACTUM_BIN", os.path.join(TARGET, "release", "fractum"))
WORK = os.path.join(TARGET, "mason_sand")
SCENE = os.path.join(ROOT, "scenes", "mason_sand_shpb.toml")
DATA = os.path.join(ROOT, "data", "mason_sand_shpb")
TESTS = ["026", "027", "028", "029", "030", "035"]
FIT_STRAINS = [round(0.03 + 0.01 * k, 2) for k in range(23)]
REPORT_STRAINS = [0.05, 0.10, 0.15, 0.20, 0.25]
SEEDS = [1, 2, 3]
QUARTZ = 2650.0

# name -> (scene key, start, kind of step, bounds)
PARAMS = {
    "young": ("material.young", 29e9, "log", (5e9, 100e9)),
    "strength": ("fracture.reference_strength", 3e9, "log", (0.1e9, 30e9)),
    "sigma_c": ("fracture.sigma_c", 592e6, "log", (50e6, 2000e6)),
    "friction": ("material.friction", 0.5, "lin", (0.1, 0.9)),
}
# The blind predictions: densities (kg/m3) of the laboratory's other tests.
DENSITIES = [1580, 1640, 1700, 1770]


def record(test):
    """(strain, axial stress MPa, radial stress MPa) on the loading branch (to the peak)."""
    rows = []
    with open(os.path.join(DATA, f"test_052212-{test}.csv")) as f:
        for r in csv.DictReader(f):
            rows.append((float(r["axial_strain"]), float(r["axial_stress_MPa"]),
                         float(r["radial_stress_MPa"])))
    peak = max(range(len(rows)), key=lambda k: rows[k][1])
    return rows[: peak + 1]


def at(xs, ys, x):
    """Linear interpolation at the first crossing of x along xs; None outside."""
    for k in range(1, len(xs)):
        if xs[k - 1] <= x <= xs[k] and xs[k] > xs[k - 1]:
            t = (x - xs[k - 1]) / (xs[k] - xs[k - 1])
            return ys[k - 1] + t * (ys[k] - ys[k - 1])
    return None


def records():
    out = {}
    for t in TESTS:
        rows = record(t)
        eps = [r[0] for r in rows]
        out[t] = {
            "strain": eps,
            "axial": [r[1] for r in rows],
            "radial": [r[2] for r in rows],
        }
    return out


def targets(recs):
    tgt = {}
    for e in FIT_STRAINS:
        vals = [at(r["strain"], r["axial"], e) for r in recs.values()]
        vals = [v for v in vals if v is not None]
        tgt[e] = statistics.mean(vals)
    return tgt


def run(name, sets, seed):
    out = os.path.join(WORK, f"{name}_seed{seed}")
    if os.path.exists(os.path.join(out, "summary.json")):
        return out
    cmd = [FRACTUM, "run", SCENE, "--threads", "1", "--quiet", "--out", out,
           "--set", f"seed={seed}"]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write(f"{name} seed {seed}: {r.stderr.strip()}\n")
        return None
    return out


def series(out):
    with open(os.path.join(out, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    col = lambda k: [float(r[k]) for r in rows]
    lat = [0.5 * (a + b) for a, b in zip(col("stress_lateral_x"), col("stress_lateral_y"))]
    return {
        "strain": col("axial_strain"),
        "opposite": [v / 1e6 for v in col("stress_opposite")],
        "driven": [v / 1e6 for v in col("stress_driven")],
        "lateral": [v / 1e6 for v in lat],
    }


def evaluate(name, sets, jobs):
    with ThreadPoolExecutor(jobs) as pool:
        outs = list(pool.map(lambda s: run(name, sets, s), SEEDS))
    if any(o is None for o in outs):
        return None
    return [series(o) for o in outs]


def mean_curve(runs, column, strains):
    vals = []
    for e in strains:
        v = [at(r["strain"], r[column], e) for r in runs]
        vals.append(statistics.mean(v) if all(x is not None for x in v) else None)
    return vals


def objective(runs, tgt):
    sim = mean_curve(runs, "opposite", FIT_STRAINS)
    terms = [math.log(max(s, 1e-6) / tgt[e]) ** 2 for s, e in zip(sim, FIT_STRAINS)
             if s is not None]
    if len(terms) < len(FIT_STRAINS):
        return float("inf")
    return statistics.mean(terms)


def point_name(p):
    return "cal_" + "_".join(f"{k}{p[k]:.4g}" for k in PARAMS)


def point_sets(p):
    return [f"{PARAMS[k][0]}={p[k]:.6g}" for k in PARAMS]


def log_path():
    return os.path.join(WORK, "calibration.json")


def calibrate(args):
    os.makedirs(WORK, exist_ok=True)
    tgt = targets(records())
    history = []
    if os.path.exists(log_path()):
        history = json.load(open(log_path()))

    def J(p):
        for h in history:
            if h["point"] == p:
                return h["J"]
        runs = evaluate(point_name(p), point_sets(p), args.jobs)
        j = objective(runs, tgt) if runs else float("inf")
        history.append({"point": dict(p), "J": j})
        json.dump(history, open(log_path(), "w"), indent=1)
        print(f"J = {j:.4f} (rms log error {math.sqrt(j):.3f}) at {p}", flush=True)
        return j

    best = {k: v[1] for k, v in PARAMS.items()}
    jbest = J(best)
    factor, shift = 2.0, 0.2
    evaluations = lambda: len({json.dumps(h["point"], sort_keys=True) for h in history})
    while evaluations() < args.budget:
        gained = False
        for k, (_, _, kind, (lo, hi)) in PARAMS.items():
            for direction in (+1, -1):
                if evaluations() >= args.budget:
                    break
                p = dict(best)
                p[k] = best[k] * factor ** direction if kind == "log" else best[k] + direction * shift
                p[k] = min(max(p[k], lo), hi)
                if p[k] == best[k]:
                    continue
                j = J(p)
                if j < jbest:
                    best, jbest, gained = p, j, True
                    break
        if not gained:
            factor, shift = math.sqrt(factor), shift / 2
    print(f"best J = {jbest:.4f} (rms log error {math.sqrt(jbest):.3f}) at {best}")
    json.dump({"best": best, "J": jbest}, open(os.path.join(WORK, "calibrated.json"), "w"),
              indent=1)


def calibrated():
    path = os.path.join(WORK, "calibrated.json")
    if os.path.exists(path):
        return json.load(open(path))["best"]
    return {k: v[1] for k, v in PARAMS.items()}


def predict(args):
    evaluate("scene", [], args.jobs)  # the shipped (calibrated) scene at 1520 kg/m3
    for rho in DENSITIES:
        phi = rho / QUARTZ
        evaluate(f"pred_{rho}", [f"sample.solid_fraction={phi:.6f}"], args.jobs)


def fmt(v, nd=1):
    return "–" if v is None else f"{v:.{nd}f}"


def report(args):
    recs = records()
    tgt = targets(recs)
    lines = []
    # The calibration history.
    if os.path.exists(log_path()):
        lines.append("| evaluation | E (GPa) | reference strength (GPa) | sigma_c (MPa) | friction | J | RMS log error |")
        lines.append("|---:|---:|---:|---:|---:|---:|---:|")
        for k, h in enumerate(json.load(open(log_path()))):
            p = h["point"]
            lines.append(f"| {k + 1} | {p['young'] / 1e9:.3g} | {p['strength'] / 1e9:.3g} | "
                         f"{p['sigma_c'] / 1e6:.3g} | {p['friction']:.2g} | {h['J']:.4f} | "
                         f"{math.sqrt(h['J']):.3f} |")
        lines.append("")
    # Records against the calibrated scene (the shipped one) and the predictions.
    band = {}
    for e in REPORT_STRAINS:
        v = [at(r["strain"], r["axial"], e) for r in recs.values()]
        v = [x for x in v if x is not None]
        band[e] = (min(v), max(v))
    cases = [("scene", "1520 (calibrated)", [])] + [
        (f"pred_{rho}", f"{rho} (predicted)", None) for rho in DENSITIES]
    lines.append("| density kg/m3 | " + " | ".join(f"{e:.2f}" for e in REPORT_STRAINS)
                 + " | lateral/axial at 0.25 |")
    lines.append("|---|" + "---:|" * (len(REPORT_STRAINS) + 1))
    lines.append("| 1520, records min-max | " + " | ".join(
        f"{band[e][0]:.1f}-{band[e][1]:.1f}" for e in REPORT_STRAINS) + " | 0.22-0.31 at the peak |")
    curves = {}
    for name, label, _ in cases:
        outs = [os.path.join(WORK, f"{name}_seed{s}") for s in SEEDS]
        outs = [o for o in outs if os.path.exists(os.path.join(o, "summary.json"))]
        if not outs:
            continue
        runs = [series(o) for o in outs]
        curves[name] = (label, runs)
        cells = []
        for e in REPORT_STRAINS:
            v = [at(r["strain"], r["opposite"], e) for r in runs]
            v = [x for x in v if x is not None]
            cells.append("–" if not v else
                         f"{statistics.mean(v):.1f} ± {statistics.stdev(v) if len(v) > 1 else 0:.1f}")
        ratio = [at(r["strain"], r["lateral"], 0.25) / at(r["strain"], r["opposite"], 0.25)
                 for r in runs if at(r["strain"], r["opposite"], 0.25)]
        lines.append(f"| {label}, {len(runs)} seeds | " + " | ".join(cells)
                     + f" | {fmt(statistics.mean(ratio) if ratio else None, 2)} |")
    # The paper's own main job (silica sand, solid fraction 0.55, 500/s, 6 mm cube), seed 1:
    # `fractum run scenes/shpb_sand.toml --out target/mason_sand/main_job_seed1`.
    main = os.path.join(WORK, "main_job_seed1")
    if os.path.exists(os.path.join(main, "summary.json")):
        runs = [series(main)]
        curves["main_job"] = ("paper's main job: silica, 1460 kg/m3, 500/s (seed 1)", runs)
        cells = [fmt(at(runs[0]["strain"], runs[0]["opposite"], e)) for e in REPORT_STRAINS]
        ratio = at(runs[0]["strain"], runs[0]["lateral"], 0.25) / at(runs[0]["strain"], runs[0]["opposite"], 0.25)
        lines.append("| paper's main job (silica sand, 1460 kg/m3, 500/s), seed 1 | "
                     + " | ".join(cells) + f" | {ratio:.2f} |")
    print("\n".join(lines))
    # The power of density at 0.1 and 0.2 strain (least squares in log-log over all densities).
    for e in (0.10, 0.20):
        xs, ys = [], []
        for name, (label, runs) in curves.items():
            if name == "main_job":
                continue
            rho = 1520 if name == "scene" else int(name.split("_")[1])
            v = [at(r["strain"], r["opposite"], e) for r in runs]
            if all(x is not None for x in v):
                xs.append(math.log(rho))
                ys.append(math.log(statistics.mean(v)))
        if len(xs) >= 2:
            mx, my = statistics.mean(xs), statistics.mean(ys)
            n = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
            d = sum((x - mx) ** 2 for x in xs)
            print(f"\nstress at {e} strain ~ density^{n / d:.2f} ({len(xs)} densities)")
    if args.plots:
        plot(args.plots, recs, curves)


def plot(folder, recs, curves):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    os.makedirs(folder, exist_ok=True)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    grid = [0.005 * k for k in range(1, 54)]
    lo = [min((v for v in (at(r["strain"], r["axial"], e) for r in recs.values()) if v is not None), default=None) for e in grid]
    hi = [max((v for v in (at(r["strain"], r["axial"], e) for r in recs.values()) if v is not None), default=None) for e in grid]
    keep = [k for k in range(len(grid)) if lo[k] is not None]
    ax.fill_between([grid[k] for k in keep], [lo[k] for k in keep], [hi[k] for k in keep],
                    color="0.8", label="six records, 1520 kg/m3 (min-max)")
    colors = ["C0", "C1", "C2", "C3", "C4", "C5"]
    for (name, (label, runs)), c in zip(curves.items(), colors):
        m = mean_curve(runs, "opposite", grid)
        sd = [statistics.stdev([at(r["strain"], r["opposite"], e) or 0 for r in runs])
              if len(runs) > 1 else 0 for e in grid]
        ok = [k for k in range(len(grid)) if m[k] is not None]
        ax.plot([grid[k] for k in ok], [m[k] for k in ok], color=c, label=label)
        ax.fill_between([grid[k] for k in ok], [m[k] - sd[k] for k in ok],
                        [m[k] + sd[k] for k in ok], color=c, alpha=0.2)
    ax.set_xlabel("axial strain")
    ax.set_ylabel("axial stress, transmitted face (MPa)")
    ax.set_title("Mason sand, 387 1/s: records and simulations (mean ± sd of 3 seeds)")
    ax.legend(fontsize=7)
    for t, r in recs.items():
        bx.plot(r["strain"], r["radial"], color="0.6", lw=0.8)
    if "scene" in curves:
        runs = curves["scene"][1]
        m = mean_curve(runs, "lateral", grid)
        ok = [k for k in range(len(grid)) if m[k] is not None]
        bx.plot([grid[k] for k in ok], [m[k] for k in ok], color="C0",
                label="simulated, 1520 kg/m3 (side faces)")
    bx.plot([], [], color="0.6", label="records (sleeve)")
    bx.set_xlabel("axial strain")
    bx.set_ylabel("radial stress (MPa)")
    bx.legend(fontsize=7)
    fig.tight_layout()
    for ext in ("svg", "png"):
        fig.savefig(os.path.join(folder, f"mason_sand.{ext}"), dpi=110)
    print(f"plots: {folder}/mason_sand.svg, .png")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=["calibrate", "predict", "report"])
    ap.add_argument("--jobs", type=int, default=3)
    ap.add_argument("--budget", type=int, default=12)
    ap.add_argument("--plots")
    args = ap.parse_args()
    if args.what == "calibrate":
        calibrate(args)
    elif args.what == "predict":
        predict(args)
    else:
        report(args)


if __name__ == "__main__":
    main()
