"""A sweep on a local Dask cluster: the step response of a driven joint over a grid of gains.

An arm (one link on a revolute joint about the vertical, so gravity does not turn it) has a PD
drive of stiffness k and damping c = 2 zeta sqrt(k I); its target jumps from 0 to 1 rad. For
every (stiffness, damping ratio) of the grid a Dask worker builds the scene, steps it and
measures the overshoot and the time to settle within 2%; the table comes back as a pandas
DataFrame, equal bit for bit to the serial run's. A second-order system overshoots by
exp(-pi zeta / sqrt(1 - zeta^2)) whatever its stiffness; the implicit drive is backward Euler on
that system, which damps a little more (by a ratio of about omega h / 2): the table shows both
beside the measured overshoot.

    PYTHONPATH=build/default/python /usr/bin/python3 python/examples/drive_sweep.py \
        [--points 4] [--scheduler tcp://host:8786 | --serial]
"""

import argparse
import math

import numpy as np

from inertia import distributed

DT, SUBSTEPS, DURATION = 1 / 240, 4, 1.5
MASS, COM, INERTIA_CM = 2.0, 0.3, 0.06  # kg, m, kg m^2 about the vertical through the com
INERTIA_PIVOT = INERTIA_CM + MASS * COM**2  # kg m^2 about the joint


def scene(stiffness, damping_ratio):
    damping = 2 * damping_ratio * math.sqrt(stiffness * INERTIA_PIVOT)
    return {
        "world": {"dt": DT, "substeps": SUBSTEPS, "sleeping": False},
        "articulations": [{
            "name": "arm", "base": "fixed",
            "drives": {"link": {"stiffness": stiffness, "damping": damping, "target": 1.0}},
            "links": [{"name": "link", "joint": {"type": "revolute", "axis": [0, 1, 0]},
                       "mass": MASS, "com": [COM, 0, 0],
                       "inertia": [0.006, INERTIA_CM, INERTIA_CM]}],
        }],
    }


def measure(world):
    """Follows the joint for DURATION seconds: its overshoot past the target (rad) and the
    last time it was more than 2% away from it (s; DURATION when it has not settled)."""
    arm = world.find_articulation("arm")
    peak, settled = 0.0, 0.0
    while world.time < DURATION:
        world.step()
        q = float(arm.q[0])
        peak = max(peak, q)
        if abs(q - 1.0) > 0.02:
            settled = world.time
    return {"overshoot": peak - 1.0, "settling_time": settled}


def closed_form(stiffness, damping_ratio):
    """The continuous second-order system's overshoot, exp(-pi zeta / sqrt(1 - zeta^2))."""
    if damping_ratio >= 1:
        return 0.0
    return math.exp(-math.pi * damping_ratio / math.sqrt(1 - damping_ratio**2))


def backward_euler(stiffness, damping_ratio):
    """The overshoot of the same linear system, I q'' = k (1 - q) - c q', stepped as the
    implicit drive steps it (backward Euler in q and q' at the world's substeps, sampled after
    each step as measure() samples it): an independent oracle for the world's number. Backward
    Euler damps by about omega h / 2 more than the continuous system."""
    h = DT / SUBSTEPS
    k = stiffness / INERTIA_PIVOT
    c = 2 * damping_ratio * math.sqrt(stiffness * INERTIA_PIVOT) / INERTIA_PIVOT
    step = np.linalg.inv(np.array([[1.0, -h], [h * k, 1 + h * c]]))  # x(t+h) = step (x + h b)
    x, b, peak = np.zeros(2), np.array([0.0, k]), 0.0
    for n in range(1, round(DURATION / h) + 1):
        x = step @ (x + h * b)
        if n % SUBSTEPS == 0:
            peak = max(peak, x[0])
    return peak - 1.0


def run(points=4, **where):
    grid = {"stiffness": np.linspace(50, 400, points).tolist(),
            "damping_ratio": np.linspace(0.1, 0.7, points).tolist()}
    table = distributed.sweep(scene, grid, measure, steps=0, **where)
    table["overshoot_continuous"] = [closed_form(k, z)
                                     for k, z in zip(table.stiffness, table.damping_ratio)]
    table["overshoot_backward_euler"] = [backward_euler(k, z)
                                         for k, z in zip(table.stiffness, table.damping_ratio)]
    return table


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=4, help="values of each parameter")
    parser.add_argument("--scheduler", help="a Dask scheduler's address (default: a local cluster)")
    parser.add_argument("--serial", action="store_true", help="run here, without Dask")
    args = parser.parse_args()
    table = run(args.points, scheduler=args.scheduler, serial=args.serial)
    print(table.to_string(index=False, float_format="%.4f"))
