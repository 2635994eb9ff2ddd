"""Reads a tumble glTF export with pygltflib (an independent glTF loader) and checks it
against the simulation's frames, written as exact CSV (17 significant digits) by the same run.

    check_gltf.py FILE.glb FRAMES.csv [--reference REF.csv --max-degrees D]

Checks, each with its reason:
  * one node per body under a root that turns z up into y up (glTF is y up);
  * key times are the frame times and the keys are the frames, to float precision: each
    stored float is the float nearest the simulated double (glTF stores 32-bit floats);
  * rotation keys are the frames' quaternions reordered to (x, y, z, w) (up to sign);
  * with --reference (a run of the same scene at a multiple of the key rate): the file's
    rotation, evaluated between keys as the glTF 2.0 specification (Appendix C) defines it,
    stays within D degrees of the simulation at every reference time between keys. The
    largest angle is printed for the docs.
"""
import argparse
import csv
import math
import sys

import numpy as np
import pygltflib

COMPONENTS = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}


def accessor_array(gltf, blob, index):
    accessor = gltf.accessors[index]
    view = gltf.bufferViews[accessor.bufferView]
    assert accessor.componentType == pygltflib.FLOAT, "animation data must be float"
    n = COMPONENTS[accessor.type]
    start = (view.byteOffset or 0) + (accessor.byteOffset or 0)
    data = np.frombuffer(blob, dtype="<f4", count=accessor.count * n, offset=start)
    return data.reshape(accessor.count, n) if n > 1 else data


def read_frames(path):
    """{body: (t[], rows[] of 13 doubles)} from the exact CSV."""
    frames = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            t, values = float(row["t"]), [float(row[k]) for k in
                                          ("x", "y", "z", "qw", "qx", "qy", "qz")]
            frames.setdefault(row["body"], ([], []))
            frames[row["body"]][0].append(t)
            frames[row["body"]][1].append(values)
    return {k: (np.array(t), np.array(v)) for k, (t, v) in frames.items()}


def load(path):
    gltf = pygltflib.GLTF2().load(path)
    blob = gltf.binary_blob()
    if blob is None:  # .gltf: the buffer is a data URI
        blob = gltf.get_data_from_buffer_uri(gltf.buffers[0].uri)
    return gltf, blob


def channels(gltf, blob):
    """{node name: {path: (interpolation, times, values)}} of the first animation."""
    result = {}
    animation = gltf.animations[0]
    for channel in animation.channels:
        sampler = animation.samplers[channel.sampler]
        name = gltf.nodes[channel.target.node].name
        result.setdefault(name, {})[channel.target.path] = (
            sampler.interpolation, accessor_array(gltf, blob, sampler.input),
            accessor_array(gltf, blob, sampler.output))
    return result


def check_root(gltf):
    root = gltf.nodes[gltf.scenes[gltf.scene].nodes[0]]
    q = np.array(root.rotation)  # (x, y, z, w)
    x, y, z, w = q
    # R applied to tumble's up (0, 0, 1) must give glTF's up (0, 1, 0)
    up = np.array([2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)])
    assert np.allclose(up, [0, 1, 0], atol=1e-7), f"root turns z up into {up}, not y up"
    return [gltf.nodes[i].name for i in root.children]


def check_keys(name, frames, anim):
    t, rows = frames
    interpolation, times, positions = anim["translation"]
    assert interpolation == "LINEAR", f"{name}: translation {interpolation}"
    assert np.array_equal(times, t.astype(np.float32)), f"{name}: key times are not frame times"
    assert np.array_equal(positions, rows[:, :3].astype(np.float32)), \
        f"{name}: positions differ from the frames beyond float rounding"
    interpolation, _, values = anim["rotation"]
    keys = values[1::3] if interpolation == "CUBICSPLINE" else values
    expected = rows[:, [4, 5, 6, 3]].astype(np.float32)  # (x, y, z, w)
    same = np.all(keys == expected, axis=1) | np.all(keys == -expected, axis=1)
    assert same.all(), f"{name}: rotation keys differ from the frames (first at {np.argmin(same)})"


def evaluate(interpolation, times, values, t):
    """The rotation at time t as the glTF 2.0 specification (Appendix C) defines it."""
    k = min(max(np.searchsorted(times, t, side="right") - 1, 0), len(times) - 2)
    td = float(times[k + 1]) - float(times[k])
    s = (t - float(times[k])) / td
    if interpolation == "CUBICSPLINE":
        v = values.astype(np.float64).reshape(-1, 3, 4)
        p0, b0, p1, a1 = v[k, 1], v[k, 2], v[k + 1, 1], v[k + 1, 0]
        q = ((2 * s**3 - 3 * s**2 + 1) * p0 + td * (s**3 - 2 * s**2 + s) * b0
             + (-2 * s**3 + 3 * s**2) * p1 + td * (s**3 - s**2) * a1)
        return q / np.linalg.norm(q)
    q0, q1 = values[k].astype(np.float64), values[k + 1].astype(np.float64)
    d = float(np.dot(q0, q1))
    if d < 0:  # slerp takes the short way
        q1, d = -q1, -d
    angle = math.acos(min(d, 1.0))
    if angle < 1e-12:
        return q0
    return (math.sin((1 - s) * angle) * q0 + math.sin(s * angle) * q1) / math.sin(angle)


def angle_degrees(a, b):
    return math.degrees(2 * math.acos(min(1.0, abs(float(np.dot(a, b))))))


def check_between(name, anim, reference):
    t_ref, rows = reference
    interpolation, times, values = anim["rotation"]
    worst = 0.0
    for t, row in zip(t_ref, rows):
        if t > times[-1] or np.any(np.isclose(t, times, rtol=0, atol=1e-9)):
            continue  # keys themselves are checked exactly above
        q = evaluate(interpolation, times, values, t)
        worst = max(worst, angle_degrees(q, row[[4, 5, 6, 3]]))
    return interpolation, worst


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("gltf")
    parser.add_argument("frames")
    parser.add_argument("--reference")
    parser.add_argument("--max-degrees", type=float)
    args = parser.parse_args()
    gltf, blob = load(args.gltf)
    frames = read_frames(args.frames)
    names = check_root(gltf)
    assert set(frames) <= set(names), f"bodies {sorted(set(frames) - set(names))} have no node"
    anims = channels(gltf, blob)
    for name in frames:
        check_keys(name, frames[name], anims[name])
    print(f"{args.gltf}: {len(frames)} bodies, keys equal the frames to float precision")
    if args.reference:
        reference = read_frames(args.reference)
        for name in frames:
            interpolation, worst = check_between(name, anims[name], reference[name])
            print(f"{args.gltf}: {name}: {interpolation} rotation between keys within "
                  f"{worst:.4f} degrees of the reference")
            if args.max_degrees is not None and worst > args.max_degrees:
                print(f"FAILED: more than {args.max_degrees} degrees", file=sys.stderr)
                return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
