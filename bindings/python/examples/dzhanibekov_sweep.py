"""Ensemble example: where the Dzhanibekov flip starts. A T-handle spun about its intermediate
principal axis (20 rad/s) with a nudge of size eps about another axis, for eps from 1e-9 to
1e-1: 17 runs at once with tumble.run_many (threads on this machine's cores, or a Dask
cluster: set TUMBLE_DASK_SCHEDULER=tcp://host:8786 to send them there).

    python bindings/python/examples/dzhanibekov_sweep.py [output.png]

What physics says: near the intermediate axis, Euler's equations linearised give a nudge
that grows as exp(lambda t) with lambda = omega0 sqrt((I3 - I2)(I2 - I1) / (I1 I3)), so the
first flip comes at t = ln(1 / eps) / lambda + a constant: a straight line against ln(1/eps)
with slope 1/lambda. About the smallest or the largest axis a nudge does not grow: no flip.
Needs matplotlib."""

import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import tumble

I = np.array([2.43e-5, 2.70e-5, 5.03e-5])  # kg m^2, principal moments (examples/scenes/)
OMEGA0 = 20.0                             # rad/s
RATE = OMEGA0 * np.sqrt((I[2] - I[1]) * (I[1] - I[0]) / (I[0] * I[2]))  # lambda, 1/s


def handle(spin_axis, eps):
    """The handle spun about principal axis spin_axis (0, 1, 2) with eps * OMEGA0 about the
    next one (body frame)."""
    omega = np.zeros(3)
    omega[spin_axis] = OMEGA0
    omega[(spin_axis + 1) % 3] = eps * OMEGA0
    return {"bodies": [{"name": "handle", "mass": 0.0801, "inertia": I.tolist(),
                        "angular_velocity_body": omega.tolist()}],
            "output": {"fps": 400, "duration": 7.0}}


def first_flip(frames, axis):
    """The first time the body's `axis` points against where it started (s), or None. With
    the inertia given as principal moments, the shape frame is the principal frame."""
    q = frames.orientation[:, 0]
    w, v = q[:, :1], q[:, 1:]
    e = np.zeros(3)
    e[axis] = 1.0
    t = 2.0 * np.cross(v, e)
    turned = e + w * t + np.cross(v, t)   # q e q*: the axis in the world
    against = np.flatnonzero(turned @ turned[0] < 0)
    return frames.t[against[0]] if len(against) else None


client = None
if os.environ.get("TUMBLE_DASK_SCHEDULER"):
    from distributed import Client
    client = Client(os.environ["TUMBLE_DASK_SCHEDULER"])

eps = np.logspace(-9, -1, 17)
runs = [handle(1, e) for e in eps] + [handle(0, 1e-2), handle(2, 1e-2)]
results = tumble.run_many(runs, method="cvode-adams", rtol=1e-10, client=client)
flips = [first_flip(f, 1) for f in results[:len(eps)]]
stable = [first_flip(results[-2], 0), first_flip(results[-1], 2)]

flipped = np.array([t is not None for t in flips])
x, y = np.log(1 / eps[flipped]), np.array([t for t in flips if t is not None])
slope, intercept = np.polyfit(x, y, 1)
print(f"lambda = {RATE:.3f} 1/s: predicted slope 1/lambda = {1 / RATE:.4f} s, fitted "
      f"{slope:.4f} s over {flipped.sum()} runs that flipped within 7 s; "
      f"about the smallest and largest axes: {stable}")

fig, ax = plt.subplots(figsize=(7, 4.5))
ax.plot(x, y, "o", label="first flip (simulated)")
ax.plot(x, intercept + x / RATE, "-", label=f"slope 1/lambda = {1 / RATE:.3f} s (theory)")
ax.set(xlabel="ln(1 / eps), eps = nudge / spin", ylabel="time of the first flip (s)",
       title="Dzhanibekov flip: a smaller nudge waits longer, by ln(1/eps)/lambda")
ax.legend()
fig.tight_layout()
output = sys.argv[1] if len(sys.argv) > 1 else "dzhanibekov_sweep.png"
fig.savefig(output, dpi=100)
print(f"wrote {output}")

# The checks (this example runs as a test): the fitted slope is 1/lambda to 3% (the linear
# theory holds once the nudge is small; the largest nudges bend the line slightly), every
# run with eps <= 1e-6 flips, and a spin about the smallest or the largest axis never does.
assert abs(slope * RATE - 1) < 0.03, slope * RATE
assert flipped[eps <= 1e-6].all()
assert stable == [None, None], stable
