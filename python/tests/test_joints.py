"""Joints made from Python are the scene files' joints: the same world, the same bytes."""

import numpy as np
import pytest

import inertia

SCENE = {
    "world": {"gravity": [0, -9.81, 0], "dt": 1 / 60, "substeps": 4},
    "bodies": [
        {"name": "bob", "position": [1, 2, 0],
         "shapes": [{"type": "sphere", "radius": 0.1, "material": {"density": 1000}}]},
        {"name": "cart", "position": [0, 0, 0],
         "shapes": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}]},
    ],
    "joints": [
        {"type": "hinge", "body_b": "bob", "anchor_a": [0, 2, 0], "anchor_b": [-1, 0, 0],
         "axis_a": [0, 0, 1], "axis_b": [0, 0, 1], "limits": [-1, 1],
         "spring": {"frequency": 1, "damping_ratio": 0.1, "rest": 0}},
        {"type": "slider", "body_b": "cart", "anchor_a": [0, 0, 0], "axis_a": [1, -1, 0],
         "limits": [-0.5, 0.5], "motor": {"speed": 0.5, "max_force": 2}},
    ],
}


def python_world():
    world = inertia.World(gravity=(0, -9.81, 0), dt=1 / 60, substeps=4)
    bob = world.create_body(position=(1, 2, 0), name="bob")
    world.add_shape(bob, inertia.Sphere(0.1), inertia.Material(density=1000))
    cart = world.create_body(name="cart")
    world.add_shape(cart, inertia.Box((0.2, 0.1, 0.1)))
    hinge = world.create_joint(inertia.HingeJoint(
        body_b=bob, anchor_a=(0, 2, 0), anchor_b=(-1, 0, 0), axis_a=(0, 0, 1), axis_b=(0, 0, 1),
        limits=(-1, 1), spring=inertia.JointSpring(frequency=1, damping_ratio=0.1)))
    slider = world.create_joint(inertia.SliderJoint(
        body_b=cart, axis_a=(1, -1, 0), limits=inertia.JointLimits(-0.5, 0.5),
        motor=inertia.JointMotor(speed=0.5, max_force=2)))
    return world, hinge, slider


def test_python_joints_step_as_the_scene_files_do():
    a, hinge, slider = python_world()
    b = inertia.parse_scene(SCENE)
    for _ in range(90):
        a.step()
        b.step()
    assert a.positions().tobytes() == b.positions().tobytes()
    assert a.orientations().tobytes() == b.orientations().tobytes()
    assert a.joint_type(hinge) == "hinge" and a.joint_type(slider) == "slider"
    assert a.joint_bodies(hinge) == (None, a.find_body("bob"))


def test_hinge_angle_and_slider_limits():
    world, hinge, slider = python_world()
    world.set_joint_spring(hinge, None)
    for _ in range(600):
        world.step()
    # Without its spring the bob swings down from horizontal onto the lower limit, -1 rad,
    # rebounds from it by up to 0.4 rad, and after 10 s rests there: gravity's torque
    # m g l cos(1) = 22 N m holds it against the limit. The limit is a soft row (120 Hz, the
    # README's joint stiffness) that gives way under that load by a few mrad: 0.01 rad covers
    # it and still tells resting from swinging.
    assert world.joint_coordinate(hinge) == pytest.approx(-1, abs=0.01)
    # The cart slides down its 45 degree rail (the motor's 2 N cannot hold m g sin 45 = 22 N),
    # along +axis, to the upper limit.
    assert world.joint_coordinate(slider) == pytest.approx(0.5, abs=0.01)
    position_error, angle_error = world.joint_error(slider)
    assert position_error < 1e-3 and angle_error < 1e-3
    force = world.joint_force(slider)
    assert force.shape == (3,)
    world.set_joint_motor(slider, None)
    world.set_joint_limits(slider, None)
    world.set_joint_enabled(hinge, False)
    assert not world.is_joint_enabled(hinge)
    world.destroy_joint(hinge)
    assert world.joints() == [slider] and world.joint_count == 1


def test_six_dof_axes_and_keyword_settings():
    world = inertia.World(gravity=(0, 0, 0))
    body = world.create_body(position=(0, 1, 0))
    world.add_shape(body, inertia.Sphere(0.2))
    axes = [inertia.JointAxis() for _ in range(6)]
    axes[3] = inertia.JointAxis(locked=False, limits=(-0.5, 0.5))
    settings = inertia.SixDofJoint(body_b=body, frame_a=((0, 1, 0), (1, 0, 0, 0)), axes=axes)
    assert settings.axes[3].limits.lower == -0.5 and settings.axes[0].locked
    joint = world.create_joint(settings)
    world.set_angular_velocity(body, (5, 0, 0))
    for _ in range(60):
        world.step()
    # Free about x within +-0.5 rad: it turned to the limit and stopped there.
    assert world.joint_axis_coordinate(joint, 3) == pytest.approx(0.5, abs=0.02)
    np.testing.assert_allclose(world.position(body), (0, 1, 0), atol=1e-3)


@pytest.mark.parametrize("hertz", [120, 60])
def test_joint_hertz_sets_the_sag_of_a_hanging_body(hertz):
    """A body hung at its centre on a ball joint sags by g / (2 pi joint_hertz)^2, the soft
    row's spring deflection (tests/dynamics/joint_solver_test.cpp: exact to float's rounding)."""
    world = inertia.World(joint_hertz=hertz, sleeping=False, threads=1)
    bob = world.create_body()
    world.add_shape(bob, inertia.Sphere(0.1), inertia.Material(density=1000))
    world.create_joint(inertia.BallJoint(body_b=bob))
    for _ in range(120):
        world.step()
    sag = 9.81 / (2 * np.pi * hertz) ** 2
    assert -world.position(bob)[1] == pytest.approx(sag, rel=1e-5)
