"""Reads the joints of tumble's USD exports with usd-core (Pixar's USD library, from PyPI) and
checks them against the scene files that made them.

    check_usd_joints.py TUMBLE OUT_DIR SCENE.json[@SECONDS]...

For each scene, `tumble run SCENE --duration SECONDS (0.1) --out OUT_DIR/<name>.usda`, then:
  * the stage opens and UsdUtils.ComplianceChecker reports no error, failed check or warning
    (nor do UsdValidation's validators, where usd-core has them);
  * one UsdPhysics joint prim per joint of the file, of the type its "type" maps to
    (ball PhysicsSphericalJoint, hinge PhysicsRevoluteJoint, slider PhysicsPrismaticJoint,
    fixed PhysicsFixedJoint), its physics:body1 the Xform of the file's first body and its
    physics:body0 that of the second (none for the world: the schema's "empty for the world");
  * each joint's frame, placed by localPos0/localRot0 in body0's Xform and by
    localPos1/localRot1 in body1's, at the transforms USD computes from the first time sample,
    is one frame: the two anchors meet at the file's anchor, and for a hinge or slider both
    frames' physics:axis ("X") lie along the file's axis. The schema's types are floats
    (point3f, quatf), so the bound is float rounding: 2^-23 of the anchors' distances from the
    bodies' origins (two roundings of a float's 2^-24), plus 1e-9 m for the doubles; the axes
    to 1e-6 (a quatf's rounding, 6e-8 a component, turns a unit vector by about 1e-7);
  * limits in the schema's units: a hinge's in degrees, a slider's in metres; break force and
    torque as the file's (N, N m: the stage's kilogramsPerUnit and metersPerUnit are 1);
  * the schema's coordinate of each limited joint (body1's joint frame against body0's: a turn
    about x, a travel along x) stays within the limits written at every time sample, and with
    SCENE.json@SECONDS comes to one of them (within 0.5 degree, a frame's swing at a bouncing
    stop, or 1 mm): the coordinate the limits are written in is the one tumble's stops hold,
    not its negative (the hinge of joint_frames.json swings to its upper stop, 57.3 degrees,
    past where its negative's lower one, -28.6, would have stopped it).
The largest anchor gap is printed for the docs.
"""
import json
import math
import os
import subprocess
import sys

import numpy as np
from pxr import Gf, Usd, UsdGeom, UsdPhysics, UsdUtils

TYPES = {"ball": "PhysicsSphericalJoint", "hinge": "PhysicsRevoluteJoint",
         "slider": "PhysicsPrismaticJoint", "fixed": "PhysicsFixedJoint"}
FLOAT_ROUNDING = 2.0**-23


def check_compliance(path):
    checker = UsdUtils.ComplianceChecker()
    checker.CheckCompliance(path)
    problems = checker.GetErrors() + checker.GetFailedChecks() + checker.GetWarnings()
    assert not problems, f"ComplianceChecker: {problems}"
    try:
        from pxr import UsdValidation
    except ImportError:
        return
    validators = UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
    errors = UsdValidation.ValidationContext(validators).Validate(Usd.Stage.Open(path))
    assert not errors, f"UsdValidation: {[e.GetMessage() for e in errors]}"


def body_frame(stage, joint, k, time):
    """(Gf.Matrix4d local-to-world of body k's Xform at time (identity for the world), the
    body's name ("world" for none))."""
    targets = joint.GetPrim().GetRelationship(f"physics:body{k}").GetTargets()
    if not targets:
        return Gf.Matrix4d(1.0), "world"
    assert len(targets) == 1, targets
    prim = stage.GetPrimAtPath(targets[0])
    assert prim and prim.GetTypeName() == "Xform", targets[0]
    return (UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(time),
            prim.GetCustomDataByKey("tumbleBody"))


def joint_frame_in_world(matrix, position, rotation):
    """World position of the joint frame's origin and world direction of its x axis."""
    origin = matrix.Transform(Gf.Vec3d(position))
    x_local = Gf.Rotation(Gf.Quatd(rotation)).TransformDir(Gf.Vec3d(1, 0, 0))
    x_world = matrix.TransformDir(x_local)
    return np.array(origin), np.array(x_world) / np.linalg.norm(np.array(x_world))


def check_joint(stage, prim, joint, time):
    """The largest anchor gap (m) of one joint, after checking it."""
    assert prim.GetTypeName() == TYPES[joint["type"]], (prim.GetPath(), prim.GetTypeName())
    physics = UsdPhysics.Joint(prim)
    bodies = list(joint["bodies"]) + (["world"] if len(joint["bodies"]) == 1 else [])
    ends, gap = [], 0.0
    for k, (pos_attr, rot_attr) in enumerate(((physics.GetLocalPos0Attr(),
                                               physics.GetLocalRot0Attr()),
                                              (physics.GetLocalPos1Attr(),
                                               physics.GetLocalRot1Attr()))):
        matrix, name = body_frame(stage, physics, k, time)
        assert name == bodies[1 - k], (prim.GetPath(), k, name, bodies)
        position = pos_attr.Get()
        origin, x_axis = joint_frame_in_world(matrix, position, rot_attr.Get())
        bound = 1e-9 + FLOAT_ROUNDING * float(np.linalg.norm(np.array(position)))
        gap = max(gap, float(np.max(np.abs(origin - joint["anchor"]))))
        assert np.max(np.abs(origin - joint["anchor"])) <= bound, (prim.GetPath(), k, origin)
        ends.append((origin, x_axis))
    bound = 1e-9 + FLOAT_ROUNDING * sum(np.linalg.norm(np.array(a.Get()))
                                        for a in (physics.GetLocalPos0Attr(),
                                                  physics.GetLocalPos1Attr()))
    assert np.max(np.abs(ends[0][0] - ends[1][0])) <= bound, (prim.GetPath(), ends)
    if joint["type"] in ("hinge", "slider"):
        axis = np.array(joint["axis"], dtype=float) / np.linalg.norm(joint["axis"])
        for _, x_axis in ends:
            assert np.max(np.abs(x_axis - axis)) <= 1e-6, (prim.GetPath(), x_axis, axis)
        assert prim.GetAttribute("physics:axis").Get() == "X"
        check_limits(prim, joint)
    for key, attribute in (("break_force", "physics:breakForce"),
                           ("break_torque", "physics:breakTorque")):
        value = prim.GetAttribute(attribute).Get()
        expected = joint.get(key, math.inf)
        assert value == np.float32(expected), (prim.GetPath(), attribute, value, expected)
    return gap


def joint_frame_rows(stage, prim, k, time):
    """(rows: the joint frame's x, y, z in the world, origin) of the frame in body k at time."""
    physics = UsdPhysics.Joint(prim)
    matrix, _ = body_frame(stage, physics, k, time)
    rotation = Gf.Rotation(Gf.Quatd(prim.GetAttribute(f"physics:localRot{k}").Get()))
    local = np.array(Gf.Matrix4d().SetRotate(rotation).ExtractRotationMatrix())
    rows = local @ np.array(matrix.ExtractRotationMatrix())  # Gf's row vectors: local, then body
    origin = np.array(matrix.Transform(Gf.Vec3d(prim.GetAttribute(f"physics:localPos{k}").Get())))
    return rows, origin


def coordinate(stage, prim, kind, time):
    """The schema's joint coordinate, body1's joint frame against body0's: a revolute joint's
    turn about x (degrees), a prismatic joint's travel along x (m)."""
    (rows0, origin0), (rows1, origin1) = (joint_frame_rows(stage, prim, k, time) for k in (0, 1))
    if kind == "hinge":
        return math.degrees(math.atan2(rows1[1] @ rows0[2], rows1[1] @ rows0[1]))
    return float((origin1 - origin0) @ rows0[0])


def check_coordinates(stage, prim, joint):
    """At every time sample the schema's coordinate of a limited hinge or slider is within the
    limits written (so the coordinate and the limits are tumble's: body_a against body_b);
    returns how near it came to a bound (0: it reached one), in the limit's units."""
    kind = joint["type"]
    lower, upper = (prim.GetAttribute(f"physics:{end}Limit").Get() for end in ("lower", "upper"))
    slack = 1e-4 if kind == "hinge" else 1e-6  # float rounding of the frames and the limits
    nearest = math.inf
    for code in range(int(stage.GetStartTimeCode()), int(stage.GetEndTimeCode()) + 1):
        value = coordinate(stage, prim, kind, Usd.TimeCode(code))
        assert lower - slack <= value <= upper + slack, (prim.GetPath(), code, value)
        nearest = min(nearest, value - lower, upper - value)
    return max(nearest, 0.0)


def check_limits(prim, joint):
    lower, upper = (prim.GetAttribute(f"physics:{end}Limit").Get() for end in ("lower", "upper"))
    if "limits" not in joint:
        assert lower == -math.inf and upper == math.inf, (prim.GetPath(), lower, upper)
        return
    scale = 180.0 / math.pi if joint["type"] == "hinge" else 1.0  # the schema's degrees
    for value, limit in zip((lower, upper), joint["limits"]):
        assert abs(value - limit * scale) <= 1e-6 * max(1.0, abs(limit * scale)), (
            prim.GetPath(), value, limit * scale)


def check_scene(tumble, out, argument):
    """argument: SCENE.json, or SCENE.json@SECONDS to run that long and require every limited
    joint to reach one of its stops (else 0.1 s)."""
    path, _, seconds = argument.partition("@")
    with open(path) as f:
        scene = json.load(f)
    usd = os.path.join(out, os.path.splitext(os.path.basename(path))[0] + ".usda")
    subprocess.run([tumble, "run", path, "--duration", seconds or "0.1", "--out", usd],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    check_compliance(usd)
    stage = Usd.Stage.Open(usd)
    assert stage, f"{usd}: does not open"
    joints = {}
    for prim in stage.GetDefaultPrim().GetChildren():
        if prim.GetCustomDataByKey("tumbleJoint") is not None:
            joints[prim.GetCustomDataByKey("tumbleIndex")] = prim
    assert sorted(joints) == list(range(len(scene["joints"]))), sorted(joints)
    time = Usd.TimeCode(stage.GetStartTimeCode())
    gap = max(check_joint(stage, joints[j], joint, time)
              for j, joint in enumerate(scene["joints"]))
    print(f"{usd}: {len(joints)} joints; the frames meet the file's anchors to {gap:.3g} m")
    for j, joint in enumerate(scene["joints"]):
        if "limits" in joint:
            nearest = check_coordinates(stage, joints[j], joint)
            print(f"{usd}: joints[{j}] ({joint['type']}): within its limits at every frame, "
                  f"{nearest:.3g} from a stop at the nearest")
            # a stop that bounces (restitution) is met between frames: the nearest frame's
            # coordinate is within a frame's swing of it (0.25 degree at 30 fps here)
            reach = 0.5 if joint["type"] == "hinge" else 1e-3
            assert not seconds or nearest <= reach, (j, "never reached a stop", nearest)


def main():
    tumble, out, scenes = sys.argv[1], sys.argv[2], sys.argv[3:]
    os.makedirs(out, exist_ok=True)
    for path in scenes:
        check_scene(tumble, out, path)


if __name__ == "__main__":
    try:
        main()
    except AssertionError as error:
        print(f"check_usd_joints: {error}", file=sys.stderr)
        sys.exit(1)
