"""inertia.Batch: N worlds stepped together give the bits of N worlds stepped alone."""

import copy

import numpy as np
import pytest

import inertia

PENDULUM = {
    "world": {"gravity": [0, -9.81, 0], "dt": 1 / 60, "substeps": 4},
    "bodies": [
        {"name": "ground", "type": "static",
         "shapes": [{"type": "plane", "normal": [0, 1, 0], "offset": 0}]},
        {"name": "bob", "position": [1, 2, 0], "shapes": [{"type": "sphere", "radius": 0.1}]},
        {"name": "box", "position": [0, 0.5, 0],
         "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
    ],
    "joints": [{"type": "hinge", "body_b": "bob", "anchor_a": [0, 2, 0], "anchor_b": [-1, 0, 0],
                "axis_a": [0, 0, 1], "axis_b": [0, 0, 1]}],
}


def alone(scene, gravity, steps):
    scene = copy.deepcopy(scene)
    scene["world"]["gravity"] = list(map(float, gravity))
    world = inertia.parse_scene(scene)
    for _ in range(steps):
        world.step()
    return world


@pytest.mark.parametrize("threads", [1, 2])
def test_batch_equals_each_world_stepped_alone(threads):
    n, steps = 8, 40
    gravity = np.zeros((n, 3), inertia.real_dtype)
    gravity[:, 1] = -np.linspace(1, 20, n)  # each world its own gravity
    gravity[:, 0] = np.linspace(-2, 2, n)  # and a sideways pull, so the box slides
    batch = inertia.Batch(PENDULUM, n, gravity=gravity, threads=threads)
    assert len(batch) == n and batch.body_count == 3
    batch.step(steps)
    p, q = batch.positions(), batch.orientations()
    v, w = batch.linear_velocities(), batch.angular_velocities()
    assert p.shape == (n, 3, 3) and q.shape == (n, 3, 4)
    for i in range(n):
        world = alone(PENDULUM, gravity[i], steps)
        assert p[i].tobytes() == world.positions().tobytes()
        assert q[i].tobytes() == world.orientations().tobytes()
        assert v[i].tobytes() == world.linear_velocities().tobytes()
        assert w[i].tobytes() == world.angular_velocities().tobytes()
    assert not np.array_equal(p[0], p[-1])  # the gravities made a difference


def test_batch_state_in_and_out_and_per_world_access():
    batch = inertia.Batch([PENDULUM, PENDULUM, PENDULUM], threads=2)  # a list: one world each
    p = batch.positions()
    p[:, 2, 1] = [1, 2, 3]  # lift the boxes by different heights
    batch.set_positions(p)
    np.testing.assert_array_equal(batch.positions(), p)
    batch.set_linear_velocities(np.zeros((3, 3, 3)))
    world = batch[1]
    assert isinstance(world, inertia.World) and batch[-1] is batch[2]
    box = world.find_body("box")
    world.apply_impulse(box, (1000, 0, 0))  # only world 1's box is pushed
    batch.step()
    v = batch.linear_velocities()
    assert v[1, 2, 0] > 0 and v[0, 2, 0] == 0 and v[2, 2, 0] == 0
    assert world.step_count == 1


def test_batch_errors():
    with pytest.raises(ValueError, match="positions"):
        inertia.Batch(PENDULUM, 2).set_positions(np.zeros((2, 2, 3)))
    other = copy.deepcopy(PENDULUM)
    other["bodies"].pop()
    with pytest.raises(ValueError, match="bodies"):
        inertia.Batch([PENDULUM, other])
    with pytest.raises(ValueError, match="gravity"):
        inertia.Batch(PENDULUM, 2, gravity=np.zeros((3, 3)))
    with pytest.raises(inertia.SceneError):
        inertia.Batch({"bodies": [{"typo": 1}]}, 2)
    with pytest.raises(IndexError):
        inertia.Batch(PENDULUM, 2)[2]
