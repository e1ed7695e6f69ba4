"""Benchmarks of the Python module (issue 20), each against its baseline in the same run:

- the cost of one World.step() on an empty world from Python, beside a bare call into the
  module (a property read): the goal is below 2 us;
- inertia.Batch of 4,096 small worlds (a pendulum; a box on a plane) at 1 and 2 threads (and
  every core), against the same worlds stepped one by one from a Python loop;
- a 10,000-scene sweep on a local Dask cluster against the serial loop.

    PYTHONPATH=build/default/python /usr/bin/python3 bench/python_bench.py [--quick]

Figures, not pass/fail; scripts/bench runs it.
"""

import argparse
import glob
import os
import sys
import time

import inertia

PENDULUM = {
    "world": {"dt": 1 / 60, "substeps": 4, "sleeping": False},
    "bodies": [{"name": "bob", "position": [1, 2, 0], "shapes": [{"type": "sphere", "radius": 0.1}]}],
    "joints": [{"type": "hinge", "body_b": "bob", "anchor_a": [0, 2, 0], "anchor_b": [-1, 0, 0],
                "axis_a": [0, 0, 1], "axis_b": [0, 0, 1]}],
}
BOX_ON_PLANE = {
    "world": {"dt": 1 / 60, "substeps": 4, "sleeping": False},
    "bodies": [
        {"type": "static", "shapes": [{"type": "plane"}]},
        {"position": [0, 0.5, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
    ],
}


def best_of(repeats, f):
    """The fastest of `repeats` timings of f() (s): the least disturbed by other work."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


def step_overhead(calls):
    world = inertia.World(threads=1)
    step = best_of(5, lambda: [world.step() for _ in range(calls)]) / calls
    read = best_of(5, lambda: [world.step_count for _ in range(calls)]) / calls
    print(f"World.step() on an empty world: {step * 1e6:.2f} us per call "
          f"(a bare property read: {read * 1e6:.2f} us; goal: step below 2 us)")


def thread_cpu_ticks():
    """CPU time (clock ticks) of each thread of this process so far (Linux), by thread id."""
    ticks = {}
    for task in glob.glob("/proc/self/task/*/stat"):
        try:
            fields = open(task).read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        ticks[task.split("/")[4]] = int(fields[11]) + int(fields[12])  # utime + stime
    return ticks


def work_split(batch, steps):
    """How the CPU time of batch.step(steps) fell on the threads, largest first: evenly spread
    work with no wall-clock gain means the machine had no idle core to give (other load)."""
    before = thread_cpu_ticks()
    batch.step(steps)
    after = thread_cpu_ticks()
    return sorted((t for t in (after[k] - before.get(k, 0) for k in after) if t), reverse=True)


def batch_scaling(n, steps):
    cores = os.cpu_count() or 1
    if hasattr(os, "getloadavg") and os.getloadavg()[0] > 0.5 * cores:
        print(f"(load average {os.getloadavg()[0]:.1f} on {cores} cores: thread scaling below "
              f"is limited by the other load; the CPU split shows whether the threads worked)")
    for name, scene in [("pendulum", PENDULUM), ("box on a plane", BOX_ON_PLANE)]:
        worlds = [inertia.parse_scene(scene, threads=1) for _ in range(n)]

        def loop():
            for _ in range(steps):
                for w in worlds:
                    w.step()

        base = n * steps / best_of(3, loop)
        print(f"{n} x {name}: a Python loop over separate worlds {base:,.0f} world-steps/s")
        for threads in sorted({1, 2, cores}):
            batch = inertia.Batch(scene, n, threads=threads)
            rate = n * steps / best_of(3, lambda: batch.step(steps))
            split = work_split(batch, steps) if os.path.isdir("/proc/self/task") else []
            print(f"  Batch at {threads:2d} threads: {rate:,.0f} world-steps/s "
                  f"({rate / base:.2f} x the loop; CPU ticks per thread {split})")


def sweep_throughput(scenes, steps):
    from inertia import distributed

    def scene(gravity):
        s = dict(BOX_ON_PLANE)
        s["world"] = dict(s["world"], gravity=[0, -gravity, 0])
        return s

    def measure(world):
        return float(world.positions()[1, 1])

    grid = {"gravity": [9.81 * (1 + i / scenes) for i in range(scenes)]}
    start = time.perf_counter()
    serial = distributed.sweep(scene, grid, measure, steps=steps, serial=True)
    t_serial = time.perf_counter() - start
    start = time.perf_counter()
    dask = distributed.sweep(scene, grid, measure, steps=steps)
    t_dask = time.perf_counter() - start
    same = serial.equals(dask)
    print(f"{scenes} scenes of {steps} steps: serial {scenes / t_serial:,.0f} scenes/s, local Dask "
          f"cluster of {os.cpu_count()} workers {scenes / t_dask:,.0f} scenes/s (cluster start "
          f"included); tables equal: {same}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes, for a smoke run")
    args = parser.parse_args()
    quick = args.quick
    step_overhead(2_000 if quick else 100_000)
    batch_scaling(256 if quick else 4096, 5 if quick else 60)
    sweep_throughput(200 if quick else 10_000, 10)
    sys.exit(0)
