#!/usr/bin/env python3
"""A split Hopkinson pressure bar: two 1D elastic steel bars around the Fractum FMU specimen.

    make fmu && .venv/bin/pip install matplotlib
    .venv/bin/python examples/shpb_bars.py --png shpb_bars.png

A striker of length `striker` (m) hits the free end of the incident bar at `speed` (m/s) and
launches a compressive pulse of particle velocity speed/2 lasting 2 striker / c. Each bar is
solved exactly by the method of characteristics on a grid with dx = c dt: right- and
left-going velocity waves a and b shift by one node per step, with v = a + b and
sigma = rho c (a - b) (compression positive). At the specimen the FMU closes the problem:

* incident bar end: the arriving wave a gives the face velocity v = 2a - sigma_s / (rho c),
  where sigma_s is the specimen's stress carried over to the bar (`bar_stress_incident`), and
  the reflected wave b = a - sigma_s / (rho c);
* transmitted bar start: the transmitted wave a = b + sigma_t / (rho c) and the face velocity
  v = a + b (`bar_stress_transmitted`, `v_transmitted`).

The communication step is the bars' dt (about 1 us); forces lag the velocities by one step.
Strain gauges in the middle of each bar record the incident, reflected and transmitted waves,
which are plotted with the specimen's stress-strain curve (FMU outputs) to a PNG.
"""
import argparse
import math
import os

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))

# Value references (fmu/modelDescription.xml).
V_INCIDENT, V_TRANSMITTED = 0, 1
STRESS_INCIDENT, STRESS_TRANSMITTED, STRAIN = 2, 3, 8
BAR_STRESS_INCIDENT, BAR_STRESS_TRANSMITTED = 6, 7
SPECIMEN_DIAMETER, BAR_DIAMETER = 10, 11


def simulate(fmu_path, speed, striker, bar_length, duration, young, density, diameter):
    c = math.sqrt(young / density)
    z = density * c  # stress per unit particle velocity
    dx = 5e-3
    dt = dx / c
    n = int(round(bar_length / dx)) + 1
    gauge = n // 2
    a_i, b_i = np.zeros(n), np.zeros(n)  # incident bar, x from the striker end to the specimen
    a_t, b_t = np.zeros(n), np.zeros(n)  # transmitted bar, x from the specimen to its far end
    pulse = 2.0 * striker / c

    md = read_model_description(fmu_path)
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu_path),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="specimen")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setReal([SPECIMEN_DIAMETER, BAR_DIAMETER], [diameter, diameter])
    fmu.exitInitializationMode()

    rows = []
    sigma_s = sigma_t = 0.0
    t = 0.0
    steps = int(duration / dt)
    for k in range(steps):
        # Waves move one node: a to the right, b to the left.
        a_i[1:] = a_i[:-1].copy()
        b_i[:-1] = b_i[1:].copy()
        a_t[1:] = a_t[:-1].copy()
        b_t[:-1] = b_t[1:].copy()
        # Striker end of the incident bar: the pulse, then a free end (a = b).
        a_i[0] = speed / 2.0 if t < pulse else b_i[0]
        # Far end of the transmitted bar: no reflection.
        b_t[-1] = 0.0
        # Specimen faces, with the specimen's stresses of the last step.
        b_i[-1] = a_i[-1] - sigma_s / z
        v_incident = a_i[-1] + b_i[-1]
        a_t[0] = b_t[0] + sigma_t / z
        v_transmitted = a_t[0] + b_t[0]
        fmu.setReal([V_INCIDENT, V_TRANSMITTED], [v_incident, v_transmitted])
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=dt)
        t += dt
        s_in, s_tr, strain, bar_in, bar_tr = fmu.getReal(
            [STRESS_INCIDENT, STRESS_TRANSMITTED, STRAIN, BAR_STRESS_INCIDENT, BAR_STRESS_TRANSMITTED])
        sigma_s, sigma_t = bar_in, bar_tr
        rows.append((t, z * a_i[gauge], -z * b_i[gauge], z * a_t[gauge], s_in, s_tr, strain,
                     v_incident, v_transmitted))
    fmu.terminate()
    fmu.freeInstance()
    return np.array(rows), dict(c=c, dt=dt, pulse=pulse, steps=steps)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--fmu", default=os.path.join(ROOT, "dist", "Fractum.fmu"))
    p.add_argument("--speed", type=float, default=6.0, help="striker speed (m/s)")
    p.add_argument("--striker", type=float, default=0.6, help="striker length (m)")
    p.add_argument("--bar-length", type=float, default=2.0, help="length of each bar (m)")
    p.add_argument("--duration", type=float, default=9.5e-4,
                   help="simulated time (s): the pulse reaches the specimen after bar-length / c, the gauges see the waves back a half bar later")
    p.add_argument("--young", type=float, default=200e9, help="bar Young's modulus (Pa)")
    p.add_argument("--density", type=float, default=7850.0, help="bar density (kg/m3)")
    p.add_argument("--diameter", type=float, default=19.05e-3, help="bar and specimen diameter (m)")
    p.add_argument("--png", default="shpb_bars.png", help="plot file ('' for none)")
    p.add_argument("--csv", default="", help="also write the series to this CSV file")
    args = p.parse_args()
    rows, info = simulate(args.fmu, args.speed, args.striker, args.bar_length, args.duration,
                          args.young, args.density, args.diameter)
    t, inc, ref, tra, s_in, s_tr, strain = (rows[:, k] for k in range(7))
    print("bars: c = %.0f m/s, dt = %.3e s, pulse %.1f us, %d steps" % (
        info["c"], info["dt"], info["pulse"] * 1e6, info["steps"]))
    print("peak incident %.1f MPa, reflected %.1f MPa, transmitted %.1f MPa; specimen strain %.3f, stress %.1f MPa" % (
        inc.max() / 1e6, ref.min() / 1e6, tra.max() / 1e6, strain[-1], s_in.max() / 1e6))
    if args.csv:
        header = "time,incident,reflected,transmitted,stress_incident,stress_transmitted,strain,v_incident,v_transmitted"
        np.savetxt(args.csv, rows, delimiter=",", header=header, comments="")
    if args.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
        ax1.plot(t * 1e6, inc / 1e6, label="incident (gauge, incident bar)")
        ax1.plot(t * 1e6, ref / 1e6, label="reflected (gauge, incident bar)")
        ax1.plot(t * 1e6, tra / 1e6, label="transmitted (gauge, transmitted bar)")
        ax1.set_xlabel("time (us)")
        ax1.set_ylabel("bar stress (MPa, compression positive)")
        ax1.legend()
        ax1.grid(alpha=0.3)
        ax2.plot(strain, s_in / 1e6, label="incident face")
        ax2.plot(strain, s_tr / 1e6, label="transmitted face")
        ax2.set_xlabel("specimen engineering strain")
        ax2.set_ylabel("specimen axial stress (MPa)")
        ax2.set_title("Fractum DEM specimen (FMU)")
        ax2.legend()
        ax2.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(args.png, dpi=120)
        print("wrote", args.png)


if __name__ == "__main__":
    main()
