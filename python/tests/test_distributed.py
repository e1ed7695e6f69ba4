"""inertia.distributed: a sweep on a Dask cluster equals the serial sweep, bit for bit."""

import pathlib
import sys

import pandas
import pytest

from inertia import distributed

sys.path.insert(0, str(pathlib.Path(__file__).parents[1] / "examples"))
import restitution_sweep  # noqa: E402

# An in-process cluster (threads, the GIL released while worlds step) starts in a fraction of a
# second; the examples' default, one process per core, is the same code past the client.
# Debian's tornado warns about its own use of asyncio.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")

IN_PROCESS = {"local_cluster": {"processes": False, "n_workers": 2, "threads_per_worker": 1}}


def test_dask_sweep_equals_the_serial_sweep():
    grid = {"restitution": [0.2, 0.6, 0.9], "friction": [0.0, 0.5]}
    serial = distributed.sweep(restitution_sweep.scene, grid, restitution_sweep.measure,
                               steps=0, serial=True)
    dask = distributed.sweep(restitution_sweep.scene, grid, restitution_sweep.measure,
                             steps=0, chunk_size=1, **IN_PROCESS)
    pandas.testing.assert_frame_equal(serial, dask, check_exact=True)
    assert list(serial.columns) == ["restitution", "friction", "bounce_height", "distance"]
    assert list(serial["restitution"]) == [0.2, 0.2, 0.6, 0.6, 0.9, 0.9]  # grid order
    # The table is physics: the first bounce rises to e^2 h (the bouncing-ball example's bound,
    # 2 g dt / v = 1.9% at dt = 1/240 s and v = 4.4 m/s, and 3e-4 m more: the top found up to a
    # step late, g dt^2 / 2 = 1e-4 m, and the bounce's start on the soft contact, measured
    # 2e-4 m low at e = 0.1), and without friction the ball keeps its 2 m/s for the 1.5 s.
    for _, row in serial.iterrows():
        assert row.bounce_height == pytest.approx(row.restitution**2, rel=0.019, abs=3e-4)
        if row.friction == 0:
            assert row.distance == pytest.approx(3.0, abs=1e-4)
        else:
            assert row.distance < 2.9  # friction turned sliding into rolling, 5/7 of the speed


def test_monte_carlo_points_and_scalar_measures():
    samples = [{"restitution": 0.3, "friction": f} for f in (0.1, 0.2)]
    table = distributed.sweep(restitution_sweep.scene, samples,
                              lambda world: world.step_count, steps=3, serial=True)
    assert list(table["value"]) == [3, 3] and list(table["friction"]) == [0.1, 0.2]


def test_bad_grids():
    with pytest.raises(ValueError, match="grid"):
        distributed.points({"restitution": 0.5})
    with pytest.raises(ValueError, match="grid"):
        distributed.points([1, 2])
    with pytest.raises(ValueError, match="steps"):
        distributed.sweep(restitution_sweep.scene, {}, len, steps=-1, serial=True)


def test_the_sweep_example_draws_its_plot(tmp_path):
    out = tmp_path / "sweep.png"
    table = restitution_sweep.run(points=2, out=str(out), **IN_PROCESS)
    assert len(table) == 4 and out.stat().st_size > 1000
