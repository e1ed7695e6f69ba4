#!/usr/bin/python3
"""Plots the harmonic oscillator's energy under every integrator (examples/integrator_energy.cpp).

    build/default/examples/example_integrator_energy OUT.csv
    scripts/plot_integrators.py OUT.csv [--out docs/integrators_energy.png]

Left: E / E0 of every method on a log scale (explicit Euler grows, backward Euler decays).
Right: the methods that keep the energy, on a linear scale (RK4 drifts slowly; symplectic
Euler and Verlet oscillate in a band forever). Uses Debian's python3-matplotlib.
"""
import argparse
import csv
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv")
    parser.add_argument("--out", default="integrators_energy.png")
    args = parser.parse_args()
    series = defaultdict(lambda: ([], []))
    with open(args.csv, newline="") as f:
        for row in csv.DictReader(f):
            t, e = series[row["method"]]
            t.append(float(row["time"]))
            e.append(float(row["energy"]))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for name, (t, e) in series.items():
        left.plot(t, [x / e[0] for x in e], label=name, linewidth=1)
        if name in ("rk4", "verlet", "velocity_verlet", "symplectic_euler"):
            right.plot(t, [x / e[0] for x in e], label=name, linewidth=1)
    left.set_yscale("log")
    left.set_title("E / E0, every method (h = 0.02 s, period 1 s)")
    right.set_title("the methods that keep it")
    for ax in (left, right):
        ax.set_xlabel("time (s)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=90)
    print(f"plot_integrators: wrote {args.out}")


if __name__ == "__main__":
    main()
