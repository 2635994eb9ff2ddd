"""Ensembles: many runs of variations of a scene, on all cores with threads (each run in C
without the GIL) or across a Dask cluster."""

import os
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable, List, Optional, Sequence

from ._scene import Frames, Scene

_SETTINGS = ("method", "dt", "rtol", "atol", "fps", "duration", "threads", "max_steps")


def _task(scene, settings, errors, reduce=None):
    """One run (module-level, so Dask can send it to a worker by reference)."""
    try:
        frames = Scene.coerce(scene).run(**settings)
        return frames if reduce is None else reduce(frames)
    except Exception as caught:
        if errors == "raise":
            raise
        return caught


def _tasks(items, defaults, errors):
    """(Scene, settings) for every item: a Scene, a path, a dict, or (one of those, settings).
    With errors="return", an item that cannot be made (a scene that does not load, settings
    that are not a dict) is its exception, to stand in the results in its place."""
    tasks = []
    for k, item in enumerate(items):
        try:
            tasks.append(_task_of(k, item, defaults))
        except Exception as caught:
            if errors == "raise":
                raise
            tasks.append(caught)
    return tasks


def _task_of(k, item, defaults):
    scene, own = item if isinstance(item, tuple) else (item, {})
    if not isinstance(own, dict):
        raise TypeError(f"item {k}: a (scene, settings) pair needs a dict of settings, got "
                        f"{type(own).__name__}")
    unknown = set(own) - set(_SETTINGS)
    if unknown:
        raise ValueError(f"item {k}: unknown settings {sorted(unknown)}; settings are "
                         f"{', '.join(_SETTINGS)}")
    base = defaults
    if "method" in own:  # its own integrator: none of the defaults' integrator settings
        base = {name: v for name, v in defaults.items() if name in ("fps", "duration")}
    return Scene.coerce(scene), {**base, **own}


def run_many(items: Sequence[Any], *, method: Optional[str] = None, dt: Optional[float] = None,
             rtol: Optional[float] = None, atol: Optional[float] = None,
             fps: Optional[float] = None, duration: Optional[float] = None,
             threads: Optional[int] = None, max_steps: Optional[int] = None,
             workers: Optional[int] = None, client=None, errors: str = "raise",
             reduce: Optional[Callable[[Frames], Any]] = None) -> List[Any]:
    """Runs every item as Scene.run does and returns their Frames in the items' order.

    An item is a Scene, a scene-file path, a dict in the scene-file format (docs/
    scene-format.md), or a pair (one of those, settings) whose settings (method, dt, rtol,
    atol, fps, duration, threads, max_steps) override the keyword arguments here, which
    override each scene's own (an item that names its method takes none of the integrator
    settings given here).
    Each run is independent and deterministic: the results equal serial runs bit for bit,
    however many workers run them and in whatever order they finish.

    Without a client the runs go to a pool of `workers` threads (default: os.cpu_count()),
    each run on one thread unless `threads` says more.
    Each run steps in C without the GIL, so threads use all cores; Python runs only between
    frames. With client (a dask.distributed.Client) each run is a Dask task on the cluster's
    workers (processes or machines): scenes travel as their JSON text (a mesh file a scene
    names must exist at the same path on the workers) and the Frames come back pickled; the
    workers need this package installed (the same version).

    reduce: a function of a run's Frames whose result is returned instead of the Frames,
    called where the run ran (on a Dask worker: only its result travels back, which is what
    makes a cluster pay off for big scenes; it must be picklable, e.g. a module's function).

    errors: "raise" (the first failure raises, in item order) or "return" (a failed item's
    place holds its exception, also for an item whose scene does not load). max_steps: each
    run's step budget from frame to frame (every method). Ctrl-C cancels the runs not yet
    started.
    """
    if errors not in ("raise", "return"):
        raise ValueError(f'errors must be "raise" or "return", got {errors!r}')
    defaults = {name: value for name, value in zip(
        _SETTINGS, (method, dt, rtol, atol, fps, duration, threads, max_steps))
        if value is not None}
    tasks = _tasks(items, defaults, errors)
    if reduce is not None and not callable(reduce):
        raise TypeError(f"reduce must be callable, got {type(reduce).__name__}")
    if client is not None:
        return _on_dask(client, tasks, errors, reduce)
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)):
        raise TypeError(f"workers must be an int, got {type(workers).__name__}")
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    pool = ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 1)
    try:
        futures = [task if isinstance(task, Exception) else
                   pool.submit(_task, task[0], task[1], errors, reduce) for task in tasks]
        return [future if isinstance(future, Exception) else future.result()
                for future in futures]
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _on_dask(client, tasks, errors, reduce):
    runs = [task for task in tasks if not isinstance(task, Exception)]
    count = len(runs)
    futures = client.map(_task, [scene for scene, _ in runs], [s for _, s in runs],
                         [errors] * count, [reduce] * count, pure=False)
    try:
        results = iter(client.gather(futures))
    except BaseException:
        client.cancel(futures)
        raise
    # the items that could not be made keep their places (errors="return")
    return [task if isinstance(task, Exception) else next(results) for task in tasks]
