"""Notebook-style example: build a scene in Python, run it, and plot what physics says must
stay constant.

    python bindings/python/examples/energy_and_momentum.py [output.png]

Two boxes joined by an undamped spring, thrown and spinning under gravity. Gravity and the
spring are conservative, so the total energy stays constant; neither exerts a torque about
the centre of mass of the two boxes (the spring's forces are equal and opposite along one
line, and uniform gravity acts as if at the centre of mass), so the angular momentum about
that moving point stays constant too. About the fixed world origin it does not: gravity's
torque (c - 0) x M g changes it. The script plots both and checks them (it runs as a test).
Needs matplotlib (pip install matplotlib)."""

import sys

import matplotlib

matplotlib.use("Agg")  # files, no window
import matplotlib.pyplot as plt
import numpy as np

import tumble

# %% The scene, in the scene-file format's words (docs/scene-format.md). SI units, z up.
builder = tumble.SceneBuilder()
box = {"type": "box", "size": [0.1, 0.2, 0.4]}  # m
builder.add_body("left", shape=box, density=700, position=[0, 0, 2],
                 velocity=[1, 0, 4], angular_velocity=[0.5, 3, 6])
builder.add_body("right", shape=box, density=700, position=[0.6, 0, 2],
                 velocity=[1, 0.5, 5], angular_velocity=[-4, 1, 0.5])
builder.add_effect("gravity")  # 9.81 m/s^2 down
builder.add_effect("spring", body_a="left", point_a=[0, 0, 0.2], body_b="right",
                   point_b=[0, 0, -0.2], stiffness=200, rest_length=0.5)  # N/m, m
scene = builder.build(fps=120, duration=3.0)

# %% One library call runs it; every frame comes back as NumPy arrays.
frames = scene.run(method="rk4", dt=1 / 960)
energy = frames.kinetic_energy + frames.potential_energy                 # J
L_center = frames.angular_momentum_about(frames.center_of_mass)          # kg m^2/s
L_origin = frames.angular_momentum                                        # about (0, 0, 0)

energy_drift = np.abs(energy - energy[0]) / np.abs(energy).max()
L_drift = np.linalg.norm(L_center - L_center[0], axis=1) / np.linalg.norm(L_center[0])
print(f"{len(frames.t)} frames, {frames.stats['steps']} steps; largest relative drift: "
      f"energy {energy_drift.max():.1e}, L about the centre of mass {L_drift.max():.1e}")

# %% The plot: conserved quantities flat, |L| about the origin not.
fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
top.plot(frames.t, frames.kinetic_energy, label="kinetic")
top.plot(frames.t, frames.potential_energy, label="potential (gravity + spring)")
top.plot(frames.t, energy, "k", label="total")
top.set(ylabel="energy (J)", title="two boxes on a spring, thrown and spinning")
top.legend(loc="center right")
bottom.plot(frames.t, np.linalg.norm(L_center, axis=1), "k", label="|L| about the centre of mass")
bottom.plot(frames.t, np.linalg.norm(L_origin, axis=1), "--", label="|L| about the world origin")
bottom.set(xlabel="t (s)", ylabel="angular momentum (kg m$^2$/s)")
bottom.legend(loc="upper left")
fig.tight_layout()
output = sys.argv[1] if len(sys.argv) > 1 else "energy_and_momentum.png"
fig.savefig(output, dpi=100)
print(f"wrote {output}")

# %% The checks that make this example a test. RK4's error at 1/960 s over 3 s is about
# (h omega)^4 per unit time for the fastest motion (the spring, omega ~ 26 rad/s; spins of
# 6 rad/s): 1e-7 relative is a bound with room, and a wrong torque or energy would be ~1e-1.
assert energy_drift.max() < 1e-7, energy_drift.max()
assert L_drift.max() < 1e-7, L_drift.max()
# About the origin gravity's torque changes L by far more than the drift above.
assert np.linalg.norm(L_origin[-1] - L_origin[0]) > 100 * L_drift.max() * np.linalg.norm(L_center[0])
