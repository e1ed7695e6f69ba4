"""Inertia, a real-time physics engine, from Python.

    import inertia
    world = inertia.World(gravity=(0, -9.81, 0), dt=1 / 60, substeps=4)
    ground = world.create_body(type="static")
    world.add_shape(ground, inertia.Plane((0, 1, 0), 0), inertia.Material(friction=0.6))
    ball = world.create_body(position=(0, 5, 0))
    world.add_shape(ball, inertia.Sphere(0.5), inertia.Material(density=1000, restitution=0.5))
    for _ in range(600):
        world.step()
    world.positions()  # (n, 3) NumPy array, metres

Units are SI throughout; quaternions are [w, x, y, z]. State arrays have dtype
inertia.real_dtype (float32, or float64 in a double-precision build).
"""

from ._inertia import *  # noqa: F401,F403  (the extension's names are the package's)
from ._inertia import __doc__ as _extension_doc  # noqa: F401
