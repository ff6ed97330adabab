#!/usr/bin/env python3
"""Times LAMMPS `pair_style granular` on the very packings that `fractum bench` times.

Usage: python3 benches/lammps_same_packing.py [N ...]   (default 1000 8000)

Reads target/fractum-bench/dense_N.txt (written by `fractum bench`), writes a LAMMPS data file
(atom_style sphere, units si) and an input with the same contact law (hertz/material, tangential
mindlin, mu 0.5, damping tsuji: the same force form as Fractum's, which Debian's 2022 LAMMPS
has; its coefficient differs slightly, its cost not), the same six walls (fix wall/gran), the same time
step (0.3 x Rayleigh) and the same Verlet skin (0.4 x the smallest radius), runs 200 warm-up and
N_STEPS timed steps with the `lmp` on PATH, and prints particle-steps per second from LAMMPS's
own loop time. Prints figures, asserts nothing; skips when `lmp` is missing.
"""
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

E, NU, RHO, MU, COR = 60e9, 0.17, 2650.0, 0.5, 0.5
STEPS = int(os.environ.get("N_STEPS", "2000"))


def rayleigh(r):
    g = E / (2 * (1 + NU))
    return math.pi * r * math.sqrt(RHO / g) / (0.1631 * NU + 0.8766)


def run(n, lmp, threads):
    src = os.path.join("target", "fractum-bench", f"dense_{n}.txt")
    if not os.path.exists(src):
        sys.exit(f"{src} is missing: run `fractum bench --bodies {n}` first")
    box, spheres = None, []
    for line in open(src):
        if line.startswith("# box"):
            box = [float(v) for v in line.split()[2:]]
        elif line.strip() and not line.startswith("#"):
            spheres.append([float(v) for v in line.split()])
    lo, hi = box[:3], box[3:]
    rmin = min(s[3] for s in spheres)
    dt = 0.3 * rayleigh(rmin)
    skin = 0.4 * rmin
    work = tempfile.mkdtemp(prefix="fractum-lammps-")
    with open(os.path.join(work, "packing.data"), "w") as f:
        f.write(f"Fractum dense packing of {n} spheres (SI)\n\n{len(spheres)} atoms\n1 atom types\n\n")
        for a, name in enumerate("xyz"):
            f.write(f"{lo[a]:.17g} {hi[a]:.17g} {name}lo {name}hi\n")
        f.write("\nAtoms # sphere\n\n")
        for i, (x, y, z, r) in enumerate(spheres, 1):
            f.write(f"{i} 1 {2 * r:.17g} {RHO:.17g} {x:.17g} {y:.17g} {z:.17g}\n")
    law = f"hertz/material {E} {COR} {NU} tangential mindlin NULL 1.0 {MU} damping tsuji"
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
run {STEPS}
""")
    cmd = [lmp, "-in", "in.bench", "-log", "log.lammps", "-screen", "none"]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    if threads > 1:
        mpirun = shutil.which("mpirun")
        if not mpirun:
            return None
        cmd = [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(threads)] + cmd
    subprocess.run(cmd, cwd=work, env=env, check=True)
    log = open(os.path.join(work, "log.lammps")).read()
    times = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)
    seconds, procs, steps, atoms = times[-1]
    shutil.rmtree(work)
    return int(atoms) * int(steps) / float(seconds)


def main():
    lmp = shutil.which("lmp") or shutil.which("lmp_serial")
    if not lmp:
        print("lmp not found: skipping the LAMMPS side")
        return
    sizes = [int(a) for a in sys.argv[1:]] or [1000, 8000]
    print("| bodies | LAMMPS MPI ranks | particle-steps/s |\n|---:|---:|---:|")
    for n in sizes:
        for ranks in (1, 2):
            rate = run(n, lmp, ranks)
            if rate is not None:
                print(f"| {n} | {ranks} | {rate:.3e} |")


if __name__ == "__main__":
    main()
