"""Joints' read-outs (include/tumble/joints.h), shared by Scene (at the start) and Simulation
(at its current state): each a library call, its refusal raised as TumbleError."""

import ctypes

import numpy as np

from . import _native
from ._core import as_pointer, failure, lib, number


def _index(joint):
    if isinstance(joint, bool) or not isinstance(joint, (int, np.integer)):
        raise TypeError(f"a joint is an index, got {type(joint).__name__}")
    if joint < 0:  # the library names an index out of range; a negative one is Python's
        raise IndexError(f"joint {joint}: joints are numbered from 0 in the order added")
    return int(joint)


def _pointer(y):
    """A NumPy state array as a double*; a pointer (the scene's own array) as it is."""
    return as_pointer(y) if isinstance(y, np.ndarray) else y


def _check(handle, status):
    if status != 0:
        raise failure(status, lib.tb_scene_detail(handle).decode())


def count(handle) -> int:
    return lib.tb_scene_joint_count(handle)


def describe(handle, names, joint) -> dict:
    """{"type", "bodies", "anchor", "axis"}: the joint's type, its bodies' names ("world" for
    the world) and its anchor and axis as given (tb_scene_joint_def)."""
    definition = _native.JointDef()
    _check(handle, lib.tb_scene_joint_def(handle, _index(joint), ctypes.byref(definition)))
    bodies = [names[i] if i < len(names) else "world"
              for i in (definition.body_a, definition.body_b)]
    return {"type": lib.tb_joint_type_name(definition.type).decode(), "bodies": bodies,
            "anchor": list(definition.anchor), "axis": list(definition.axis)}


def reaction(handle, y, joint):
    """(force (3,) N, torque (3,) N m) on the joint's first body at state y, world frame."""
    force, torque = np.empty(3), np.empty(3)
    _check(handle, lib.tb_scene_joint_reaction(handle, _pointer(y), _index(joint),
                                                as_pointer(force), as_pointer(torque)))
    return force, torque


def error(handle, y, joint):
    """(position error (m, or rad as a sine), velocity error (m/s, rad/s)) at state y."""
    position, velocity = ctypes.c_double(), ctypes.c_double()
    _check(handle, lib.tb_scene_joint_error(handle, _pointer(y), _index(joint),
                                             ctypes.byref(position), ctypes.byref(velocity)))
    return position.value, velocity.value


def axial(handle, y, joint):
    """(coordinate, motor, stop) of a hinge or slider at state y (tb_scene_joint_axial): the
    angle about the axis (rad) or the travel along it (m) from the pose when the joint was made,
    and the motor's and the stop's load on the axial row (N m for a hinge, N for a slider;
    positive drives the coordinate up on the first body), each 0 when not acting."""
    values = [ctypes.c_double() for _ in range(3)]
    _check(handle, lib.tb_scene_joint_axial(handle, _pointer(y), _index(joint),
                                             *(ctypes.byref(v) for v in values)))
    return tuple(v.value for v in values)


def set_motor(handle, joint, mode, value, max_force):
    """Sets a hinge's or slider's motor (tb_scene_set_joint_motor): mode "off", "velocity"
    (value the speed, rad/s or m/s) or "position" (value the target, rad or m); max_force
    (N m or N, > 0) None for the joint's cap as it is. The library's refusal raised, nothing
    changed."""
    if not isinstance(mode, str) or mode not in _native.MOTOR_MODES:
        raise ValueError(f"mode must be one of {', '.join(map(repr, _native.MOTOR_MODES))}, "
                         f"got {mode!r}")
    index, value = _index(joint), number("value", value)
    if max_force is None:  # the cap the joint has (0 without a motor: the library refuses it)
        definition = _native.JointDef()
        _check(handle, lib.tb_scene_joint_def(handle, index, ctypes.byref(definition)))
        max_force = 0.0 if mode == "off" else definition.motor_max_force
    _check(handle, lib.tb_scene_set_joint_motor(handle, index, _native.MOTOR_MODES[mode], value,
                                                 number("max_force", max_force)))


def broken(handle, joint) -> bool:
    flag = ctypes.c_bool()
    _check(handle, lib.tb_scene_joint_broken(handle, _index(joint), ctypes.byref(flag)))
    return flag.value


def project(handle, tolerance=0.0) -> float:
    """Projects the scene's states onto its joints, positions then velocities
    (tb_scene_project_joints); returns the largest joint error left (m or rad, m/s or rad/s).
    tolerance: the largest accepted, 0 for the library's 1e-12. A start the projection cannot
    bring within it raises TumbleError (SOLVER_FAILED, naming the joint), the states unchanged."""
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float, np.floating)):
        raise TypeError(f"tolerance must be a number, got {type(tolerance).__name__}")
    left = ctypes.c_double()
    _check(handle, lib.tb_scene_project_joints(handle, float(tolerance), ctypes.byref(left)))
    return left.value
