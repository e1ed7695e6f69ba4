"""Snapshots continue bit-identically; value types pickle."""

import pickle

import numpy as np

import inertia
from conftest import SOURCE_DIR


def state_bytes(world):
    return b"".join(
        a.tobytes()
        for a in (world.positions(), world.orientations(), world.linear_velocities(),
                  world.angular_velocities())
    )


def run(world, steps):
    out = []
    for _ in range(steps):
        world.step()
        out.append(state_bytes(world))
    return out


def test_restore_state_continues_bit_identically():
    # A pile of boxes with contacts and warm starts, and joints: everything a step carries over.
    world = inertia.load_scene(str(SOURCE_DIR / "scenes" / "pendulums.json"))
    run(world, 20)
    saved = world.save_state()
    assert saved.step_count == 20
    first = run(world, 30)
    world.restore_state(saved)
    assert world.step_count == 20
    second = run(world, 30)
    assert first == second
    assert first[0] != first[-1]  # it moved


def test_value_types_pickle():
    values = [
        inertia.Material(density=7800, friction=0.4, restitution=0.2),
        inertia.Sphere(0.25),
        inertia.Box((1, 2, 3)),
        inertia.Capsule(0.1, 0.4),
        inertia.Cylinder(0.2, 0.3),
        inertia.Plane((0, 0, 1), 2),
    ]
    for v in values:
        back = pickle.loads(pickle.dumps(v))
        assert type(back) is type(v)
    m = pickle.loads(pickle.dumps(values[0]))
    assert (m.density, m.friction, m.restitution) == (7800, np.float32(0.4), np.float32(0.2))
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(values[2])).half_extents, (1, 2, 3))
    world = inertia.World()
    body = world.create_body()
    assert pickle.loads(pickle.dumps(body)) == body
