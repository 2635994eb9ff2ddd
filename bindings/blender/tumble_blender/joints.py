"""Blender's rigid body constraints as tumble joints (docs/blender.md, "Constraints").

    joints, apart = read_joints(world, bodies, fps, notes)

joints: the scene file's "joints" list; apart: the pairs of body names whose contact the
constraints turn off (Disable Collisions, on by default in Blender). bodies: the names of the
objects that became tumble bodies (a passive object that became a ground plane is the world).

Blender builds each constraint in Bullet at the constraint object's world location (the pivot)
and rotation (its frame; the scale is not used), between object1 (Bullet's body A) and object2
(B). A hinge turns about the frame's z axis and a slider moves along its x axis. tumble's joint
takes body_a = object1 and body_b = object2 (object2 when object1 is the world), so that:
  * a hinge's angle, Bullet's getHingeAngle (A's turn against B's about z), is tumble's (body_a
    against body_b): its limits carry over; with the bodies' roles swapped they are negated;
  * a slider's position, Bullet's (B's travel from A along x), is minus tumble's (body_a's from
    body_b): its limits are negated (and swapped back into order);
  * a MOTOR constraint (Bullet's free 6-dof joint with a motor about and along its frame's x)
    between the bodies of a HINGE or SLIDER whose axis its x lies along becomes that joint's
    velocity motor: Bullet drives the rate of the motor's object1 against its object2 about
    (along) x to the target velocity (for a hinge and a slider alike, unlike the slider's
    position), under a cap its solver applies as max_impulse / fps_step per step, i.e. a torque
    (N m) or force (N) of max_impulse; tumble's cap is that torque or force. Bullet reaches the
    speed within a step when the cap allows; tumble's motor approaches it at 20 /s (a 50 ms
    time constant, docs/joints.md, Motors).
  * Bullet breaks a constraint when the impulse one of its rows applies in one substep reaches
    the breaking threshold (an impulse, N s): a force (torque) of threshold / dt, dt = 1 /
    (fps substeps_per_frame), both tumble's break_force (N) and break_torque (N m). tumble
    compares the magnitude of the reaction, Bullet each row's component: within a factor
    sqrt(3) of each other, never more.
"""
import numpy as np

from .scene_export import rotate, world_pose
from .shapes import ShapeError, f32

TYPES = {"FIXED": "fixed", "POINT": "ball", "HINGE": "hinge", "SLIDER": "slider"}
PARALLEL = 1e-6  # a motor's x axis and its joint's axis: 1 - |cos| at most this


def constraint_objects(world):
    found = world.constraints.objects if world.constraints is not None else []
    return sorted((o for o in found if o.rigid_body_constraint is not None), key=lambda o: o.name)


def frame_axes(obj):
    """(pivot (3,), x axis (3,), z axis (3,)) of a constraint object in the world."""
    origin, q = world_pose(obj)
    return origin, rotate(q, np.array([1.0, 0.0, 0.0])), rotate(q, np.array([0.0, 0.0, 1.0]))


def ends(obj, rbc, bodies):
    """(body_a, body_b or None for the world, +1 when body_a is object1 else -1)."""
    first, second = rbc.object1, rbc.object2
    if first is None or second is None or first == second:
        raise ShapeError(f"'{obj.name}': a {rbc.type} constraint needs two different objects "
                         f"(Object 1 and Object 2), got {first and first.name!r} and "
                         f"{second and second.name!r}")
    for other in (first, second):
        if other.rigid_body is None:
            raise ShapeError(f"'{obj.name}': its {rbc.type} constraint's object '{other.name}' "
                             f"is not a rigid body")
    names = [o.name if o.name in bodies else None for o in (first, second)]
    if names == [None, None]:
        raise ShapeError(f"'{obj.name}': its {rbc.type} constraint joins two objects that are "
                         f"not tumble bodies ('{first.name}', '{second.name}'), nothing to move")
    return (names[0], names[1], 1) if names[0] is not None else (names[1], None, -1)


def joint_of(obj, bodies, fps, substeps):
    rbc = obj.rigid_body_constraint
    body_a, body_b, sign = ends(obj, rbc, bodies)
    pivot, x_axis, z_axis = frame_axes(obj)
    joint = {"type": TYPES[rbc.type], "bodies": [body_a] + ([body_b] if body_b else []),
             "anchor": [float(v) for v in pivot]}
    if rbc.type == "HINGE":
        joint["axis"] = [float(v) for v in z_axis]
        if rbc.use_limit_ang_z:
            joint["limits"] = sorted(sign * f32(v) for v in (rbc.limit_ang_z_lower,
                                                             rbc.limit_ang_z_upper))
    elif rbc.type == "SLIDER":
        joint["axis"] = [float(v) for v in x_axis]
        if rbc.use_limit_lin_x:
            joint["limits"] = sorted(-sign * f32(v) for v in (rbc.limit_lin_x_lower,
                                                              rbc.limit_lin_x_upper))
    if rbc.use_breaking:
        force = f32(rbc.breaking_threshold) * fps * substeps
        joint["break_force"], joint["break_torque"] = force, force
    return joint, sign


def motor_of(obj, joints, bodies):
    """A MOTOR constraint as the motor of the hinge or slider between its bodies."""
    rbc = obj.rigid_body_constraint
    pair = {rbc.object1 and rbc.object1.name, rbc.object2 and rbc.object2.name}
    _, x_axis, _ = frame_axes(obj)
    for joint, sign, source in joints:
        if {source.object1.name, source.object2.name} != pair:
            continue
        cosine = float(np.dot(x_axis, joint.get("axis", [0.0, 0.0, 0.0])))
        hinge = joint["type"] == "hinge" and rbc.use_motor_ang
        slider = joint["type"] == "slider" and rbc.use_motor_lin
        if not (hinge or slider) or 1 - abs(cosine) > PARALLEL:
            continue
        if "motor" in joint:
            raise ShapeError(f"'{obj.name}': a second MOTOR on the {joint['type']} between "
                             f"'{rbc.object1.name}' and '{rbc.object2.name}'")
        order = 1 if rbc.object1 == source.object1 else -1
        speed = rbc.motor_ang_target_velocity if hinge else rbc.motor_lin_target_velocity
        cap = rbc.motor_ang_max_impulse if hinge else rbc.motor_lin_max_impulse
        speed = sign * order * np.sign(cosine) * f32(speed)
        joint["motor"] = {"speed": float(speed), ("max_torque" if hinge else "max_force"): f32(cap)}
        return
    raise ShapeError(f"'{obj.name}': a MOTOR constraint maps onto tumble only as the motor of a "
                     f"HINGE (Angular motor, its x axis along the hinge's z) or SLIDER (Linear "
                     f"motor, its x along the slider's) constraint between the same two objects; "
                     f"none found")


def read_joints(world, bodies, fps, notes):
    """(joints, apart) of the world's constraints; refuses (ShapeError) a type with no
    counterpart, naming the object and the type."""
    mapped, motors, apart = [], [], []
    substeps = world.substeps_per_frame
    for obj in constraint_objects(world):
        rbc = obj.rigid_body_constraint
        if not rbc.enabled:
            notes.append(f"'{obj.name}': its {rbc.type} constraint is disabled: ignored")
            continue
        if rbc.type == "MOTOR":
            motors.append(obj)
            continue
        if rbc.type not in TYPES:
            raise ShapeError(f"'{obj.name}': rigid body constraint type {rbc.type} has no "
                             f"counterpart in tumble (it takes FIXED, POINT, HINGE, SLIDER, and "
                             f"MOTOR on a HINGE's or SLIDER's bodies)")
        joint, sign = joint_of(obj, bodies, fps, substeps)
        mapped.append((joint, sign, rbc))
        if rbc.disable_collisions and len(joint["bodies"]) == 2:
            apart.append(frozenset(joint["bodies"]))
    for obj in motors:
        motor_of(obj, mapped, bodies)
    return [joint for joint, _, _ in mapped], apart
