"""Shared fixtures: where the sources and the `inertia` command are, and small worlds."""

import os
import pathlib
import shutil

import pytest

import inertia

SOURCE_DIR = pathlib.Path(os.environ.get("INERTIA_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


@pytest.fixture
def scenes():
    return SOURCE_DIR / "scenes"


@pytest.fixture
def cli():
    """The `inertia` command of the same build (CTest passes its path in INERTIA_CLI)."""
    path = os.environ.get("INERTIA_CLI") or shutil.which("inertia")
    if not path:
        pytest.fail("set INERTIA_CLI to the inertia command of this build (CTest does)")
    return path


def ball_world(height=5.0, **settings):
    """A ground plane and a 0.5 m ball of water density at `height` (m)."""
    world = inertia.World(**settings)
    ground = world.create_body(type="static", name="ground")
    world.add_shape(ground, inertia.Plane((0, 1, 0), 0), inertia.Material(friction=0.6))
    ball = world.create_body(position=(0, height, 0), name="ball")
    world.add_shape(ball, inertia.Sphere(0.5), inertia.Material(density=1000, restitution=0.5))
    return world, ground, ball
