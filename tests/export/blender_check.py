"""Imports a tumble glTF export into Blender (headless) and checks the imported objects' world
positions and rotations at every key frame against the run's exact CSV.

    blender -b --factory-startup --python tests/export/blender_check.py -- \
        FILE.glb FRAMES.csv FPS [REFERENCE.csv] [--max-metres 1e-4] [--max-degrees 0.1]

With REFERENCE.csv (the same run at a multiple of FPS) the rotation is also compared between
keys, at the reference's times, and the largest angle printed (not held to the tolerance: it
measures what the importer does between keys).

Blender's importer turns glTF's y up into its own z up, undoing the root node's turn, so an
object's world position is tumble's world position again. It also turns each mesh's vertices
into z-up coordinates (glTF (x, y, z) becomes Blender (x, -z, y), a +90 degree turn about x),
so an object's rotation is tumble's shape rotation composed with the inverse turn:
R_blender = R_tumble R_x(-90 degrees), and the vertices land in the world where tumble puts them. The scene's frame rate is set to the keys'
rate first, so key k (t = k / FPS) lands on frame k. The importer's handling of CUBICSPLINE
rotations is reported: how many keyframes each rotation curve has, and their interpolation.
Exit status 0 when every body is within the tolerances, 1 otherwise.
"""
import csv
import math
import sys

import numpy

numpy.bool = bool  # Blender 3.4's importer still uses numpy.bool, removed in NumPy 1.24

import bpy  # noqa: E402
import mathutils  # noqa: E402


# The importer's turn of mesh coordinates, undone: R_x(-90 degrees) as (w, x, y, z).
MESH_TURN = mathutils.Quaternion((math.sqrt(0.5), -math.sqrt(0.5), 0.0, 0.0))


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:]
    options = {"--max-metres": 1e-4, "--max-degrees": 0.1}
    positional = []
    while argv:
        item = argv.pop(0)
        if item in options:
            options[item] = float(argv.pop(0))
        else:
            positional.append(item)
    reference = positional[3] if len(positional) > 3 else None
    return positional[0], positional[1], float(positional[2]), reference, options


def read_frames(path):
    frames = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            frames.setdefault(row["body"], []).append(
                (float(row["t"]), [float(row[k]) for k in ("x", "y", "z")],
                 [float(row[k]) for k in ("qw", "qx", "qy", "qz")]))
    return frames


def angle_degrees(a, b):
    """The angle of the rotation between unit quaternions a and b, in double precision:
    2 atan2(|vector part|, |w|) of a^-1 b (acos of a float32 dot product near 1 would round
    to 0.06 degrees)."""
    a = numpy.array(a, dtype=numpy.float64)
    b = numpy.array(b, dtype=numpy.float64)
    w = a[0] * b[0] + a[1:] @ b[1:]
    vector = a[0] * b[1:] - b[0] * a[1:] - numpy.cross(a[1:], b[1:])
    return math.degrees(2 * math.atan2(numpy.linalg.norm(vector), abs(w)))


def describe_rotation_curves(obj):
    action = obj.animation_data.action if obj.animation_data else None
    if action is None:
        return "no action"
    curves = [c for c in action.fcurves if "rotation" in c.data_path]
    if not curves:
        return "no rotation curve"
    c = curves[0]
    kinds = sorted({k.interpolation for k in c.keyframe_points})
    return f"{c.data_path}: {len(c.keyframe_points)} keyframes a curve, {'/'.join(kinds)}"


def worst_pose(scene, obj, rows, fps):
    """Largest position (m) and rotation (degrees) difference over the rows' times."""
    worst_metres, worst_degrees = 0.0, 0.0
    for t, x, q in rows:
        frame = t * fps
        whole = int(math.floor(frame))  # Blender wants 0 <= subframe < 1
        scene.frame_set(whole, subframe=frame - whole)
        world = obj.matrix_world
        worst_metres = max(worst_metres, (world.translation - mathutils.Vector(x)).length)
        expected = mathutils.Quaternion(q) @ MESH_TURN
        worst_degrees = max(worst_degrees, angle_degrees(world.to_quaternion(), expected))
    return worst_metres, worst_degrees


def main():
    path, frames_path, fps, reference_path, options = arguments()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = round(fps)
    scene.render.fps_base = round(fps) / fps
    bpy.ops.import_scene.gltf(filepath=path)
    frames = read_frames(frames_path)
    failed = False
    for name, rows in frames.items():
        obj = bpy.data.objects[name]
        worst_metres, worst_degrees = worst_pose(scene, obj, rows, fps)
        ok = worst_metres <= options["--max-metres"] and worst_degrees <= options["--max-degrees"]
        failed |= not ok
        print(f"blender_check: {path}: {name}: {len(rows)} frames, position within "
              f"{worst_metres:.2e} m, rotation within {worst_degrees:.2e} degrees "
              f"({describe_rotation_curves(obj)}) {'ok' if ok else 'FAILED'}")
    if reference_path is not None:
        for name, rows in read_frames(reference_path).items():
            keys = {t for t, _, _ in frames[name]}
            between = [row for row in rows if row[0] not in keys and row[0] <= max(keys)]
            _, degrees = worst_pose(scene, bpy.data.objects[name], between, fps)
            print(f"blender_check: {path}: {name}: between keys, rotation within "
                  f"{degrees:.4f} degrees of the reference ({len(between)} times)")
    return 1 if failed else 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    import os
    os._exit(code)  # Blender's own exit status would be 0 whatever the script returns
