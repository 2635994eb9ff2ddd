"""Reads a tumble USD export with usd-core (Pixar's USD library, from PyPI) and checks it against
the simulation's frames, written as exact CSV (17 significant digits) by the same run.

    check_usd.py FILE.usda FRAMES.csv --scene SCENE.json [--reference REF.csv --max-degrees D]

Checks, each with its reason:
  * the stage opens and UsdUtils.ComplianceChecker reports no error, failed check or warning,
    nor do all of UsdValidation's validators where usd-core has them (what a USD pipeline's
    validation would say);
  * the stage is z up in metres (upAxis Z, metersPerUnit 1: tumble's world), its time codes
    are frames (timeCodesPerSecond = framesPerSecond = the scene's fps; frame k is time code k)
    and startTimeCode/endTimeCode span the frames;
  * one Xform per body under the default prim, its customData naming the body; at every frame
    its xformOp:translate (double3) and xformOp:orient (quatd) samples are the CSV's shape-frame
    pose within 1e-9 m and 1e-9 rad (the file holds the doubles themselves: 0 is expected), and
    the local-to-world transform USD computes from them puts the shape frame where the CSV does
    (origin within 1e-9 m; rotation matrix within 1e-7, USD's own rounding, see below);
  * the body's "shape" child is the USD primitive the scene file's shape maps to, with its sizes
    (Cube scaled to the box, Sphere, Capsule and Cylinder along Z, Mesh for meshes, with the
    mesh's own number of triangles, not its hull's: the writer draws the scene's visual mesh);
    an OBJ of several groups is a piece each ("piece_k" at the origin), each its group's
    triangles;
  * with --reference (the same scene run at a multiple of the frame rate): USD's own
    interpolation of the orientation (attribute Get at a time code between frames, which slerps)
    stays within D degrees of the simulation at every reference time. The largest angle is
    printed for the docs.
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np
from pxr import Gf, Usd, UsdGeom, UsdUtils


def read_frames(path):
    """{body: (t[], rows[] of x, y, z, qw, qx, qy, qz)} from the exact CSV."""
    frames = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            frames.setdefault(row["body"], ([], []))
            frames[row["body"]][0].append(float(row["t"]))
            frames[row["body"]][1].append([float(row[k]) for k in
                                           ("x", "y", "z", "qw", "qx", "qy", "qz")])
    return {k: (np.array(t), np.array(v)) for k, (t, v) in frames.items()}


def rotation_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def turn_angle(a, b):
    """Angle (rad) of the rotation between unit quaternions a and b (q and -q alike), from
    conj(a) b = (cos h, sin h n): atan2 keeps full precision at small angles, where acos of the
    dot product would lose half the digits."""
    w = a[0] * b[0] + np.dot(a[1:], b[1:])
    v = a[0] * b[1:] - b[0] * a[1:] - np.cross(a[1:], b[1:])
    return 2.0 * math.atan2(float(np.linalg.norm(v)), abs(float(w)))


def quaternion(value):
    """(w, x, y, z) of a Gf.Quatd."""
    i = value.GetImaginary()
    return np.array([value.GetReal(), i[0], i[1], i[2]])


def check_compliance(path):
    checker = UsdUtils.ComplianceChecker()
    checker.CheckCompliance(path)
    problems = checker.GetErrors() + checker.GetFailedChecks() + checker.GetWarnings()
    assert not problems, f"ComplianceChecker: {problems}"
    try:  # the validation framework that replaces the checker (usd-core 24.11 and later)
        from pxr import UsdValidation
    except ImportError:
        return
    validators = UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
    errors = UsdValidation.ValidationContext(validators).Validate(Usd.Stage.Open(path))
    assert not errors, f"UsdValidation: {[e.GetMessage() for e in errors]}"


def check_stage(stage, fps, times):
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z, UsdGeom.GetStageUpAxis(stage)
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0, UsdGeom.GetStageMetersPerUnit(stage)
    assert stage.GetTimeCodesPerSecond() == fps, (stage.GetTimeCodesPerSecond(), fps)
    assert stage.GetFramesPerSecond() == fps, (stage.GetFramesPerSecond(), fps)
    assert stage.GetStartTimeCode() == round(times[0] * fps), stage.GetStartTimeCode()
    assert stage.GetEndTimeCode() == round(times[-1] * fps), stage.GetEndTimeCode()
    assert stage.HasDefaultPrim(), "no default prim"


def body_prims(stage):
    """{body name: prim} of the default prim's Xform children that name a body."""
    bodies = {}
    for prim in stage.GetDefaultPrim().GetChildren():
        name = prim.GetCustomDataByKey("tumbleBody")
        if name is not None:
            assert prim.GetTypeName() == "Xform", prim.GetTypeName()
            assert name not in bodies, f"two prims for body {name!r}"
            bodies[name] = prim
    return bodies


def check_poses(prim, fps, t, rows):
    """Worst errors over the frames: the samples' position (m) and rotation (rad), and the
    transform's origin (m) and rotation matrix entries."""
    xformable = UsdGeom.Xformable(prim)
    translate, orient = prim.GetAttribute("xformOp:translate"), prim.GetAttribute("xformOp:orient")
    assert translate.GetTypeName() == "double3" and orient.GetTypeName() == "quatd"
    worst = [0.0] * 4
    for k in range(len(t)):
        code = t[k] * fps
        assert abs(code - round(code)) < 1e-9 * max(1.0, code), f"t = {t[k]} is not a frame"
        time = Usd.TimeCode(round(code))
        worst[0] = max(worst[0], float(np.max(np.abs(np.array(translate.Get(time)) - rows[k, :3]))))
        worst[1] = max(worst[1], turn_angle(quaternion(orient.Get(time)), rows[k, 3:]))
        matrix = xformable.ComputeLocalToWorldTransform(time)
        m = np.array([[matrix[i][j] for j in range(4)] for i in range(4)])
        # Gf matrices act on row vectors: p_world = p_local M, so M's translation is its last row
        worst[2] = max(worst[2], float(np.max(np.abs(m[3, :3] - rows[k, :3]))))
        worst[3] = max(worst[3], float(np.max(np.abs(m[:3, :3].T - rotation_matrix(rows[k, 3:])))))
    return worst


SHAPES = {"box": "Cube", "sphere": "Sphere", "ellipsoid": "Sphere", "capsule": "Capsule",
          "cylinder": "Cylinder", "mesh": "Mesh", "points": "Mesh", None: "Mesh"}


SCENE_FOLDER = "."  # where the scene file's mesh files are (set in main)


def obj_group_triangles(path):
    """Triangles in each object or group of an OBJ file, counted here as the scene loader reads
    the file (a polygon of n corners fanned into n - 2; an "o" or "g" starts a new group once
    faces have come), for the meshes' own triangles the writer must draw."""
    runs, new_group = [], True
    with open(path) as f:
        for line in f:
            words = line.split()
            if words and words[0] in ("o", "g"):
                new_group = True
            elif words and words[0] == "f":
                if new_group or not runs:
                    runs.append(0)
                    new_group = False
                runs[-1] += len(words) - 3
    return runs


def mesh_triangles(shape):
    """A "mesh" shape's own triangles per piece: one count, or one per group of its OBJ file."""
    if "file" in shape:
        return obj_group_triangles(os.path.join(SCENE_FOLDER, shape["file"]))
    return [len(shape["triangles"])]


def check_shape(prim, shape, triangles=None):
    """triangles: how many the Mesh must have (a mesh is drawn with its own triangles)."""
    kind = shape.get("type") if isinstance(shape, dict) else None
    runs = mesh_triangles(shape) if kind == "mesh" and triangles is None else None
    if runs is not None and len(runs) > 1:  # an OBJ of groups: one piece each, at the origin
        for k, count in enumerate(runs):
            holder = prim.GetChild(f"piece_{k}")
            assert holder and holder.GetTypeName() == "Xform", (prim.GetPath(), k)
            assert np.array_equal(holder.GetAttribute("xformOp:translate").Get(), [0, 0, 0])
            check_shape(holder, shape, count)
        return
    if runs is not None:
        triangles = runs[0]
    if isinstance(shape, list):  # pieces: each in an Xform "piece_k" placing it in the body
        for k, piece in enumerate(shape):
            holder = prim.GetChild(f"piece_{k}")
            assert holder and holder.GetTypeName() == "Xform", (prim.GetPath(), k)
            position = holder.GetAttribute("xformOp:translate").Get()
            orientation = quaternion(holder.GetAttribute("xformOp:orient").Get())
            assert np.allclose(position, piece.get("position", [0, 0, 0]), rtol=0, atol=1e-15)
            assert np.allclose(orientation, piece.get("orientation", [1, 0, 0, 0]), rtol=0,
                               atol=1e-12)
            check_shape(holder, piece,
                        sum(mesh_triangles(piece)) if piece.get("type") == "mesh" else None)
        return
    child = prim.GetChild("shape")
    assert child and child.GetTypeName() == SHAPES[kind], (prim.GetPath(), kind,
                                                          child.GetTypeName())
    get = lambda name: child.GetAttribute(name).Get()  # noqa: E731
    if kind == "box":
        assert get("size") == 1.0 and np.allclose(get("xformOp:scale"), shape["size"], rtol=1e-15)
    elif kind == "ellipsoid":
        assert get("radius") == 1.0
        assert np.allclose(get("xformOp:scale"), shape["semi_axes"], rtol=1e-15)
    elif kind == "sphere":
        assert get("radius") == shape["radius"]
    elif kind in ("capsule", "cylinder"):
        assert get("axis") == "Z" and get("radius") == shape["radius"]
        assert get("height") == shape["length"]
    else:
        mesh = UsdGeom.Mesh(child)
        counts = mesh.GetFaceVertexCountsAttr().Get()
        assert len(counts) > 0 and set(counts) == {3}, "a mesh of triangles"
        assert len(mesh.GetFaceVertexIndicesAttr().Get()) == 3 * len(counts)
        assert triangles is None or len(counts) == triangles, (prim.GetPath(), len(counts),
                                                               triangles)


def check_fidelity(bodies, fps, reference, max_degrees):
    """Largest angle (degrees) between USD's interpolated orientation and the simulation."""
    worst = 0.0
    for name, (t, rows) in reference.items():
        orient = bodies[name].GetAttribute("xformOp:orient")
        for k in range(len(t)):
            q = quaternion(orient.Get(Usd.TimeCode(t[k] * fps)))
            worst = max(worst, math.degrees(turn_angle(q, rows[k, 3:])))
    print(f"USD slerp vs simulation: largest rotation error {worst:.3g} degrees")
    assert worst <= max_degrees, f"{worst} degrees > {max_degrees}"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("usd")
    parser.add_argument("frames")
    parser.add_argument("--scene", required=True)
    parser.add_argument("--fps", type=float, help="the run's (default: the scene file's)")
    parser.add_argument("--reference")
    parser.add_argument("--max-degrees", type=float, default=0.1)
    args = parser.parse_args()
    with open(args.scene) as f:
        scene = json.load(f)
    global SCENE_FOLDER
    SCENE_FOLDER = os.path.dirname(os.path.abspath(args.scene))
    fps = args.fps or scene.get("output", {}).get("fps", 60.0)
    frames = read_frames(args.frames)
    check_compliance(args.usd)
    stage = Usd.Stage.Open(args.usd)
    assert stage, f"{args.usd}: does not open"
    check_stage(stage, fps, next(iter(frames.values()))[0])
    bodies = body_prims(stage)
    assert set(bodies) == set(frames), (sorted(bodies), sorted(frames))
    shapes = {b.get("name"): b.get("shape") for b in scene["bodies"]}
    worst = [0.0] * 4
    for name, (t, rows) in frames.items():
        check_shape(bodies[name], shapes.get(name))
        worst = [max(a, b) for a, b in zip(worst, check_poses(bodies[name], fps, t, rows))]
    print(f"{args.usd}: {len(bodies)} bodies; largest difference from the CSV at the frames: "
          f"samples {worst[0]:.3g} m, {worst[1]:.3g} rad; transform {worst[2]:.3g} m, "
          f"{worst[3]:.3g} (rotation matrix entries)")
    assert worst[0] <= 1e-9 and worst[1] <= 1e-9, f"samples off the CSV: {worst[:2]}"
    # USD turns the quaternion into a matrix through an axis and angle (GfRotation), whose acos
    # near a zero turn keeps about half of a double's digits: sqrt(2.2e-16) ~ 1.5e-8
    assert worst[2] <= 1e-9 and worst[3] <= 1e-7, f"transform off the CSV: {worst[2:]}"
    if args.reference:
        check_fidelity(bodies, fps, read_frames(args.reference), args.max_degrees)


if __name__ == "__main__":
    try:
        main()
    except AssertionError as error:
        print(f"check_usd: {sys.argv[1]}: {error}", file=sys.stderr)
        sys.exit(1)
