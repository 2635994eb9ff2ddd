"""Notebook-style example: throw a spinning box, plot its path and its spin.

    TUMBLE_LIBRARY=build-shared/libtumble.so python bindings/python/examples/plot_trajectory.py

Writes trajectory.png (needs matplotlib: pip install matplotlib)."""

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import tumble

# %% A box thrown up and forward with a wobbly spin, under gravity.
builder = tumble.SceneBuilder()
builder.add_body("box", shape={"type": "box", "size": [0.1, 0.2, 0.4]}, density=700,
                 position=[0, 0, 1], velocity=[2, 0, 6], angular_velocity=[0.5, 1.0, 8.0])
builder.add_effect("gravity")
frames = builder.build(fps=60, duration=1.2).run(method="rk4", dt=1 / 240)

# %% The centre follows a parabola; the spin vector wanders while L stays fixed.
x, z = frames.position[:, 0, 0], frames.position[:, 0, 2]
spin = np.linalg.norm(frames.angular_velocity[:, 0], axis=1)
fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
left.plot(x, z, "o-", markersize=3)
left.set(xlabel="x (m)", ylabel="z (m)", title="path of the box")
right.plot(frames.t, spin, label="|omega| (rad/s)")
right.plot(frames.t, np.linalg.norm(frames.angular_momentum, axis=1), label="|L| (kg m^2/s)")
right.set(xlabel="t (s)", title="spin and angular momentum")
right.legend()
fig.tight_layout()
fig.savefig("trajectory.png", dpi=100)
print(f"{len(frames.t)} frames, {frames.stats['steps']} steps; wrote trajectory.png")
