"""A batch of 1,000 pendulums, each released from its own angle, stepped together across the
cores: their periods against the exact period of a physical pendulum at large amplitude,
T = 4 sqrt(I / (m g L)) K(sin(theta0 / 2)).

    PYTHONPATH=build/default/python /usr/bin/python3 python/examples/pendulum_batch.py [N]
"""

import math
import sys
import time

import numpy as np

import inertia

LENGTH, RADIUS, DT = 1.0, 0.05, 1 / 120

# One pendulum: a small ball on a massless rod, hinged to the world 2 m up.
SCENE = {
    "world": {"gravity": [0, -9.81, 0], "dt": DT, "substeps": 4, "sleeping": False},
    "bodies": [{"name": "bob", "position": [0, 2 - LENGTH, 0],
                "shapes": [{"type": "sphere", "radius": RADIUS}]}],
    "joints": [{"type": "hinge", "body_b": "bob", "anchor_a": [0, 2, 0],
                "anchor_b": [0, LENGTH, 0], "axis_a": [0, 0, 1], "axis_b": [0, 0, 1]}],
}


def exact_period(theta0, g=9.81):
    """The period (s) of the ball on its rod released at rest from theta0 (rad): a physical
    pendulum, I = m L^2 + 2/5 m r^2 about the pivot, with the complete elliptic integral
    K(k) = pi / (2 AGM(1, sqrt(1 - k^2)))."""
    k = np.sin(np.asarray(theta0) / 2)
    a, b = np.ones_like(k), np.sqrt(1 - k * k)
    for _ in range(30):
        a, b = (a + b) / 2, np.sqrt(a * b)
    inertia_over_mass = LENGTH**2 + 0.4 * RADIUS**2
    return 4 * np.sqrt(inertia_over_mass / (g * LENGTH)) * (np.pi / (2 * a))


def periods(n=1000, threads=0, max_angle=2.5, swings=2):
    """Releases n pendulums from angles in (0, max_angle] rad and returns (angles, periods) of
    `swings` full periods each, timed at the bob's crossings of the vertical (linear
    interpolation between steps), and the wall-clock seconds spent stepping."""
    angles = np.linspace(max_angle / n, max_angle, n)
    batch = inertia.Batch(SCENE, n, threads=threads)
    # Turn each bob about the pivot to its angle: position and orientation, in one call each.
    p = batch.positions()
    p[:, 0, 0] = LENGTH * np.sin(angles)
    p[:, 0, 1] = 2 - LENGTH * np.cos(angles)
    q = np.zeros((n, 1, 4))
    q[:, 0, 0], q[:, 0, 3] = np.cos(angles / 2), np.sin(angles / 2)
    batch.set_positions(p)
    batch.set_orientations(q)
    crossings = [[] for _ in range(n)]
    x_prev, t, wall = batch.positions()[:, 0, 0].astype(float), 0.0, 0.0
    horizon = 1.2 * swings * exact_period(max_angle)
    while t < horizon:
        start = time.perf_counter()
        batch.step()
        wall += time.perf_counter() - start
        t += DT
        x = batch.positions()[:, 0, 0].astype(float)
        for i in np.nonzero(np.sign(x) != np.sign(x_prev))[0]:
            crossings[i].append(t - DT * x[i] / (x[i] - x_prev[i]))
        x_prev = x
    # Crossings 0 and 2 * swings are `swings` periods apart.
    measured = np.array([(c[2 * swings] - c[0]) / swings for c in crossings])
    return angles, measured, wall


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    angles, measured, wall = periods(n)
    exact = exact_period(angles)
    error = np.abs(measured / exact - 1)
    print(f"{n} pendulums, {wall:.2f} s of stepping")
    for i in np.linspace(0, n - 1, 6).astype(int):
        print(f"  release at {angles[i]:.3f} rad: period {measured[i]:.4f} s, "
              f"exact {exact[i]:.4f} s")
    print(f"largest relative error {error.max():.2e}")
