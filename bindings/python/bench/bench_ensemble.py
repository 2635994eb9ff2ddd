"""run_many's speed-up and per-task overhead on this machine: 8 runs of 500 spinning boxes
(RK4 at 1/240 s, 5 s at 30 fps) serially, on 2 threads, and on a Dask LocalCluster of 2 worker
processes (returning every frame, 7.8 MB a run, or only the last orientations); then 200 tiny runs (1 body, one frame) for the cost of a task itself. Wall-clock
seconds, the median of 3. Prints CSV: workload,how,seconds,per_task_ms,speedup."""

import time

import numpy as np

import tumble


def boxes(n, spin):
    return {"bodies": [{"name": f"b{i}", "shape": {"type": "box", "size": [0.1, 0.2, 0.4]},
                        "density": 700, "position": [float(i), 0, 0],
                        "angular_velocity": [spin, 5.0, 0.2]} for i in range(n)],
            "integrator": {"method": "rk4", "dt": 1 / 240},
            "output": {"fps": 30, "duration": 5.0}}


def last_state(frames):
    """What travels back from a worker when only a summary is needed."""
    return frames.orientation[-1].copy()


def timed(function, repeats=3):
    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        seconds.append(time.perf_counter() - start)
    return float(np.median(seconds))


def main():
    import distributed

    workloads = {
        "8 x 500 bodies": [tumble.Scene.from_dict(boxes(500, 0.1 * k)) for k in range(8)],
        "200 tiny": [tumble.Scene.from_dict({**boxes(1, 0.1), "output": {"duration": 0}})
                     for _ in range(200)],
    }
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        client.run(lambda: __import__("tumble").__version__)  # workers import the package
        print("workload,how,seconds,per_task_ms,speedup")
        for name, scenes in workloads.items():
            ways = {"serial": lambda: [s.run() for s in scenes],
                    "threads-2": lambda: tumble.run_many(scenes, workers=2),
                    "dask-2-processes": lambda: tumble.run_many(scenes, client=client),
                    "dask-2-processes-reduced": lambda: tumble.run_many(
                        scenes, client=client, reduce=last_state)}
            serial = None
            for how, function in ways.items():
                seconds = timed(function)
                serial = serial or seconds
                print(f"{name},{how},{seconds:.3f},{1e3 * seconds / len(scenes):.3f},"
                      f"{serial / seconds:.2f}")


if __name__ == "__main__":
    main()
