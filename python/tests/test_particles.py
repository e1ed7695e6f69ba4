"""Particle systems built from Python: fields, obstacles and emitters do what they say."""

import numpy as np
import pytest

import inertia


def fountain(**settings):
    world = inertia.World()
    ps = world.create_particle_system(name="drops", capacity=100, **settings)
    world.add_emitter(ps, inertia.Emitter(burst=20, speed=0, lifetime=float("inf"), size=0.01,
                                          position=(0, 1, 0), shape="sphere", radius=0.2))
    world.add_field(ps, inertia.GravityField(g=(0, -9.81, 0)))
    return world, ps


def test_gravity_field_accelerates_every_particle_alike():
    world, ps = fountain()
    for _ in range(30):
        world.step()
    # Symplectic Euler integrates the velocity of a constant acceleration exactly: v = g a for
    # every particle (released at rest), a its age (a burst leaves during the first step, each
    # particle at its own time, so it has flown for its age, not the world's time), up to float
    # rounding of 30 additions to v (30 ulp of 5 m/s) and to the age (30 ulp of 0.5 s, times g).
    v = world.particle_velocities(ps)
    assert v.shape == (20, 3)
    ages = world.particle_ages(ps)
    assert np.all((ages > world.time - 1 / 60) & (ages <= world.time))
    np.testing.assert_allclose(v[:, 1], -9.81 * ages, atol=30 * 4.8e-7 + 9.81 * 30 * 6e-8)
    np.testing.assert_array_equal(v[:, [0, 2]], 0)
    assert world.particle_stats(ps) == {"alive": 20, "emitted": 20, "died": 0, "dropped": 0}
    assert world.particle_system_name(ps) == "drops" and world.particle_systems() == [ps]


def test_plane_obstacle_catches_the_particles():
    world, ps = fountain(restitution=0.0)
    world.add_obstacle(ps, inertia.Plane((0, 1, 0), 0))
    for _ in range(120):
        world.step()
    # They rest on the plane at their radius (0.01 m) above it; continuous collision lets none
    # through.
    np.testing.assert_allclose(world.particle_positions(ps)[:, 1], 0.01, atol=1e-4)


def test_fields_limited_to_a_region_and_lifetimes():
    world = inertia.World()
    ps = world.create_particle_system(capacity=50)
    world.add_emitter(ps, inertia.Emitter(burst=10, speed=0, lifetime=0.5))
    world.add_field(ps, inertia.WindField(velocity=(1, 0, 0), k=10),
                    region=((5, 5, 5), (6, 6, 6)))  # far away: no wind here
    for _ in range(10):
        world.step()
    np.testing.assert_array_equal(world.particle_velocities(ps), 0)
    for _ in range(30):
        world.step()
    assert world.particle_count(ps) == 0  # 0.5 s lifetimes, 0.67 s gone by
    assert world.particle_stats(ps)["died"] == 10
