"""The module steps a scene to the same bytes as `inertia run --record` writes."""

import subprocess

import numpy as np
import pytest

import inertia

HEADER = "time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n"


def real(x):
    # DESIGN.md section 6: %.9g for float, %.17g for double (C's printf of the value as a
    # double, which Python's % formatting reproduces digit for digit).
    digits = 9 if inertia.real_dtype == np.float32 else 17
    return "%.*g" % (digits, float(x))


def record(world, names, out):
    """One CSV block per recorded step, as io::BodyRecorder writes it."""
    t = real(inertia.real_dtype.type(world.time))
    p, q = world.positions(), world.orientations()
    v, w = world.linear_velocities(), world.angular_velocities()
    for i, name in enumerate(names):
        values = [*p[i], *q[i], *v[i], *w[i]]
        out.append(",".join([t, name] + [real(x) for x in values]) + "\n")


@pytest.mark.parametrize(
    "scene, steps",
    [
        ("bounce.json", 120),  # contacts and restitution, velocity Verlet in free flight
        ("pendulums.json", 60),  # hinge, ball, chain and slider joints
        ("pyramid.json", 30),  # many boxes in contact, the solver's colours across threads
        ("articulations.json", 120),  # a driven arm and a floating walker touching bodies
    ],
)
def test_same_bytes_as_inertia_run(cli, scenes, tmp_path, scene, steps):
    csv = tmp_path / "cli.csv"
    subprocess.run(
        [cli, "run", str(scenes / scene), "--steps", str(steps), "--record", str(csv), "-q"],
        check=True,
    )
    world = inertia.load_scene(str(scenes / scene))
    names = [world.body_name(b) or str(i) for i, b in enumerate(world.bodies())]
    rows = [HEADER]
    record(world, names, rows)
    for _ in range(steps):
        world.step()
        record(world, names, rows)
    expected = csv.read_text()
    assert len(rows) == 1 + (steps + 1) * len(names)
    assert "".join(rows) == expected
