"""The Python package against the C API on the same run, both keeping every frame in memory:
1000 boxes with random spins under gravity, RK4 at 1/240 s, 121 frames (2 s at 60 fps).

    python bindings/python/bench/bench_frames.py --c-bench build/bench/bench_frames_in_memory

The C side (bench/bench_frames_in_memory.c) stores what Scene.run stores: each frame filled by
tb_scene_frame_values into one block, the energies, momenta and centre of mass. Both time CPU
seconds for loading the scene from its text, running it and keeping the frames, and report
the median of the repeats, run alternately. Prints CSV: api,bodies,frames,median_ms, then the
ratio python/c (docs/performance.md records it)."""

import argparse
import json
import os
import pathlib
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np

import tumble


def scene_description(bodies, seed=1):
    rng = np.random.default_rng(seed)
    return {
        "bodies": [{"name": f"box{i}", "shape": {"type": "box", "size": [0.1, 0.2, 0.4]},
                    "density": 700, "position": [float(i % 40), float(i // 40), 1.0],
                    "velocity": rng.uniform(-1, 1, 3).tolist(),
                    "angular_velocity": rng.uniform(-5, 5, 3).tolist()}
                   for i in range(bodies)],
        "effects": [{"type": "gravity"}],
        "integrator": {"method": "rk4", "dt": 1 / 240},
        "output": {"fps": 60, "duration": 2.0},
    }


def processor():
    for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--c-bench", required=True, help="path of bench_frames_in_memory")
    parser.add_argument("--bodies", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "bench.json")
        with open(path, "w") as f:
            json.dump(scene_description(args.bodies), f)
        scene = tumble.Scene.from_file(path)
        c_ms, python_ms = [], []
        for _ in range(args.repeats):
            out = subprocess.run([args.c_bench, path, "1"], check=True, capture_output=True,
                                 text=True).stdout
            c_ms.append(float(out.splitlines()[1].split(",")[3]))
            start = time.process_time()
            frames = scene.run()
            python_ms.append(1e3 * (time.process_time() - start))
        count = len(frames.t)
    c, py = float(np.median(c_ms)), float(np.median(python_ms))
    print("api,bodies,frames,median_ms")
    print(f"c,{args.bodies},{count},{c:.3f}")
    print(f"python,{args.bodies},{count},{py:.3f}")
    print(f"# python/c = {py / c:.3f} ({args.repeats} repeats each, alternating; "
          f"{processor()}; Python {sys.version.split()[0]})", file=sys.stderr)


if __name__ == "__main__":
    main()
