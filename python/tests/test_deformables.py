"""Deformables from Python: the generators' models, creation, fields and obstacles, and the
vertices as (n, 3) arrays that alias the deformable's memory."""

import gc

import numpy as np
import pytest

import inertia

G = 9.81
H = 1 / 60


def world_with(model, **settings):
    world = inertia.World(dt=H)
    d = world.create_deformable(model, **settings)
    world.add_deformable_field(d, inertia.GravityField((0, -G, 0)))
    return world, d


def test_generators_build_the_documented_models():
    rope = inertia.rope(start=(0, 0, 0), end=(2, 0, 0), segments=4, mass=2)
    assert rope.vertex_count == 5
    np.testing.assert_allclose(rope.positions[:, 0], [0, 0.5, 1, 1.5, 2], atol=1e-6)
    np.testing.assert_allclose(rope.masses, 0.4, rtol=1e-6)  # 2 kg spread evenly
    assert rope.spring_count == 4 + 3  # stretch between neighbours, bend from i to i + 2
    cloth = inertia.cloth(size=(1, 2), resolution=(2, 3), pinned=[0, 2])
    assert cloth.vertex_count == 3 * 4 and cloth.triangle_count == 2 * 2 * 3
    assert cloth.pinned == [0, 2]
    assert inertia.soft_sphere(subdivisions=1).vertex_count == 10 * 4 + 2 + 1  # and the centre
    assert inertia.soft_box(resolution=[1, 2, 3]).vertex_count == 2 * 3 * 4
    hair = inertia.hair(strands=20, segments=4, radius=0.1, length=0.3)
    assert hair.vertex_count == 20 * 5 and hair.pinned == list(range(0, 100, 5))
    np.testing.assert_allclose(np.linalg.norm(hair.positions[::5], axis=1), 0.1, rtol=1e-5)
    corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
               (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    faces = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
             (3, 7, 6), (3, 6, 2), (0, 4, 7), (0, 7, 3), (1, 2, 6), (1, 6, 5)]
    soft = inertia.soft_mesh(inertia.TriangleMesh(corners, faces), resolution=2)
    assert soft.vertex_count == 8 + 8 and soft.triangle_count == 12  # corners, then centres
    np.testing.assert_allclose(soft.positions[8], (0.25, 0.25, 0.25), atol=1e-6)
    with pytest.raises(ValueError, match="closed"):
        inertia.soft_mesh(inertia.TriangleMesh(corners, faces[:-1]))


def test_free_fall_follows_the_implicit_steps_closed_form():
    # Springs at rest moving as one carry no force, so every vertex gains h g a step and
    # x_N = x_0 + g h^2 N (N + 1) / 2 (backward Euler's positions use the new velocities).
    world, d = world_with(inertia.cloth(position=(0, 10, 0), resolution=(4, 4)))
    start = world.deformable_positions(d).copy()
    n = 60
    for _ in range(n):
        world.step()
    drop = G * H * H * n * (n + 1) / 2  # 4.987 m
    moved = world.deformable_positions(d) - start
    # The solve stops at a relative residual of 1e-6 (5e-6 m over the drop), and each of the 60
    # steps rounds float positions near 5 m (ulp 4.8e-7): 3e-5 m covers both.
    np.testing.assert_allclose(moved[:, 1], -drop, atol=3e-5)
    np.testing.assert_allclose(moved[:, [0, 2]], 0, atol=3e-5)
    np.testing.assert_allclose(world.deformable_velocities(d)[:, 1], -G * H * n, rtol=1e-5)


def test_a_hanging_spring_settles_at_m_g_over_k():
    # A one-segment rope pinned at the top: the bottom vertex (half of 1 kg) hangs where the
    # spring holds its weight, extension m g / k; backward Euler's fixed point is that
    # equilibrium exactly, so the residual is rounding: spring forces from float positions near
    # 1 m (ulp 1.2e-7) give an extension good to a few ulps, 1e-6 m.
    k, m = 5000.0, 0.5
    world, d = world_with(
        inertia.rope(start=(0, 0, 0), end=(0, -1, 0), segments=1, mass=2 * m, stretch=k,
                     damping=20, pinned=[0]))
    for _ in range(600):
        world.step()
    p = world.deformable_positions(d)
    np.testing.assert_array_equal(p[0], (0, 0, 0))  # pinned
    assert -p[1, 1] - 1 == pytest.approx(m * G / k, abs=1e-6)
    assert np.abs(world.deformable_velocities(d)).max() < 1e-5
    e = world.deformable_energy(d)
    assert e["spring"] == pytest.approx(0.5 * k * (m * G / k) ** 2, rel=1e-2)


def test_a_cloth_lands_on_a_plane_obstacle_at_its_thickness():
    world, d = world_with(inertia.cloth(position=(0, 0.5, 0)), thickness=0.02)
    world.add_deformable_obstacle(d, inertia.Plane((0, 1, 0), 0))
    for _ in range(120):
        world.step()
    y = world.deformable_positions(d)[:, 1]
    # Pushed out at the end of every step to the thickness and the library's skin of 1e-3 of it
    # (src/deformable/obstacle_collision.cpp: a resting vertex stays outside), 0.02002 m; the
    # float sum rounds by an ulp of 0.02 (1.9e-9), and 1e-7 m covers it.
    np.testing.assert_allclose(y, 0.02 * 1.001, atol=1e-7)


def test_vertex_arrays_alias_and_write_back():
    world, d = world_with(inertia.rope(segments=3))
    view = world.deformable_positions(d)
    assert not view.flags.writeable and view.shape == (4, 3) and view.dtype == inertia.real_dtype
    world.step()
    np.testing.assert_array_equal(view, world.deformable_positions(d))  # it followed the step
    assert view[0, 1] < 0
    world.set_deformable_positions(d, np.zeros((4, 3)) + (1, 2, 3))
    np.testing.assert_array_equal(view, np.tile((1, 2, 3), (4, 1)))
    world.set_deformable_velocities(d, np.ones((4, 3)))
    np.testing.assert_array_equal(world.deformable_velocities(d), 1)
    world.set_vertex_pinned(d, 0)
    assert world.is_vertex_pinned(d, 0) and not world.is_vertex_pinned(d, 1)
    np.testing.assert_array_equal(world.deformable_velocities(d)[0], 0)
    np.testing.assert_allclose(world.deformable_masses(d), 0.25)
    assert world.deformable_springs(d).tolist() == [[0, 1], [1, 2], [2, 3], [0, 2], [1, 3]]
    assert not world.deformable_broken(d).any()
    # Destroying a deformable with views alive is refused; the views keep the world alive.
    with pytest.raises(ValueError, match="still view"):
        world.destroy_deformable(d)
    del view
    gc.collect()
    world.destroy_deformable(d)
    assert not world.is_valid(d) and world.deformables() == []
    other, e = world_with(inertia.rope())
    view = other.deformable_velocities(e)
    del other
    gc.collect()
    assert view.shape == (11, 3)


def test_deformable_errors_name_the_argument():
    with pytest.raises(ValueError):
        inertia.rope(segments=0)
    with pytest.raises(ValueError, match="pinned"):
        inertia.rope(segments=2, pinned=[3])
    with pytest.raises(ValueError, match="resolution"):
        inertia.soft_box(resolution=[1, 2])
    world = inertia.World()
    with pytest.raises(ValueError, match="integrator"):
        world.create_deformable(inertia.rope(), integrator="nope")
    with pytest.raises(ValueError, match="linear_solver"):
        world.create_deformable(inertia.rope(), linear_solver="cholesky")
    with pytest.raises(ValueError, match="thickness"):
        world.create_deformable(inertia.rope(), thickness=-1)
    d = world.create_deformable(inertia.rope(segments=2))
    with pytest.raises(ValueError, match="positions"):
        world.set_deformable_positions(d, np.zeros((2, 3)))
    with pytest.raises(ValueError, match="finite"):
        world.set_deformable_velocities(d, np.full((3, 3), np.nan))
    with pytest.raises(IndexError):
        world.set_vertex_pinned(d, 3)
    with pytest.raises(ValueError, match="field"):
        world.add_deformable_field(d, "gravity")
    world.destroy_deformable(d)
    with pytest.raises(ValueError):
        world.deformable_positions(d)
