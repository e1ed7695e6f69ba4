"""Bad input raises a Python exception naming the JSON pointer or the argument, and the
interpreter goes on (every test below runs in the same process)."""

import json
import re
import threading

import numpy as np
import pytest

import inertia
from conftest import SOURCE_DIR, ball_world


def test_scene_errors_carry_file_and_json_pointer(tmp_path):
    path = tmp_path / "typo.json"
    path.write_text(json.dumps({"world": {"gravty": [0, -9.81, 0]}}))
    with pytest.raises(inertia.SceneError) as e:
        inertia.load_scene(str(path))
    assert e.value.pointer == "/world/gravty"
    assert e.value.file == str(path)
    assert "gravty" in str(e.value) and isinstance(e.value, ValueError)

    with pytest.raises(inertia.SceneError) as e:
        inertia.load_scene(str(tmp_path / "missing.json"))
    assert e.value.reason == "no such file" and e.value.pointer == ""


def test_parse_scene_reports_pointers_into_dicts():
    scene = {
        "bodies": [
            {"name": "a", "shapes": [{"type": "sphere", "radius": 0.5}]},
            {"name": "b", "shapes": [{"type": "sphere", "radius": -1}]},
        ]
    }
    with pytest.raises(inertia.SceneError) as e:
        inertia.parse_scene(scene)
    assert e.value.pointer.startswith("/bodies/1/shapes/0")
    scene["bodies"][1]["shapes"][0]["radius"] = 0.5
    scene["joints"] = [{"type": "hinge", "body_a": "a", "body_b": "nobody"}]
    with pytest.raises(inertia.SceneError) as e:
        inertia.parse_scene(scene)
    assert e.value.pointer.startswith("/joints/0")
    with pytest.raises(inertia.SceneError) as e:
        inertia.parse_scene("{ not json", name="inline.json")
    assert e.value.file == "inline.json:1:4"  # syntax errors name the line and column


@pytest.mark.parametrize(
    "make, argument",
    [
        (lambda: inertia.Sphere(-1), "radius"),
        (lambda: inertia.Sphere(float("nan")), "radius"),
        (lambda: inertia.Box((1, 1)), "half_extents"),
        (lambda: inertia.Box(None), "half_extents"),
        (lambda: inertia.Box("big"), "half_extents"),
        (lambda: inertia.Material(density=-5), "density"),
        (lambda: inertia.World(dt=0), "dt"),
        (lambda: inertia.World(substeps=1000), "substeps"),
        (lambda: inertia.World(solver="magic"), "solver"),
        (lambda: inertia.World(gravity=(0, 1)), "gravity"),
        (lambda: inertia.ConvexHull([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), "point"),
        (lambda: inertia.TriangleMesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 7]]), "ndex"),
        (lambda: inertia.HeightField([[1, 2], [3]], 1), "heights"),
        (lambda: inertia.Compound([]), "child"),
        (lambda: inertia.Compound([(inertia.Sphere(1), (0, 0, 0), (0, 0, 0, 0))]), "quaternion"),
        (lambda: inertia.Compound([inertia.Sphere(1)]), "children"),
        (lambda: inertia.SixDofJoint(frame_a=(1, 2)), "frame_a"),
        (lambda: inertia.SixDofJoint(axes=[1] * 6), "axes"),
        (lambda: inertia.Emitter(speed=(1,)), "speed"),
        (lambda: inertia.World().create_particle_system(capacity=2**40), "capacity"),
        (lambda: inertia.Batch({}, 0), "world"),
    ],
)
def test_bad_values_raise_value_errors_naming_them(make, argument):
    with pytest.raises(ValueError, match=argument):
        make()


def test_bad_body_arguments():
    world, ground, ball = ball_world()
    with pytest.raises(ValueError, match="position"):
        world.create_body(position=(1, 2))
    with pytest.raises(ValueError, match="type"):
        world.create_body(type="floating")
    with pytest.raises(ValueError, match="finite"):
        world.set_position(ball, (0, float("nan"), 0))
    with pytest.raises(ValueError, match="finite"):
        world.set_linear_velocity(ball, (np.inf, 0, 0))
    with pytest.raises(ValueError, match="shape"):
        world.add_shape(ball, "sphere")
    with pytest.raises(ValueError, match="[Pp]lane"):  # planes go on static bodies only
        world.add_shape(ball, inertia.Plane())
    with pytest.raises(ValueError, match="dt"):
        world.step(-1)
    with pytest.raises(ValueError, match="frame_time"):
        world.advance(float("nan"))
    with pytest.raises(ValueError, match="max_steps"):
        world.advance(0.1, max_steps=0)
    with pytest.raises(ValueError, match="positions"):
        world.set_positions(np.zeros((3, 3)))  # two bodies
    with pytest.raises(ValueError, match="direction"):
        world.cast_ray((0, 0, 0), (0, 0, 0))
    with pytest.raises(KeyError):
        world.find_body("nobody")
    world.destroy_body(ball)
    with pytest.raises(ValueError, match="invalid body id"):
        world.position(ball)
    with pytest.raises(TypeError):
        world.position(None)
    assert not world.is_valid(ball) and world.is_valid(ground)


def test_bad_joint_arguments():
    world, ground, ball = ball_world()
    with pytest.raises(TypeError, match="anchr_a"):
        inertia.HingeJoint(body_b=ball, anchr_a=(0, 1, 0))
    with pytest.raises(ValueError, match="limits"):
        inertia.HingeJoint(body_b=ball, limits=(1, 2, 3))
    with pytest.raises(ValueError, match="body_b"):
        inertia.HingeJoint(body_b="ball")
    with pytest.raises(ValueError, match="motor"):
        inertia.HingeJoint(body_b=ball, motor=(1, 2))
    with pytest.raises(ValueError):  # a body joined to itself
        world.create_joint(inertia.BallJoint(body_a=ball, body_b=ball))
    with pytest.raises(ValueError):  # lower limit above the upper
        world.create_joint(inertia.HingeJoint(body_b=ball, limits=(1, -1)))
    with pytest.raises(ValueError, match="axis"):
        world.create_joint(inertia.SliderJoint(body_b=ball, axis_a=(0, 0, 0)))


def emitted(world, capacity, burst):
    """A particle system of `world` holding `burst` immortal particles after one step."""
    ps = world.create_particle_system(capacity=capacity)
    world.add_emitter(ps, inertia.Emitter(burst=burst, lifetime=float("inf")))
    world.step()
    return ps


def test_particle_system_with_live_views_is_not_destroyed():
    world = inertia.World()
    ps = emitted(world, 10, 5)
    view = world.particle_positions(ps)
    with pytest.raises(ValueError, match="view"):
        world.destroy_particle_system(ps)
    del view
    world.destroy_particle_system(ps)
    assert not world.is_valid(ps)
    with pytest.raises(ValueError):
        world.particle_positions(ps)
    with pytest.raises(ValueError, match="shape"):
        inertia.Emitter(shape="torus")


def test_restore_state_is_refused_while_views_are_alive():
    # Restoring a snapshot taken before the system existed frees its pool: a view kept across
    # it read freed memory (a segmentation fault before the refusal).
    world = inertia.World()
    empty = world.save_state()
    ps = emitted(world, 100, 50)
    view = world.particle_positions(ps)
    with pytest.raises(ValueError, match="restore_state: 1 NumPy arrays still view"):
        world.restore_state(empty)
    assert world.is_valid(ps) and world.particle_count(ps) == 50  # nothing restored
    del view
    world.restore_state(empty)
    assert not world.is_valid(ps)


def polls_refused(target, poll):
    """Runs target() on a thread and calls poll() here until one is refused or it ends."""
    thread = threading.Thread(target=target)
    refused = None
    thread.start()
    while thread.is_alive() and refused is None:
        try:
            poll()
        except RuntimeError as e:
            refused = str(e)
    thread.join()
    return refused


def test_a_world_being_stepped_refuses_other_threads():
    # Steps run without the GIL, and this thread polls meanwhile. 60 steps of a pyramid of 55
    # boxes take a few tenths of a second: a poll meets one of them.
    scene = str(SOURCE_DIR / "scenes" / "pyramid.json")
    world = inertia.load_scene(scene)
    refused = polls_refused(lambda: world.advance(1.1, max_steps=60), world.positions)
    assert "another thread is stepping" in refused
    assert world.step_count == 60 and world.positions().shape[1] == 3  # usable again
    batch = inertia.Batch(scene, 2)
    refused = polls_refused(lambda: batch[1].advance(1.1, max_steps=60), batch.positions)
    assert "another thread is stepping" in refused
    refused = polls_refused(lambda: batch.step(60), lambda: batch[0].time)
    assert "another thread is stepping" in refused


def test_particle_writes_must_be_finite():
    world = inertia.World()
    ps = emitted(world, 10, 2)
    with pytest.raises(ValueError, match="finite"):
        world.set_particle_positions(ps, [[0, 0, 0], [0, np.nan, 0]])
    with pytest.raises(ValueError, match="finite"):
        world.set_particle_velocities(ps, [[0, 0, 0], [np.inf, 0, 0]])


def _jointed(settings):
    world, _, ball = ball_world()
    return world.create_joint(settings(ball))


def _with_link(**kwargs):
    model = inertia.ArticulationModel()
    return model.add_link(mass=1.0, inertia=(1, 1, 1), **kwargs)


def _in_system(item):
    world = inertia.World()
    system = world.create_particle_system()
    if isinstance(item, inertia.Emitter):
        return world.add_emitter(system, item)
    return world.add_field(system, item)


# Every numeric keyword of the API's constructors and create_* calls, with how to make the
# object that reads it: (name, make(**{keyword: value}), the keywords).
KEYWORDS = [
    ("World", lambda **k: inertia.World(**k), ["gravity", "dt", "joint_hertz",
                                                "joint_damping_ratio"]),
    ("create_body", lambda **k: ball_world()[0].create_body(**k),
     ["position", "orientation", "velocity", "angular_velocity", "linear_damping",
      "angular_damping", "gravity_scale", "mass", "inertia"]),
    ("Material", lambda **k: inertia.Material(**k),
     ["density", "friction", "dynamic_friction", "restitution", "rolling_friction",
      "spinning_friction"]),
    ("Capsule", lambda **k: inertia.Capsule(**k), ["radius", "half_height"]),
    ("Cylinder", lambda **k: inertia.Cylinder(**k), ["radius", "half_height"]),
    ("Plane", lambda **k: inertia.Plane(**k), ["normal", "offset"]),
    ("Box", lambda **k: inertia.Box(**k), ["half_extents"]),
    ("JointMotor", lambda **k: _jointed(
        lambda b: inertia.HingeJoint(body_b=b, motor=inertia.JointMotor(**k))),
     ["speed", "max_force", "target", "servo_frequency"]),
    ("JointSpring", lambda **k: _jointed(
        lambda b: inertia.HingeJoint(body_b=b, spring=inertia.JointSpring(**k))),
     ["frequency", "damping_ratio", "rest"]),
    ("BallJoint", lambda **k: _jointed(lambda b: inertia.BallJoint(body_b=b, **k)),
     ["anchor_a", "anchor_b", "axis_a", "axis_b", "cone_limit", "friction", "break_force",
      "break_torque"]),
    ("SliderJoint", lambda **k: _jointed(lambda b: inertia.SliderJoint(body_b=b, **k)),
     ["anchor_a", "axis_a", "friction"]),
    ("DistanceJoint", lambda **k: _jointed(lambda b: inertia.DistanceJoint(body_b=b, **k)),
     ["length", "min_length", "max_length"]),
    ("Emitter", lambda **k: _in_system(inertia.Emitter(**k)),
     ["position", "radius", "angle", "rate", "direction", "spread", "speed", "lifetime", "mass",
      "size"]),
    ("VortexField", lambda **k: _in_system(inertia.VortexField(**k)),
     ["center", "axis", "angular_speed", "core_radius", "tightness"]),
    ("AttractorField", lambda **k: _in_system(inertia.AttractorField(**k)),
     ["position", "strength", "cutoff", "min_distance"]),
    ("TurbulenceField", lambda **k: _in_system(inertia.TurbulenceField(**k)),
     ["amplitude", "scale", "speed"]),
    ("WindField", lambda **k: _in_system(inertia.WindField(**k)), ["velocity", "k"]),
    ("Drive", lambda **k: _with_link(drive=inertia.Drive(**k)),
     ["stiffness", "damping", "target", "target_velocity", "max_force"]),
    ("add_link", _with_link,
     ["axis", "origin_position", "origin_orientation", "limits", "damping", "friction",
      "armature", "velocity_limit"]),
    ("rope", lambda **k: inertia.rope(**k), ["start", "end", "mass", "stretch", "bend", "damping"]),
    ("cloth", lambda **k: inertia.cloth(**k), ["size", "mass", "stretch", "shear", "bend"]),
    ("hair", lambda **k: inertia.hair(**k), ["radius", "cap_angle", "length", "mass"]),
]
# How many numbers each keyword takes where it is not one: NaN goes into the first.
VECTORS = {"gravity": 3, "position": 3, "orientation": 4, "velocity": 3, "angular_velocity": 3,
           "inertia": 3, "normal": 3, "anchor_a": 3, "anchor_b": 3, "axis_a": 3, "axis_b": 3,
           "direction": 3, "center": 3, "axis": 3, "start": 3, "end": 3, "origin_position": 3,
           "origin_orientation": 4, "limits": 2, "half_extents": 3}
PAIRS = {("Emitter", k) for k in ("speed", "lifetime", "mass", "size")} | {("cloth", "size")}


@pytest.mark.parametrize("where, make, keyword",
                         [(w, m, k) for w, m, keywords in KEYWORDS for k in keywords])
def test_every_numeric_keyword_refuses_nan_by_its_python_name(where, make, keyword):
    """The message names the keyword the caller wrote, not the C++ field behind it: no
    `Type::` qualifier and no camelCase (pythonMessage)."""
    n = 2 if (where, keyword) in PAIRS else VECTORS.get(keyword, 1)
    value = float("nan") if n == 1 else tuple([float("nan")] + [1.0] * (n - 1))
    with pytest.raises(ValueError) as e:
        make(**{keyword: value})
    message = str(e.value)
    assert re.search(rf"\b{keyword}\b", message), message
    assert "::" not in message and not re.search(r"\b[a-z]+[A-Z]\w*", message), message
