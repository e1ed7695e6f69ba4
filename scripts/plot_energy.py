#!/usr/bin/python3
"""Plots the CSV of `inertia run --energy OUT.csv` into a PNG.

    scripts/plot_energy.py OUT.csv [--out OUT.png]

Top: kinetic, potential and total energy (J) against time (s). Bottom: linear momentum
(kg m/s) and angular momentum about the origin (kg m^2/s), component by component.
Uses Debian's python3-matplotlib (installed by scripts/setup), hence /usr/bin/python3.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = ["time", "kinetic", "potential", "total", "px", "py", "pz", "lx", "ly", "lz"]


def read(path):
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header != COLUMNS:
            sys.exit(f"plot_energy: {path}: expected the header {','.join(COLUMNS)}")
        data = {c: [] for c in COLUMNS}
        for row in reader:
            for c, v in zip(COLUMNS, row):
                data[c].append(float(v))
    return data


def main():
    parser = argparse.ArgumentParser(description="Plot `inertia run --energy` output")
    parser.add_argument("csv", help="CSV written by inertia run --energy")
    parser.add_argument("--out", help="PNG to write (default: the CSV's name with .png)")
    args = parser.parse_args()
    out = args.out or (args.csv[:-4] if args.csv.endswith(".csv") else args.csv) + ".png"
    d = read(args.csv)

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for key, label in (("kinetic", "kinetic"), ("potential", "potential"), ("total", "total")):
        top.plot(d["time"], d[key], label=label, linewidth=2 if key == "total" else 1)
    top.set_ylabel("energy (J)")
    top.legend()
    top.grid(alpha=0.3)
    for key in ("px", "py", "pz"):
        bottom.plot(d["time"], d[key], label=key + " (kg m/s)")
    for key in ("lx", "ly", "lz"):
        bottom.plot(d["time"], d[key], "--", label=key + " (kg m^2/s)")
    bottom.set_xlabel("time (s)")
    bottom.set_ylabel("momentum")
    bottom.legend(ncol=2, fontsize="small")
    bottom.grid(alpha=0.3)
    fig.suptitle(args.csv)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print(f"plot_energy: wrote {out}")


if __name__ == "__main__":
    main()
