"""Notebook-style example: throw a spinning box, plot its path and its spin.

    python bindings/python/examples/plot_trajectory.py [output.png]

Writes trajectory.png (needs matplotlib: pip install matplotlib)."""

import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import tumble

# %% A box thrown up and forward with a wobbly spin, under gravity.
builder = tumble.SceneBuilder()
builder.add_body("box", shape={"type": "box", "size": [0.1, 0.2, 0.4]}, density=700,
                 position=[0, 0, 1], velocity=[2, 0, 6], angular_velocity=[0.5, 1.0, 8.0])
builder.add_effect("gravity")
frames = builder.build(fps=60, duration=1.2).run(method="rk4", dt=1 / 240)

# %% The centre follows a parabola. Gravity acts at the centre of mass, so it exerts no torque
# about it: the angular momentum about the centre of mass stays fixed while the spin vector
# omega wanders (the box is not spinning about a principal axis). About the world origin L
# grows, by the torque x x M g: that is the orbital part, not the spin.
x, z = frames.position[:, 0, 0], frames.position[:, 0, 2]
spin = np.linalg.norm(frames.angular_velocity[:, 0], axis=1)
L_center = np.linalg.norm(frames.angular_momentum_about(frames.center_of_mass), axis=1)
fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
left.plot(x, z, "o-", markersize=3)
left.set(xlabel="x (m)", ylabel="z (m)", title="path of the box")
right.plot(frames.t, spin, label="|omega| (rad/s)")
right.plot(frames.t, L_center, label="|L| about the centre of mass (kg m^2/s)")
right.set(xlabel="t (s)", title="spin and angular momentum")
right.legend()
fig.tight_layout()
output = sys.argv[1] if len(sys.argv) > 1 else "trajectory.png"
fig.savefig(output, dpi=100)
print(f"{len(frames.t)} frames, {frames.stats['steps']} steps; wrote {output}")

# %% What the plot shows, checked (this example runs as a test): L about the centre of mass
# is constant to round-off (the state holds L; no torque acts on it), omega's direction is
# not (it turns by more than 5 degrees), and the path is the parabola (RK4 is exact on it).
assert np.ptp(L_center) < 1e-12 * L_center[0], np.ptp(L_center)
direction = frames.angular_velocity[:, 0] / spin[:, None]
turned = np.degrees(np.arccos(np.clip(direction @ direction[0], -1, 1))).max()
print(f"omega turned by up to {turned:.1f} degrees; |L| about the centre of mass "
      f"{L_center[0]:.4f} kg m^2/s throughout")
assert turned > 5, turned
np.testing.assert_allclose(frames.center_of_mass[:, 2], 1 + 6 * frames.t - 9.81 / 2 * frames.t**2,
                           atol=1e-12)
