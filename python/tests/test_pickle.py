"""Worlds pickle (and so travel to Dask workers): a world made from a scene is rebuilt from the
scene and the steps it took, replayed; the library is deterministic, so the copy holds the same
bytes and continues bit-identically. A world built or changed through the API refuses, with a
message saying why, rather than pickling something that would continue differently."""

import copy
import pickle

import numpy as np
import pytest

import inertia
from conftest import SOURCE_DIR, ball_world
from test_state import run, state_bytes

PENDULUMS = str(SOURCE_DIR / "scenes" / "pendulums.json")


def test_pickled_world_continues_bit_identically():
    world = inertia.load_scene(PENDULUMS)
    run(world, 20)
    world.advance(0.05)  # an accumulator carried over too
    world.step(0.01)     # and a step of another length
    back = pickle.loads(pickle.dumps(world))
    assert back.step_count == world.step_count and back.time == world.time
    assert state_bytes(back) == state_bytes(world)
    first, second = run(world, 30), run(back, 30)
    assert first == second
    assert first[0] != first[-1]  # it moved
    # A copy is independent of the original, and pickles again.
    again = copy.deepcopy(back)
    back.step()
    assert state_bytes(again) != state_bytes(back)
    assert run(pickle.loads(pickle.dumps(again)), 1) == run(again, 1)


def test_scene_dicts_overrides_and_batch_worlds_pickle():
    scene = {"world": {"dt": 1 / 120},
             "bodies": [{"name": "ball", "position": [0, 3, 0],
                         "shapes": [{"type": "sphere", "radius": 0.5}]}]}
    world = inertia.parse_scene(scene, dt=1 / 240)
    run(world, 7)
    back = pickle.loads(pickle.dumps(world))
    assert back.dt == world.dt and state_bytes(back) == state_bytes(world)

    batch = inertia.Batch(scene, 3, gravity=[(0, -1, 0), (0, -2, 0), (0, -3, 0)])
    batch.step(5)
    copies = [pickle.loads(pickle.dumps(batch[i])) for i in range(3)]
    for i, c in enumerate(copies):
        np.testing.assert_array_equal(c.gravity, (0, -(i + 1), 0))
        assert state_bytes(c) == state_bytes(batch[i]) and c.step_count == 5


def test_worlds_changed_through_the_api_refuse_to_pickle():
    built, _, _ = ball_world()
    with pytest.raises(TypeError, match="built or changed through the API"):
        pickle.dumps(built)
    world = inertia.load_scene(PENDULUMS)
    world.step()
    pickle.dumps(world)
    world.set_linear_velocities(world.linear_velocities())  # a change pickling cannot replay
    with pytest.raises(TypeError, match="built or changed"):
        pickle.dumps(world)
    batch = inertia.Batch(PENDULUMS, 2)
    batch.set_positions(batch.positions())
    with pytest.raises(TypeError):
        pickle.dumps(batch[0])
    # Reading does not count as a change.
    world = inertia.load_scene(PENDULUMS)
    world.positions(), world.contacts(), world.save_state(), world.bodies()
    pickle.dumps(world)


def test_a_world_restored_to_its_own_snapshot_pickles_as_then():
    world = inertia.load_scene(PENDULUMS)
    run(world, 5)
    saved = world.save_state()
    run(world, 5)
    world.apply_force(world.bodies()[-1], (1, 0, 0))  # changed: no longer its scene's replay
    world.restore_state(saved)                         # but the snapshot's world is
    back = pickle.loads(pickle.dumps(world))
    assert back.step_count == 5 and run(back, 10) == run(world, 10)
    # Another world's snapshot: this world's settings with that world's bodies, no recipe.
    other = inertia.load_scene(PENDULUMS)
    other.restore_state(saved)
    with pytest.raises(TypeError, match="built or changed"):
        pickle.dumps(other)


def test_bad_pickled_states_raise():
    world = inertia.load_scene(PENDULUMS)
    cls, args, state = world.__reduce_ex__(2)[:3]
    blank = inertia.World.__new__(inertia.World)
    with pytest.raises((ValueError, TypeError)):
        blank.__setstate__((2,) + tuple(state[1:]))
    with pytest.raises((ValueError, TypeError)):
        inertia.World.__new__(inertia.World).__setstate__("nonsense")
    with pytest.raises(inertia.SceneError):
        inertia.World.__new__(inertia.World).__setstate__((1, b"{", "x.json", None, None, None, []))


def test_worlds_travel_through_dask_serialisation():
    # What a Dask client does to a World it sends to a worker process (cloudpickle underneath).
    protocol = pytest.importorskip("distributed.protocol")
    world = inertia.load_scene(PENDULUMS)
    run(world, 10)
    header, frames = protocol.serialize(world, serializers=["pickle"])
    back = protocol.deserialize(header, frames)
    assert run(back, 10) == run(world, 10)


def test_a_refused_destroy_leaves_the_world_picklable():
    # Refused while a view is alive, the destroy changed nothing: the world still follows its
    # scene and pickles (the check used to take the world as changed).
    for name, systems, view_of, destroy in (
            ("fountain", "particle_systems", "particle_positions", "destroy_particle_system"),
            ("flag", "deformables", "deformable_positions", "destroy_deformable")):
        world = inertia.load_scene(str(SOURCE_DIR / "scenes" / f"{name}.json"))
        world.step()
        target = getattr(world, systems)()[0]
        view = getattr(world, view_of)(target)
        with pytest.raises(ValueError, match="view"):
            getattr(world, destroy)(target)
        back = pickle.loads(pickle.dumps(world))
        assert state_bytes(back) == state_bytes(world), name
        del view
