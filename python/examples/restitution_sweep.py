"""A restitution and friction sweep on a local Dask cluster, drawn with matplotlib.

A ball of radius 0.1 m is thrown from 1 m up at 2 m/s sideways onto the ground; for every pair
of restitution and friction the sweep measures the height of its first bounce (restitution
predicts e^2 h) and how far it has gone after 1.5 s (friction turns sliding into rolling). Each
point is a scene stepped on a Dask worker; the table comes back as a pandas DataFrame.

    PYTHONPATH=build/default/python /usr/bin/python3 python/examples/restitution_sweep.py \
        [--points 8] [--out sweep.png] [--scheduler tcp://host:8786 | --serial]
"""

import argparse

import numpy as np

import inertia
from inertia import distributed

DROP, RADIUS, SPEED, DT = 1.0, 0.1, 2.0, 1 / 240


def scene(restitution, friction):
    return {
        "world": {"dt": DT, "substeps": 4, "sleeping": False},
        "bodies": [
            {"name": "ground", "type": "static",
             "shapes": [{"type": "plane", "material": {"friction": 1.0}}]},
            {"name": "ball", "position": [0, DROP + RADIUS, 0], "velocity": [SPEED, 0, 0],
             "shapes": [{"type": "sphere", "radius": RADIUS,
                         "material": {"restitution": restitution, "friction": friction}}]},
        ],
    }


def measure(world):
    """Follows the ball for 1.5 s: the top of its first bounce, and where it is at the end."""
    ball = world.find_body("ball")
    top, phase = float("nan"), "falling"  # then "rising" after the first impact, then "done"
    while world.time < 1.5:
        world.step()
        y = float(world.position(ball)[1]) - RADIUS
        vy = float(world.linear_velocity(ball)[1])
        if phase == "falling" and vy > 0:
            phase = "rising"
        elif phase == "rising" and vy <= 0:
            top, phase = y, "done"
    return {"bounce_height": top, "distance": float(world.position(ball)[0])}


def run(points=8, out="restitution_sweep.png", **where):
    grid = {"restitution": np.linspace(0.1, 0.9, points).tolist(),
            "friction": np.linspace(0.0, 1.0, points).tolist()}
    table = distributed.sweep(scene, grid, measure, steps=0, **where)
    if out:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2, figsize=(10, 4))
        for ax, column, label in [(axes[0], "bounce_height", "first bounce (m)"),
                                  (axes[1], "distance", "distance after 1.5 s (m)")]:
            image = table.pivot(index="friction", columns="restitution", values=column)
            shown = ax.imshow(image.values, origin="lower", aspect="auto",
                              extent=[grid["restitution"][0], grid["restitution"][-1],
                                      grid["friction"][0], grid["friction"][-1]])
            ax.set_xlabel("restitution")
            ax.set_ylabel("friction")
            fig.colorbar(shown, ax=ax, label=label)
        fig.tight_layout()
        fig.savefig(out, dpi=100)
    return table


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=8, help="values of each parameter")
    parser.add_argument("--out", default="restitution_sweep.png", help="the plot (PNG)")
    parser.add_argument("--scheduler", help="a Dask scheduler's address (default: a local cluster)")
    parser.add_argument("--serial", action="store_true", help="run here, without Dask")
    args = parser.parse_args()
    table = run(args.points, args.out, scheduler=args.scheduler, serial=args.serial)
    print(table.to_string(index=False))
    print(f"wrote {args.out}")
