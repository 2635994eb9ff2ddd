"""Simulating a Plan with tumble frame by frame and writing the result as keys; removing them.

The keys tumble writes are marked: they sit in the F-Curve group "tumble" of the object's action
(an action the bake made is itself marked with the custom property "tumble_bake"), and the
object keeps, in its custom property "tumble_bake", the channels written and the pose it had,
which free_bake puts back."""
import json
import math
import re

import numpy as np

from .scene_export import euler_quaternion, quaternion_multiply, rotate

MARK = "tumble_bake"
GROUP = "tumble"
WORLD_MARK = "tumble_bake_disabled_world"


class BakeError(RuntimeError):
    """tumble refused the scene or failed; the message names the object."""


def name_objects(message, plan):
    """tumble's messages name bodies by their path (bodies[2]) or their name, which is the
    object's: add the object's name to each path."""
    names = [body["name"] for body in plan.scene["bodies"]]

    def body(match):
        i = int(match.group(1))
        return f"{match.group(0)} (object '{names[i]}')" if i < len(names) else match.group(0)

    def effect(match):
        i = int(match.group(1))
        effects = plan.scene["effects"]
        if i >= len(effects):
            return match.group(0)
        e = effects[i]
        named = e.get("bodies") or [e.get("body")] if "body" in e or "bodies" in e else []
        what = f" of {', '.join(repr(n) for n in named if n)}" if named else ""
        return f"{match.group(0)} ({e['type']}{what})"

    message = re.sub(r"bodies\[(\d+)\]", body, message)
    return re.sub(r"effects\[(\d+)\]", effect, message)


def load(tumble, plan):
    text = json.dumps(plan.scene)
    try:
        return tumble.Scene(text, name="Blender scene")
    except tumble.TumbleError as refused:
        raise BakeError(f"tumble refused the scene: {name_objects(str(refused), plan)}") from None


def simulate(tumble, plan, progress=None):
    """Each active object's (frames, 3) origins and (frames, 4) quaternions of its shape frame
    (its origin and rotation), frame by frame through tumble.Simulation, at t = k / fps as
    `tumble run` makes its frames (Simulation.run's times, which equal Scene.run's bit for bit)."""
    scene = load(tumble, plan)
    try:
        sim = tumble.Simulation(scene)
    except tumble.TumbleError as refused:  # e.g. bodies that start inside each other
        raise BakeError(f"tumble refused the scene: {name_objects(str(refused), plan)}") from None
    fps = sim.scene.run_settings["fps"]
    frames = plan.frame_end - plan.frame_start + 1
    index = [sim.body(obj.name) for obj in plan.active]
    values = np.empty((frames, len(index), 7))
    for k in range(frames):
        if k > 0:
            try:
                sim.advance(k / fps)
            except tumble.TumbleError as failed:
                raise BakeError(f"tumble failed at frame {plan.frame_start + k}: "
                                f"{name_objects(str(failed), plan)}") from None
        values[k] = sim.frame_values()[index, 0:7]
        if progress is not None:
            progress(k)
    return {obj.name: (values[:, i, 0:3], values[:, i, 3:7]) for i, obj in enumerate(plan.active)}


def rotation_channels(obj, quaternions):
    """(data path, (frames, n) values) of the rotation in the object's own rotation mode; Euler
    angles and quaternions kept continuous from frame to frame."""
    import mathutils

    mode = obj.rotation_mode
    q = np.array(quaternions)
    for k in range(1, len(q)):
        if q[k] @ q[k - 1] < 0:
            q[k] = -q[k]
    if mode == "QUATERNION":
        return "rotation_quaternion", q
    if mode == "AXIS_ANGLE":
        # angle in [0, 2 pi) from atan2, exact at small angles (acos loses half the digits)
        norms = np.linalg.norm(q[:, 1:], axis=1)
        angles = 2 * np.arctan2(norms, q[:, 0])
        axes = np.where(norms[:, None] > 0, q[:, 1:] / np.maximum(norms, 1e-300)[:, None],
                        [0.0, 0.0, 1.0])
        return "rotation_axis_angle", np.column_stack([angles, axes])
    rows, previous = [], obj.rotation_euler.copy()
    for row in q:
        previous = mathutils.Quaternion(row).to_euler(mode, previous)  # the branch nearest
        rows.append(refine_euler(np.array(previous, dtype=np.float64), mode, row))
    return "rotation_euler", np.array(rows)


def refine_euler(angles, order, target):
    """Euler angles from mathutils (single precision) brought to double precision by Newton
    steps: for R = R_c R_b R_a (a turned first) a change of the angles turns the frame by
    omega = e_c dc + R_c e_b db + R_c R_b e_a da (world frame); left as they are at gimbal lock."""
    for _ in range(2):
        q = euler_quaternion(angles, order)
        error = quaternion_multiply(target, q * [1, -1, -1, -1])
        error = error if error[0] >= 0 else -error
        omega = 2 * error[1:]  # the small turn from q to target, rad
        columns, frame = [], np.array([1.0, 0, 0, 0])
        for axis in reversed(order):
            i = "XYZ".index(axis)
            unit = np.zeros(3)
            unit[i] = 1.0
            columns.append((i, rotate(frame, unit)))
            turn = np.zeros(4)
            turn[0], turn[1 + i] = math.cos(angles[i] / 2), math.sin(angles[i] / 2)
            frame = quaternion_multiply(frame, turn)
        jacobian = np.zeros((3, 3))
        for i, column in columns:
            jacobian[:, i] = column
        if abs(np.linalg.det(jacobian)) < 1e-6:
            break
        angles = angles + np.linalg.solve(jacobian, omega)
    return angles


def check_free_channels(obj):
    """Refuses an object whose own keys the bake would overwrite (a previous bake of tumble's is
    freed first)."""
    action = obj.animation_data.action if obj.animation_data else None
    if action is None:
        return
    taken = {fc.data_path for fc in action.fcurves if fc.group is None or fc.group.name != GROUP}
    path = {"QUATERNION": "rotation_quaternion", "AXIS_ANGLE": "rotation_axis_angle"}.get(
        obj.rotation_mode, "rotation_euler")
    for clash in sorted(taken & {"location", path}):
        raise BakeError(f"'{obj.name}' has keys on {clash}: an active rigid body's keys would be "
                        f"overwritten; delete them (Object > Animation > Clear Keyframes)")


def write_keys(obj, frame_start, origins, quaternions):
    import bpy

    created = obj.animation_data is None or obj.animation_data.action is None
    if obj.animation_data is None:
        obj.animation_data_create()
    if created:
        obj.animation_data.action = bpy.data.actions.new(f"{obj.name} tumble")
        obj.animation_data.action[MARK] = True
    action = obj.animation_data.action
    rotation_path, rotation = rotation_channels(obj, quaternions)
    obj[MARK] = {"action_created": created, "paths": ["location", rotation_path],
                 "location": list(obj.location), "rotation_mode": obj.rotation_mode,
                 "rotation_quaternion": list(obj.rotation_quaternion),
                 "rotation_euler": list(obj.rotation_euler),
                 "rotation_axis_angle": list(obj.rotation_axis_angle)}
    frames = frame_start + np.arange(len(origins), dtype=np.float64)
    for path, table in (("location", origins), (rotation_path, rotation)):
        for i in range(table.shape[1]):
            curve = action.fcurves.new(path, index=i, action_group=GROUP)
            curve.keyframe_points.add(len(frames))
            curve.keyframe_points.foreach_set("co", np.column_stack([frames, table[:, i]]).ravel())
            for point in curve.keyframe_points:
                point.interpolation = "LINEAR"
            curve.update()


def free(scene):
    """Removes every key the bake wrote in the scene and puts each object's pose back; turns
    Blender's rigid body world back on if the bake turned it off. Returns the objects freed."""
    import bpy

    freed = []
    for obj in scene.objects:
        record = obj.get(MARK)
        if record is None:
            continue
        action = obj.animation_data.action if obj.animation_data else None
        if action is not None:
            paths = set(record["paths"])
            for curve in [fc for fc in action.fcurves if fc.data_path in paths and
                          fc.group is not None and fc.group.name == GROUP]:
                action.fcurves.remove(curve)
            group = action.groups.get(GROUP)
            if group is not None and not group.channels:
                action.groups.remove(group)
            if record["action_created"] and action.get(MARK) and not action.fcurves:
                obj.animation_data.action = None
                bpy.data.actions.remove(action)
        obj.location = record["location"]
        obj.rotation_quaternion = record["rotation_quaternion"]
        obj.rotation_euler = record["rotation_euler"]
        obj.rotation_axis_angle = record["rotation_axis_angle"]
        del obj[MARK]
        freed.append(obj.name)
    if scene.get(WORLD_MARK):
        if scene.rigidbody_world is not None:
            scene.rigidbody_world.enabled = True
        del scene[WORLD_MARK]
    return freed
