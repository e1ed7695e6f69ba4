"""State as NumPy arrays: copies for bodies, views of the pool's memory for particles."""

import gc

import numpy as np
import pytest

import inertia
from conftest import ball_world


def test_body_arrays_have_the_documented_shapes_and_dtype():
    world, ground, ball = ball_world(height=5)
    p, q = world.positions(), world.orientations()
    assert p.shape == (2, 3) and q.shape == (2, 4) and p.dtype == inertia.real_dtype
    assert world.linear_velocities().shape == (2, 3)
    assert world.angular_velocities().shape == (2, 3)
    assert world.bodies() == [ground, ball]
    np.testing.assert_array_equal(p[1], world.position(ball))
    np.testing.assert_array_equal(q[1], (1, 0, 0, 0))


def test_body_arrays_round_trip_and_writing_them_moves_the_bodies():
    world = inertia.World(gravity=(0, 0, 0))
    bodies = [world.create_body() for _ in range(4)]
    for b in bodies:
        world.add_shape(b, inertia.Sphere(0.1))
    rng = np.random.default_rng(1)
    p = rng.uniform(-10, 10, (4, 3)).astype(inertia.real_dtype)
    v = rng.uniform(-1, 1, (4, 3)).astype(inertia.real_dtype)
    # Half turns about the axes: unit quaternions that normalising leaves bit for bit.
    q = np.eye(4, dtype=inertia.real_dtype)
    world.set_positions(p)
    world.set_orientations(q)
    world.set_linear_velocities(v)
    world.set_angular_velocities(np.zeros((4, 3)))  # float64 in, converted
    np.testing.assert_array_equal(world.positions(), p)
    np.testing.assert_array_equal(world.orientations(), q)
    world.set_orientations(2 * q)  # normalised on the way in
    np.testing.assert_array_equal(world.orientations(), q)
    np.testing.assert_array_equal(world.linear_velocities(), v)
    # Without gravity each flies straight: x + v t after one step (rounding of 4 substeps).
    world.step()
    np.testing.assert_allclose(world.positions(), p + v / 60, atol=1e-5)


def test_particle_arrays_alias_the_pool_and_writes_move_particles():
    # Views are read-only (the pool trusts its values; writes are checked by set_particle_*),
    # and they see what those writes do.
    world = inertia.World()
    ps = world.create_particle_system(name="dust", capacity=100)
    world.add_emitter(ps, inertia.Emitter(burst=10, lifetime=float("inf"), speed=0))
    world.step()
    assert world.particle_count(ps) == 10
    a, b = world.particle_positions(ps), world.particle_positions(ps)
    assert a.shape == (10, 3) and a.dtype == inertia.real_dtype
    assert np.shares_memory(a, b)  # the same memory: no copy
    with pytest.raises(ValueError, match="read-only"):
        a[0] = 1
    world.set_particle_positions(ps, np.arange(30).reshape(10, 3))
    np.testing.assert_array_equal(a, np.arange(30).reshape(10, 3))  # the view sees the write
    v = world.particle_velocities(ps)
    world.set_particle_velocities(ps, np.tile((0, 1, 0), (10, 1)))  # no fields: they coast
    np.testing.assert_array_equal(v[:, 1], 1)
    world.step()
    np.testing.assert_allclose(a[:, 1], np.arange(30).reshape(10, 3)[:, 1] + 1 / 60, atol=1e-5)
    world.set_particle_velocities(ps, np.zeros((10, 3)))
    np.testing.assert_array_equal(v, 0)
    assert world.particle_ids(ps).tolist() == list(range(10))
    with pytest.raises(ValueError, match="positions"):
        world.set_particle_positions(ps, np.zeros((9, 3)))


def test_a_view_keeps_its_world_alive():
    world = inertia.World()
    ps = world.create_particle_system(capacity=4)
    world.add_emitter(ps, inertia.Emitter(burst=4, lifetime=float("inf")))
    world.step()
    view = world.particle_positions(ps)
    expected = view.copy()
    del world
    gc.collect()
    np.testing.assert_array_equal(view, expected)  # still the pool's memory, still alive
