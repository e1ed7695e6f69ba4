"""Bodies, contacts and ray casts against closed forms."""

import numpy as np
import pytest

import inertia
from conftest import ball_world


def test_free_fall_matches_the_symplectic_euler_closed_form():
    # No ground: the ball flies free. Symplectic Euler over k substeps of tau gives exactly
    # v_k = v0 + g k tau and x_k = x0 + v0 t + g t^2 / 2 + g t tau / 2 (t = k tau): the closed
    # form of the true motion plus the method's first-order error g t tau / 2.
    g, dt, substeps, steps = -9.81, 1 / 60, 4, 60
    world = inertia.World(gravity=(0, g, 0), dt=dt, substeps=substeps)
    ball = world.create_body(position=(0, 100, 0), velocity=(1, 2, 0))
    world.add_shape(ball, inertia.Sphere(0.5))
    for _ in range(steps):
        world.step()
    t = world.time
    tau = np.float32(dt) / substeps
    p, v = world.position(ball), world.linear_velocity(ball)
    # Float rounding: 240 additions to a 100 m position, each off by at most half an ulp
    # (3.8e-6 m at 100 m), bound the drift at 240 * 3.8e-6 = 9e-4 m; velocities at 10 m/s,
    # 240 * 4.8e-7 = 1.2e-4 m/s.
    assert t == pytest.approx(1.0, abs=1e-6)
    assert v[1] == pytest.approx(2 + g * t, abs=1.2e-4)
    assert v[0] == 1 and v[2] == 0
    exact = 100 + 2 * t + g * t * t / 2
    assert p[1] == pytest.approx(exact + g * t * tau / 2, abs=9e-4)
    # ... and the method's error is what the closed form predicts (0.0204 m), not noise.
    assert exact - p[1] == pytest.approx(-g * t * tau / 2, abs=9e-4)
    assert p[0] == pytest.approx(1 * t, abs=1e-5)


@pytest.mark.parametrize("integrator", ["velocity_verlet", "rk4"])
def test_free_fall_is_exact_with_second_order_methods(integrator):
    # Velocity Verlet and RK4 integrate a constant acceleration exactly: only rounding is left
    # (the same bound as above).
    world = inertia.World(gravity=(0, -9.81, 0), integrator=integrator)
    ball = world.create_body(position=(0, 100, 0), velocity=(1, 2, 0))
    world.add_shape(ball, inertia.Sphere(0.5))
    for _ in range(60):
        world.step()
    t = world.time
    assert world.position(ball)[1] == pytest.approx(100 + 2 * t - 9.81 * t * t / 2, abs=9e-4)


def test_ball_comes_to_rest_on_the_ground_with_its_weight_carried():
    world, ground, ball = ball_world(height=2, dt=1 / 60, substeps=4)
    began = []
    for _ in range(300):
        world.step()
        began += world.contact_begin_events()
    assert world.position(ball)[1] == pytest.approx(0.5, abs=0.01)  # linear slop 5 mm
    assert len(began) >= 1 and {began[0].body_a, began[0].body_b} == {ground, ball}
    contacts = [c for c in world.contacts() if ball in (c.body_a, c.body_b)]
    assert len(contacts) == 1
    # At rest the last substep's impulse carries the weight over a substep: m g dt / substeps.
    mass = world.mass(ball)
    assert mass == pytest.approx(1000 * 4 / 3 * np.pi * 0.5**3, rel=1e-5)
    impulse = contacts[0].normal_impulses.sum()
    assert impulse == pytest.approx(mass * 9.81 / 60 / 4, rel=0.02)
    assert contacts[0].points_a.shape == (len(contacts[0].normal_impulses), 3)


def test_ray_cast_hits_the_ball_then_the_ground():
    world, ground, ball = ball_world(height=3)
    hit = world.cast_ray((0, 10, 0), (0, -1, 0))
    assert hit.body == ball and hit.distance == pytest.approx(10 - 3.5, abs=1e-5)
    np.testing.assert_allclose(hit.normal, (0, 1, 0), atol=1e-6)
    hit = world.cast_ray((2, 10, 0), (0, -2, 0))  # the direction need not be unit
    assert hit.body == ground and hit.distance == pytest.approx(10, abs=1e-5)
    np.testing.assert_allclose(hit.point, (2, 0, 0), atol=1e-5)
    assert world.cast_ray((2, 10, 0), (0, -1, 0), max_distance=9) is None
    assert world.cast_ray((0, 10, 0), (0, 1, 0)) is None


def test_advance_takes_whole_fixed_steps():
    world, _, _ = ball_world()
    assert world.advance(0.06) == 3  # 3 steps of 1/60 s, and 0.6 of a step left over
    assert world.step_count == 3
    assert world.interpolation_alpha == pytest.approx(0.6, abs=1e-5)
    assert world.advance(1.0, max_steps=8) == 8  # the rest of the long frame is dropped


def test_forces_and_impulses_change_momentum_by_their_impulse():
    world = inertia.World(gravity=(0, 0, 0))
    body = world.create_body()
    world.add_shape(body, inertia.Box((0.5, 0.5, 0.5)), inertia.Material(density=8))  # 8 kg
    world.apply_impulse(body, (8, 0, 0))  # 1 m/s at once
    assert world.linear_velocity(body)[0] == pytest.approx(1)
    world.apply_force(body, (0, 16, 0))  # 16 N over one step of 1/60 s: 2/60 m/s
    world.step()
    np.testing.assert_allclose(world.linear_momentum(), (8, 16 / 60, 0), rtol=1e-6)


def test_filtered_ball_falls_through_the_ground_as_in_free_fall():
    # The ground in category 4, the ball's mask without it: no contact, so the ball follows
    # the free fall's symplectic Euler closed form of the test above (its bound: 9e-4 m).
    g, dt, substeps, steps = -9.81, 1 / 60, 4, 60
    world = inertia.World(gravity=(0, g, 0), dt=dt, substeps=substeps)
    ground = world.create_body(type="static")
    world.set_filter(world.add_shape(ground, inertia.Plane((0, 1, 0), 0)), category=4)
    ball = world.create_body(position=(0, 1, 0))
    shape = world.add_shape(ball, inertia.Sphere(0.5))
    world.set_filter(shape, mask=0xFFFFFFFF & ~4)
    assert world.filter(shape) == (1, 0xFFFFFFFB, 0)
    for _ in range(steps):
        world.step()
    t, tau = world.time, np.float32(dt) / substeps
    assert world.position(ball)[1] == pytest.approx(1 + g * t * t / 2 + g * t * tau / 2, abs=9e-4)
    with pytest.raises(TypeError):
        world.set_filter(shape, category=-1)
