"""What a force written in Python costs: RK4 runs of N free boxes, with and without a Python
force (zero, or -k x on every body), in microseconds per derivative evaluation (CPU time,
median of 5). Prints CSV: bodies,force,us_per_derivative,us_per_body_derivative."""

import time

import numpy as np

import tumble


def boxes(n):
    return {"bodies": [{"name": f"b{i}", "shape": {"type": "box", "size": [0.1, 0.2, 0.4]},
                        "density": 700, "position": [float(i), 0, 0],
                        "angular_velocity": [0.3, 5.0, 0.2]} for i in range(n)]}


FORCES = {
    "none": None,
    "python-zero": lambda t, state: np.zeros((state.shape[0], 3)),
    "python-spring": lambda t, state: -10.0 * state[:, 0:3],
}


def per_derivative(n, force, repeats=5):
    times = []
    for _ in range(repeats):
        sim = tumble.Simulation(boxes(n), method="rk4", dt=1e-3,
                                forces=[force] if force else [])
        start = time.process_time()
        sim.advance(0.2)
        times.append((time.process_time() - start) / sim.stats["derivative_evals"])
    return 1e6 * float(np.median(times))


def main():
    print("bodies,force,us_per_derivative,us_per_body_derivative")
    for n in (1, 100):
        for name, force in FORCES.items():
            us = per_derivative(n, force)
            print(f"{n},{name},{us:.3f},{us / n:.4f}")


if __name__ == "__main__":
    main()
