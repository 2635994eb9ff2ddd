"""ctypes releases the GIL on every foreign call (the library is a CDLL, not a PyDLL): while a
run steps in C, other Python threads go on."""

import ctypes
import threading
import time

import tumble
from tumble import _native


def _many_boxes(bodies):
    return tumble.Scene.from_dict({
        "bodies": [{"name": f"b{i}", "shape": {"type": "box", "size": [0.1, 0.2, 0.4]},
                    "density": 700, "position": [float(i), 0, 0],
                    "angular_velocity": [0.3, 5.0, 0.2]} for i in range(bodies)]})


def test_another_thread_runs_while_a_run_steps_in_c():
    # Between frames 1 and 2 the main thread is inside tb_scene_run, in C, for ~0.2 s (1000
    # bodies, 4000 RK4 steps: 1000 took 0.044 s on an idle machine, too short to tell), running
    # no Python. A thread that notes how long it waited
    # between two turns of its loop must never wait long there; were the GIL held over the call
    # (PyDLL), it would wait the whole stretch. Bound: half the stretch (the OS may pause a
    # thread for a few ms on a shared machine; the switch interval is 5 ms).
    assert type(_native.lib) is ctypes.CDLL
    measuring, stop, longest = threading.Event(), threading.Event(), [0.0]
    marks = []

    def loop():
        last = time.perf_counter()
        while not stop.is_set():
            now = time.perf_counter()
            if measuring.is_set():
                longest[0] = max(longest[0], now - last)
            last = now

    def on_frame(k, t, values):
        marks.append(time.perf_counter())
        if k == 1:
            measuring.set()
        elif k == 2:
            measuring.clear()

    thread = threading.Thread(target=loop)
    thread.start()
    try:
        _many_boxes(1000).run(method="rk4", dt=2.5e-4, fps=1, duration=2.0, on_frame=on_frame)
    finally:
        stop.set()
        thread.join()
    stretch = marks[2] - marks[1]
    assert stretch > 0.05, f"the run between frames took {stretch:.3f} s: too short to tell"
    assert longest[0] < 0.5 * stretch, \
        f"the other thread waited {longest[0]:.3f} s of the {stretch:.3f} s in C"
