#!/usr/bin/env python3
"""PyBullet on bench_peer_contact's cases, with the same columns.

The worlds come from `bench_peer_contact --describe` (bench/bench_peer_world.h): the same
bodies, sizes, masses, poses, velocities, planes, gravity and material as tumble's and MuJoCo's
rows, and the same figures measured from poses alone (deepest penetration over samples every
10 ms, 0.5 ms for the ball; fastest body over the last second of the span, the last sample's for
spans under 2 s; the ball's restitution; the cloud's momentum change over the sum of |P|).

PyBullet (the pybullet wheel from PyPI, Bullet's sequential-impulse solver, "pgs" below) runs at
its defaults (1/240 s, 50 solver iterations, ERP 0.2, split impulse) and at a finer setting,
1/1000 s, the one where its dice sink under 2 mm (docs/performance.md). Bullet multiplies the
two bodies' coefficients of a touching pair, so each body and plane gets the square root of
the world's friction and restitution. Bodies get no velocity damping (PyBullet's default is
0.04 /s, which the other engines do not have); sleeping stays at PyBullet's default. The CPU
time is the process's (time.process_time) over the calls to stepSimulation alone, the median of
the repeats.

usage: bench_peer_pybullet.py --describe-with BENCH_PEER_CONTACT [--quick] [--case NAME]
                              [--repeats N]
Exits 77 (a skipped test) when pybullet or numpy cannot be imported.
"""
import argparse
import contextlib
import json
import math
import os
import statistics
import subprocess
import sys
import time



@contextlib.contextmanager
def quiet_stderr():
    """pybullet writes its build time to standard error, without a newline, at import and at
    each connection: kept out of the rows, which ctest reads with the notes."""
    sys.stderr.flush()
    saved = os.dup(2)
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 2)
    try:
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(null)


try:
    import numpy as np

    with quiet_stderr():
        import pybullet
except ImportError as error:  # the smoke test is skipped, not failed
    print(f"bench_peer_pybullet: {error}: skipped", file=sys.stderr)
    sys.exit(77)

# (method, step s, solver iterations): the defaults, and the finer step that sinks < 2 mm
SETTINGS = [("pgs", 1.0 / 240.0, 50), ("pgs-fine", 1.0 / 1000.0, 50)]


def build(world, dt, iterations):
    """A DIRECT PyBullet world of the description; the body ids in its order."""
    with quiet_stderr():
        client = pybullet.connect(pybullet.DIRECT)
    pybullet.setGravity(0, 0, world["gravity"], physicsClientId=client)
    pybullet.setTimeStep(dt, physicsClientId=client)
    pybullet.setPhysicsEngineParameter(numSolverIterations=iterations, physicsClientId=client)
    friction = math.sqrt(world["friction"])
    restitution = math.sqrt(world["restitution"])
    for plane in world["planes"]:
        n = plane["normal"]
        shape = pybullet.createCollisionShape(pybullet.GEOM_PLANE, planeNormal=n,
                                              physicsClientId=client)
        body = pybullet.createMultiBody(0, shape,
                                        basePosition=[plane["offset"] * c for c in n],
                                        physicsClientId=client)
        pybullet.changeDynamics(body, -1, lateralFriction=friction, restitution=restitution,
                                physicsClientId=client)
    ids = []
    for b in world["bodies"]:
        if b["type"] == "sphere":
            shape = pybullet.createCollisionShape(pybullet.GEOM_SPHERE, radius=b["half"][0],
                                                  physicsClientId=client)
        else:
            shape = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=b["half"],
                                                  physicsClientId=client)
        w, x, y, z = b["q"]
        body = pybullet.createMultiBody(b["mass"], shape, basePosition=b["x"],
                                        baseOrientation=[x, y, z, w], physicsClientId=client)
        pybullet.changeDynamics(body, -1, lateralFriction=friction, restitution=restitution,
                                linearDamping=0.0, angularDamping=0.0, physicsClientId=client)
        pybullet.resetBaseVelocity(body, b["v"], b["w"], physicsClientId=client)
        ids.append(body)
    return client, ids


def sample(client, ids):
    """Centres (n, 3), rotations (n, 3, 3: shape to world) and velocities (n, 3)."""
    x, R, v = [], [], []
    for body in ids:
        position, orientation = pybullet.getBasePositionAndOrientation(body,
                                                                       physicsClientId=client)
        x.append(position)
        R.append(pybullet.getMatrixFromQuaternion(orientation))
        v.append(pybullet.getBaseVelocity(body, physicsClientId=client)[0])
    return np.array(x), np.array(R).reshape(-1, 3, 3), np.array(v)


def box_reach(half, R, L):
    """Half the extent along unit axes L (n, 3) of boxes (half (n, 3), R (n, 3, 3))."""
    return np.sum(half * np.abs(np.einsum("nik,ni->nk", R, L)), axis=1)


def deepest(world, x, R):
    """The deepest penetration (bench_peer_world.h's peer_deepest, vectorised)."""
    bodies = world["bodies"]
    half = np.array([b["half"] for b in bodies])
    sphere = np.array([b["type"] == "sphere" for b in bodies])
    depth = 0.0
    for plane in world["planes"]:
        n = np.array(plane["normal"], dtype=float)
        reach = np.where(sphere, half[:, 0], box_reach(half, R, np.broadcast_to(n, x.shape)))
        depth = max(depth, float(np.max(plane["offset"] - (x @ n - reach))))
    radius = np.where(sphere, half[:, 0], np.linalg.norm(half, axis=1))
    i, j = np.triu_indices(len(bodies), 1)
    d = x[j] - x[i]
    distance = np.linalg.norm(d, axis=1)
    near = distance < radius[i] + radius[j]
    i, j, d, distance = i[near], j[near], d[near], distance[near]
    both = sphere[i] & sphere[j]
    if np.any(both):
        depth = max(depth, float(np.max(radius[i][both] + radius[j][both] - distance[both])))
    boxes = ~sphere[i] & ~sphere[j]
    if np.any(boxes):
        depth = max(depth, box_overlap(half[i][boxes], R[i][boxes], half[j][boxes],
                                       R[j][boxes], d[boxes]))
    return depth


def box_overlap(ha, Ra, hb, Rb, d):
    """The largest over the pairs of the least overlap over the 15 separating axes."""
    axes = [Ra[:, :, k] for k in range(3)] + [Rb[:, :, k] for k in range(3)]
    for i in range(3):
        for j in range(3):
            axes.append(np.cross(Ra[:, :, i], Rb[:, :, j]))
    least = np.full(len(d), np.inf)
    for L in axes:
        norm = np.linalg.norm(L, axis=1)
        usable = norm >= 1e-9  # parallel edges: the face axes decide
        L = L / np.where(usable, norm, 1.0)[:, None]
        overlap = box_reach(ha, Ra, L) + box_reach(hb, Rb, L) - np.abs(np.sum(d * L, axis=1))
        least = np.where(usable, np.minimum(least, overlap), least)
    return float(np.max(least))


def run(world, dt, iterations):
    """One run: CPU s of the stepping, steps, and the figures."""
    client, ids = build(world, dt, iterations)
    masses = np.array([b["mass"] for b in world["bodies"]])
    duration, interval = world["duration"], world["sample"]
    samples = max(1, round(duration / interval))
    _, _, v = sample(client, ids)
    P0 = masses @ v
    scale = float(np.sum(masses * np.linalg.norm(v, axis=1)))
    seconds, steps = 0.0, 0
    figures = {"deepest": 0.0, "fastest": 0.0, "impact": 0.0, "rebound": 0.0, "momentum": math.nan}
    for k in range(1, samples + 1):
        t = duration * k / samples
        target = round(t / dt)
        start = time.process_time()
        while steps < target:
            pybullet.stepSimulation(physicsClientId=client)
            steps += 1
        seconds += time.process_time() - start
        x, R, v = sample(client, ids)
        figures["deepest"] = max(figures["deepest"], deepest(world, x, R))
        if t >= duration - (1.0 if duration >= 2.0 else 0.0) - 1e-9:
            figures["fastest"] = max(figures["fastest"], float(np.max(np.linalg.norm(v, axis=1))))
        if v[0, 2] < figures["impact"]:
            figures["impact"], figures["rebound"] = v[0, 2], 0.0
        figures["rebound"] = max(figures["rebound"], v[0, 2])
        if scale > 0:
            figures["momentum"] = float(np.linalg.norm(masses @ v - P0)) / scale
    pybullet.disconnect(physicsClientId=client)
    return seconds, steps, figures


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--describe-with", required=True, help="bench_peer_contact's path")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--case", action="append", default=[])
    parser.add_argument("--repeats", type=int, default=0)
    args = parser.parse_args()
    command = [args.describe_with, "--describe"] + (["--quick"] if args.quick else [])
    for name in args.case:
        command += ["--case", name]
    worlds = json.loads(subprocess.run(command, check=True, capture_output=True,
                                       text=True).stdout)
    repeats = args.repeats or (1 if args.quick else 3)
    print(f"bench_peer_pybullet: pybullet API {pybullet.getAPIVersion()}; load average "
          f"{os.getloadavg()[0]:.2f} at the start", file=sys.stderr, flush=True)
    print("case,engine,bodies,method,setting,cpu_per_simulated_s,cpu_seconds,steps,"
          "deepest_m,fastest_m_per_s,restitution,momentum_error,cpu_per_step_us", flush=True)
    for world in worlds:
        for method, dt, iterations in SETTINGS:
            times = []
            for _ in range(repeats):
                seconds, steps, f = run(world, dt, iterations)
                times.append(seconds)
            seconds = statistics.median(times)
            ball = world["case"] == "ball"
            restitution = f["rebound"] / -f["impact"] if ball and f["impact"] < 0 else math.nan
            momentum = f["momentum"] if world["case"] == "cloud" else math.nan
            print(f"{world['case']},pybullet,{len(world['bodies'])},{method},{dt:.4g},"
                  f"{seconds / world['duration']:.4g},{seconds:.4g},{steps},{f['deepest']:.3g},"
                  f"{f['fastest']:.3g},{restitution:.4g},{momentum:.3g},"
                  f"{1e6 * seconds / steps if steps else math.nan:.4g}", flush=True)
    print(f"bench_peer_pybullet: load average {os.getloadavg()[0]:.2f} at the end",
          file=sys.stderr)


if __name__ == "__main__":
    main()
