"""The examples run, and their results hold against the closed forms they print."""

import math
import pathlib
import runpy
import sys

import numpy as np
import pytest

EXAMPLES = pathlib.Path(__file__).parents[1] / "examples"
sys.path.insert(0, str(EXAMPLES))

import bouncing_ball  # noqa: E402
import drive_sweep  # noqa: E402
import pendulum_batch  # noqa: E402


def test_bouncing_ball_follows_restitution():
    g, dt, e, h0 = 9.81, 1 / 240, 0.8, 2.0
    heights = bouncing_ball.bounce_heights(h0, e, bounces=3)
    # Restitution acts on the approach speed at the start of the step in which the ball lands,
    # up to g dt slower than the impact speed v_j: a relative error of up to 2 g dt / v_j in
    # height per bounce, adding up over the bounces (1.3% after the first, 4.4% after the third).
    bound = 0.0
    for k, h in enumerate(heights, start=1):
        bound += 2 * g * dt / (e ** (k - 1) * math.sqrt(2 * g * h0))
        assert h == pytest.approx(h0 * e ** (2 * k), rel=bound)


def test_pendulum_periods_match_the_elliptic_integral():
    angles, measured, _ = pendulum_batch.periods(n=40, threads=2)
    exact = pendulum_batch.exact_period(angles)
    # Sources: symplectic Euler's phase error, (omega h)^2 / 24 = 2e-5 at h = 1/480 s; the
    # joint's give under the centripetal load (about 5e-5 m in 1 m); crossings timed by linear
    # interpolation. Measured 2.2e-4 at 2.5 rad; 1e-3 still tells the exact period from the
    # small-angle one, which is 39% short at 2.5 rad.
    np.testing.assert_allclose(measured, exact, rtol=1e-3)
    assert exact[-1] / exact[0] > 1.6


def test_examples_run_as_scripts(capsys, monkeypatch):
    runpy.run_path(str(EXAMPLES / "bouncing_ball.py"), run_name="__main__")
    monkeypatch.setattr(sys, "argv", ["pendulum_batch.py", "12"])
    runpy.run_path(str(EXAMPLES / "pendulum_batch.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert "bounce 3" in out and "12 pendulums" in out


# An in-process cluster starts in a fraction of a second (test_distributed.py); the example's
# default, one worker process per core, is the same code past the client.
IN_PROCESS = {"local_cluster": {"processes": False, "n_workers": 2, "threads_per_worker": 1}}


@pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")
def test_drive_sweep_on_a_local_dask_cluster_overshoots_as_a_second_order_system():
    table = drive_sweep.run(points=2, **IN_PROCESS)
    serial = drive_sweep.run(points=2, serial=True)
    assert table.equals(serial)  # bit for bit
    assert len(table) == 4
    for row in table.itertuples():
        # The world's implicit drive is backward Euler on I q'' = k (1 - q) - c q': the
        # example's recurrence in float64 gives its overshoot to the float32 world's rounding
        # of q (1e-7 per step; measured 7e-7 after 360 steps). It damps more than the
        # continuous system, by about omega h / 2 in ratio: 0.02 rad less overshoot here.
        assert row.overshoot == pytest.approx(row.overshoot_backward_euler, abs=1e-5), row
        assert row.overshoot < row.overshoot_continuous
    # The overshoot depends on the damping ratio, and on the stiffness only through omega h.
    assert table.overshoot.max() > 0.65 and table.overshoot.min() < 0.05
