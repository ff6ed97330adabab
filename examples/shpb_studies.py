#!/usr/bin/env python3
"""The SHPB studies of the granular paper, Section 5 (docs/validation.md, "SHPB
studies"): the four packings of Section 5.2 under both readings of the strength model, the
model switches of Fig. 34, the aspect ratios of Table 4 / Fig. 36, and the main job at wall
friction 0 and 0.5.

Usage: python3 examples/shpb_studies.py [--groups packings,switches,aspect,walls]
                                        [--cases CASE,...] [--seeds 1,2,3] [--jobs 2]
                                        [--report-only] [--plots DIR]

Each case is a shipped scene with `--set` overrides, run with `fractum run --threads 1`,
`--jobs` at a time (default 2), into target/shpb_studies/CASE_seedN/; a finished run (its
summary.json exists) is not run again, so an interrupted study picks up where it stopped
(delete the folder after changing the physics). Prints, per case, the axial stress at 0.05,
0.1, 0.2, 0.3 and 0.4 strain (mean and sample sd over the seeds when there are several), the
top (driven) and bottom faces' stresses at 0.1 and 0.3, the broken fraction and the mass-median
piece diameter at the last report strain, as a markdown table; with --plots (and matplotlib)
draws each group's stress-strain curves (the first seed's) to DIR/shpb_study_GROUP.svg and .png.
Build first: `cargo build --release`. A full study (every group, one seed) takes about an
hour on two cores.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
TARGET = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
FRACTUM = os.environ.get("FRACTUM_BIN", os.path.join(TARGET, "release", "fractum"))
WORK = os.path.join(TARGET, "shpb_studies")
STRAINS = ["0.05", "0.1", "0.2", "0.3", "0.4"]
BOTH = 'fracture.weibull_on="both"'
NO_FRACTURE = 'effects=["contact","damping","friction"]'
NO_COHESION = 'effects=["contact","damping","friction","fracture","weibull"]'

# group -> [(case, scene, sets, label)]; a case named in several groups runs once.
GROUPS = {
    "packings": [
        ("random_diff", "shpb_sand", [], "random, different sizes (Fig. 23)"),
        ("random_same", "shpb_random_mono", [], "random, same size (Fig. 24)"),
        ("hex", "shpb_hcp", [], "hexagonal close packed (Fig. 25)"),
        ("cubic", "shpb_cubic", [], "simple cubic (Fig. 26)"),
        ("random_diff_both", "shpb_sand", [BOTH], "random, different sizes; Weibull on sigma_c too"),
        ("random_same_both", "shpb_random_mono", [BOTH], "random, same size; Weibull on sigma_c too"),
        ("hex_both", "shpb_hcp", [BOTH], "hexagonal close packed; Weibull on sigma_c too"),
        ("cubic_both", "shpb_cubic", [BOTH], "simple cubic; Weibull on sigma_c too"),
        ("cubic_intact", "shpb_cubic", [NO_FRACTURE], "simple cubic without fracture"),
        # Without fracture the step is not adapted, and at the main job's safety 0.4 the
        # unbreakable sample's contacts pass the velocity Verlet limit at 0.39 strain.
        (
            "random_diff_intact",
            "shpb_sand",
            [NO_FRACTURE, "time.safety=0.2"],
            "random, different sizes, without fracture (Fig. 32; safety 0.2)",
        ),
    ],
    "switches": [
        ("random_diff", "shpb_sand", [], "every technique (Fig. 34; the main job)"),
        ("no_cohesion", "shpb_sand", [NO_COHESION], "no cohesive springs"),
        ("no_ideal_plane", "shpb_sand", ["fracture.ideal_plane=false"], "no ideal-plane rotation"),
        ("no_jitter", "shpb_sand", ["fracture.plane_jitter=false"], "no slight rotation"),
        (
            "aligned",
            "shpb_sand",
            ['sample.orientations="aligned"', "fracture.ideal_plane=false"],
            "principal directions along x, y, z, no plane rotation (Fig. 33)",
        ),
    ],
    "aspect": [
        ("hex", "shpb_hcp", [], "hex, 10 layers (H/d 0.80-0.92)"),
        ("hex_7", "shpb_hcp", ["sample.layers=[10,10,7]"], "hex, 7 layers (H/d 0.56-0.65)"),
        ("cubic", "shpb_cubic", [], "cubic, 10 layers (H/d 1)"),
        ("cubic_7", "shpb_cubic", ["sample.layers=[10,10,7]"], "cubic, 7 layers (H/d 0.7)"),
    ],
    "walls": [
        ("random_diff", "shpb_sand", [], "wall friction 0.5 (the scenes'; the main job)"),
        ("walls_0", "shpb_sand", ["walls.friction=0"], "lubricated walls (friction 0)"),
    ],
}


def run_dir(case, seed):
    return os.path.join(WORK, f"{case}_seed{seed}")


def run(case, scene, sets, seed, report_only):
    out = run_dir(case, seed)
    if os.path.exists(os.path.join(out, "summary.json")) or report_only:
        return
    cmd = [FRACTUM, "run", os.path.join(ROOT, "scenes", scene + ".toml"), "--quiet",
           "--threads", "1", "--out", out, "--set", f"seed={seed}", "--set", "output.vtk=0"]
    for s in sets:
        cmd += ["--set", s]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        print(f"{case} seed {seed} failed: {done.stderr.strip()}", file=sys.stderr)


def series(case, seed):
    path = os.path.join(run_dir(case, seed), "series.csv")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def at_strain(rows, column, e):
    """`column` at axial strain e, linearly interpolated between rows; None outside."""
    for a, b in zip(rows, rows[1:]):
        if a["axial_strain"] <= e <= b["axial_strain"] and b["axial_strain"] > a["axial_strain"]:
            w = (e - a["axial_strain"]) / (b["axial_strain"] - a["axial_strain"])
            return a[column] + w * (b[column] - a[column])
    return None


def fmt(values, scale=1e-6, digits=1):
    values = [v for v in values if v is not None]
    if not values:
        return "–"
    m = statistics.mean(values) * scale
    if len(values) == 1:
        return f"{m:.{digits}f}"
    return f"{m:.{digits}f} ± {statistics.stdev(values) * scale:.{digits}f}"


def report(groups, seeds):
    for g in groups:
        print(f"\n### {g}\n")
        print("| case | seeds | stress at 0.05 / 0.1 / 0.2 / 0.3 / 0.4 strain (MPa) "
              "| top / bottom at 0.1 | top / bottom at 0.3 | broken fraction | d50 at the end (µm) |")
        print("|---|---:|---|---|---|---:|---:|")
        for case, _, _, label in GROUPS[g]:
            sums = []
            for s in seeds:
                p = os.path.join(run_dir(case, s), "summary.json")
                if os.path.exists(p):
                    with open(p) as f:
                        sums.append((s, json.load(f)))
            if not sums:
                print(f"| {label} | 0 | not run | | | | |")
                continue
            stress = " / ".join(
                fmt([x["stress_at_strain"].get(e) for _, x in sums]) for e in STRAINS)
            faces = []
            for e in (0.1, 0.3):
                rows = [series(case, s) for s, _ in sums]
                top = [at_strain(r, "stress_driven", e) for r in rows if r]
                bottom = [at_strain(r, "stress_opposite", e) for r in rows if r]
                faces.append(f"{fmt(top)} / {fmt(bottom)}")
            broken = [x.get("broken_particles", 0) / x["sample"]["count"] for _, x in sums]
            d50 = []
            for _, x in sums:
                d = x.get("median_diameter_at_strain", {})
                if d:
                    d50.append(d[max(d, key=float)])
            print(f"| {label} | {len(sums)} | {stress} | {faces[0]} | {faces[1]} | "
                  f"{fmt(broken, 1, 3)} | {fmt(d50, 1e6, 0)} |")


def plot(groups, seed, where):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("no matplotlib: no plots", file=sys.stderr)
        return
    for g in groups:
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        for case, _, _, label in GROUPS[g]:
            rows = series(case, seed)
            if not rows:
                continue
            e = [r["axial_strain"] for r in rows]
            s = [0.5 * (r["stress_driven"] + r["stress_opposite"]) / 1e6 for r in rows]
            style = "--" if case.endswith(("_both", "_intact")) or case == "walls_0" else "-"
            ax.plot(e, s, style, label=label, lw=1.2)
        ax.set_xlabel("axial strain")
        ax.set_ylabel("axial stress (MPa), mean of top and bottom")
        ax.set_title(f"SHPB study: {g} (seed {seed})")
        ax.set_yscale("log")
        ax.set_ylim(1, 3000)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        for ext in ("svg", "png"):
            fig.savefig(os.path.join(where, f"shpb_study_{g}.{ext}"), dpi=110)
        plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--groups", default=",".join(GROUPS))
    ap.add_argument("--cases", help="run only these cases of the groups, in this order")
    ap.add_argument("--seeds", default="1")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--report-only", action="store_true")
    ap.add_argument("--plots", metavar="DIR")
    a = ap.parse_args()
    groups = [g for g in a.groups.split(",") if g]
    for g in groups:
        if g not in GROUPS:
            sys.exit(f"--groups: unknown group {g!r}; allowed: {', '.join(GROUPS)}")
    seeds = [int(s) for s in a.seeds.split(",") if s]
    if not os.path.exists(FRACTUM):
        sys.exit(f"no fractum binary at {FRACTUM}: run `cargo build --release` first")
    jobs = [(c, sc, st, s) for g in groups for (c, sc, st, _) in GROUPS[g] for s in seeds]
    if a.cases:
        order = [c for c in a.cases.split(",") if c]
        known = {j[0] for j in jobs}
        for c in order:
            if c not in known:
                sys.exit(f"--cases: {c!r} is no case of {', '.join(groups)}")
        jobs = sorted((j for j in jobs if j[0] in order), key=lambda j: order.index(j[0]))
    seen, unique = set(), []
    for j in jobs:
        if (j[0], j[3]) not in seen:
            seen.add((j[0], j[3]))
            unique.append(j)
    with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        list(pool.map(lambda j: run(*j, a.report_only), unique))
    report(groups, seeds)
    if a.plots:
        plot(groups, seeds[0], a.plots)


if __name__ == "__main__":
    main()
