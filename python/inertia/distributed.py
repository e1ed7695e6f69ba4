"""Parameter sweeps and Monte-Carlo studies over a Dask cluster (Debian's python3-distributed).

    from inertia import distributed

    def scene(restitution, friction):          # one point of the grid -> a scene (dict or path)
        return {...}

    def measure(world):                        # the stepped world -> a row of results
        return {"height": float(world.position(world.find_body("ball"))[1])}

    table = distributed.sweep(scene, {"restitution": [0.2, 0.5, 0.8], "friction": [0.1, 0.9]},
                              measure, steps=300)

The grid is a dict of lists (every combination, the first key varying slowest) or a list of
dicts (one point each: Monte-Carlo samples). Every point is a scene built by `make_scene(**point)`,
stepped `steps` times on one thread, and measured (a measure that follows a trajectory steps
the world itself, with steps=0); the result is a pandas DataFrame with one row
per point, in grid order: the point's parameters, then the measured columns.

Where it runs: by default on a local cluster of one single-threaded worker process per core,
started for the call and closed after it; `scheduler="tcp://host:8786"` runs it on an existing
cluster (whose workers must be able to `import inertia`), `client=` on a Client you hold, and
`serial=True` in this process without Dask. Worlds are deterministic whatever the thread count,
so each of these gives the same table, bit for bit.
"""

from __future__ import annotations

import itertools
import os
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

import inertia

Grid = Union[Mapping[str, Sequence[Any]], Sequence[Mapping[str, Any]]]


def points(grid: Grid) -> list[dict[str, Any]]:
    """The grid's points in order: every combination of a dict of lists (the first key varying
    slowest), or the dicts of a list as they are."""
    if isinstance(grid, Mapping):
        keys = list(grid)
        for key in keys:
            if isinstance(grid[key], (str, bytes)) or not isinstance(grid[key], Iterable):
                raise ValueError(f"grid: {key!r}: expected a list of values")
        return [dict(zip(keys, values)) for values in itertools.product(*(grid[k] for k in keys))]
    if isinstance(grid, (str, bytes)) or not all(isinstance(p, Mapping) for p in grid):
        raise ValueError("grid: expected a dict of lists or a list of dicts")
    return [dict(p) for p in grid]


def run_point(make_scene: Callable[..., Any], point: Mapping[str, Any],
              measure: Callable[[inertia.World], Any], steps: int) -> dict[str, Any]:
    """Builds, steps and measures one point (on one thread): the unit of work of a sweep."""
    scene = make_scene(**point)
    if isinstance(scene, (dict, str)) and not (isinstance(scene, str) and os.path.exists(scene)):
        world = inertia.parse_scene(scene, threads=1)
    else:
        world = inertia.load_scene(os.fspath(scene), threads=1)
    for _ in range(steps):
        world.step()
    row = measure(world)
    return dict(row) if isinstance(row, Mapping) else {"value": row}


def _run_chunk(make_scene, chunk, measure, steps):
    return [run_point(make_scene, p, measure, steps) for p in chunk]


def sweep(make_scene: Callable[..., Any], grid: Grid, measure: Callable[[inertia.World], Any], *,
          steps: int, scheduler: Optional[str] = None, client: Any = None,
          serial: bool = False, chunk_size: Optional[int] = None,
          local_cluster: Optional[Mapping[str, Any]] = None):
    """Runs `make_scene(**point)` for every point of `grid` for `steps` steps and returns a
    pandas DataFrame of the points and `measure(world)` (a dict of columns, or one value, the
    column "value").

    scheduler: a Dask scheduler's address ("tcp://host:8786"); client: a distributed.Client to
    use; neither: a local cluster (LocalCluster(**local_cluster); by default one worker process
    per core, one thread each). serial: run here, without Dask. chunk_size: points per task
    (default: about four tasks per worker), so that small scenes are not swamped by the
    scheduling of a task each.
    """
    import pandas

    if steps < 0:
        raise ValueError("steps: must be >= 0")
    todo = points(grid)
    if serial:
        rows = _run_chunk(make_scene, todo, measure, steps)
    else:
        rows = _on_cluster(make_scene, todo, measure, steps, scheduler, client, chunk_size,
                           local_cluster)
    return pandas.DataFrame([{**p, **r} for p, r in zip(todo, rows)])


def _on_cluster(make_scene, todo, measure, steps, scheduler, client, chunk_size, local_cluster):
    import distributed

    if client is not None and scheduler is not None:
        raise ValueError("give scheduler or client, not both")
    owned = []
    try:
        if client is None:
            if scheduler is not None:
                client = distributed.Client(scheduler)
            else:
                options = {"n_workers": os.cpu_count() or 1, "threads_per_worker": 1,
                           "processes": True, "dashboard_address": ":0"}
                options.update(local_cluster or {})
                cluster = distributed.LocalCluster(**options)
                owned.append(cluster)
                client = distributed.Client(cluster)
            owned.insert(0, client)
        workers = max(1, sum(client.nthreads().values()))
        size = chunk_size or max(1, len(todo) // (4 * workers))
        chunks = [todo[i:i + size] for i in range(0, len(todo), size)]
        futures = client.map(_run_chunk, [make_scene] * len(chunks), chunks,
                             [measure] * len(chunks), [steps] * len(chunks), pure=False)
        return [row for chunk in client.gather(futures) for row in chunk]
    finally:
        for thing in owned:
            thing.close()
