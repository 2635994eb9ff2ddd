"""ctypes declarations of the C API the bindings use. Struct layouts are checked against the
headers by tests/test_layout.py (a C probe prints sizeof/offsetof from the real headers)."""

import ctypes
import ctypes.util
import json
import os
import pathlib

from ._export import WriterDef
from ._version import LAYOUT_FILE, __version__

DETAIL_SIZE = 1024  # TB_DETAIL_SIZE
STATE_SIZE = 13
FRAME_VALUES = 13  # TB_FRAME_VALUES: doubles a body takes in tb_scene_frame_values


class Error(ctypes.Structure):
    _fields_ = [("status", ctypes.c_int), ("message", ctypes.c_char * DETAIL_SIZE)]


class IntegratorDef(ctypes.Structure):
    _fields_ = [
        ("method", ctypes.c_int),
        ("dt", ctypes.c_double),
        ("rtol", ctypes.c_double),
        ("atol", ctypes.c_double),
        ("atol_vector", ctypes.POINTER(ctypes.c_double)),
        ("max_steps", ctypes.c_long),
        ("initial_step", ctypes.c_double),
        ("max_step", ctypes.c_double),
        ("max_order", ctypes.c_int),
        ("linear_solver", ctypes.c_int),
        ("preconditioner_half_bandwidth", ctypes.c_int),
        ("threads", ctypes.c_int),
        ("internal_cookie", ctypes.c_int),
    ]


class RunDef(ctypes.Structure):
    _fields_ = [
        ("integrator", IntegratorDef),
        ("fps", ctypes.c_double),
        ("duration", ctypes.c_double),
        ("internal_cookie", ctypes.c_int),
    ]


class BodyState(ctypes.Structure):
    _fields_ = [("x", ctypes.c_double * 3), ("q", ctypes.c_double * 4),
                ("P", ctypes.c_double * 3), ("L", ctypes.c_double * 3)]


class MassProperties(ctypes.Structure):
    _fields_ = [
        ("mass", ctypes.c_double),
        ("center", ctypes.c_double * 3),
        ("moments", ctypes.c_double * 3),
        ("rotation", ctypes.c_double * 4),
    ]


class IntegratorStats(ctypes.Structure):
    _fields_ = [
        ("steps", ctypes.c_long),
        ("derivative_evals", ctypes.c_long),
        ("jacobian_derivative_evals", ctypes.c_long),
        ("failed_steps", ctypes.c_long),
        ("error_test_failures", ctypes.c_long),
        ("nonlinear_failures", ctypes.c_long),
        ("linear_iterations", ctypes.c_long),
        ("last_step", ctypes.c_double),
        ("current_step", ctypes.c_double),
        ("last_order", ctypes.c_int),
        ("current_order", ctypes.c_int),
        ("reinitializations", ctypes.c_long),
        ("nonlinear_iterations", ctypes.c_long),
        ("jacobian_evals", ctypes.c_long),
        ("rest_time", ctypes.c_double),
    ]


class AccuracySetting(ctypes.Structure):
    _fields_ = [("method", ctypes.c_int), ("setting", ctypes.c_double)]


class AccuracyDef(ctypes.Structure):
    _fields_ = [
        ("settings", ctypes.POINTER(AccuracySetting)),
        ("setting_count", ctypes.c_size_t),
        ("reference_rtol", ctypes.c_double),
        ("check_rtol", ctypes.c_double),
        ("max_steps", ctypes.c_long),
        ("reference", ctypes.c_int),
        ("reference_step_fraction", ctypes.c_double),
        ("horizon_tolerance", ctypes.c_double),
        ("progress", ctypes.c_void_p),
        ("progress_ctx", ctypes.c_void_p),
        ("internal_cookie", ctypes.c_int),
    ]


class AccuracyResult(ctypes.Structure):
    _fields_ = [
        ("method", ctypes.c_int),
        ("setting", ctypes.c_double),
        ("status", ctypes.c_int),
        ("detail", ctypes.c_char * DETAIL_SIZE),
        ("error", ctypes.c_double),
        ("position_error", ctypes.c_double),
        ("angle_error", ctypes.c_double),
        ("cpu_seconds", ctypes.c_double),
        ("steps", ctypes.c_long),
        ("derivative_evals", ctypes.c_long),
        ("energy_error", ctypes.c_double),
    ]


class AccuracyReference(ctypes.Structure):
    _fields_ = [("error", ctypes.c_double), ("position_error", ctypes.c_double),
                ("angle_error", ctypes.c_double), ("method", ctypes.c_int),
                ("setting", ctypes.c_double), ("check_setting", ctypes.c_double),
                ("horizon", ctypes.c_double), ("horizon_frames", ctypes.c_size_t),
                ("frames", ctypes.c_size_t), ("energy_error", ctypes.c_double),
                ("cvode_detail", ctypes.c_char * DETAIL_SIZE)]


class ContactEvent(ctypes.Structure):
    _fields_ = [("kind", ctypes.c_int), ("t", ctypes.c_double), ("body_a", ctypes.c_size_t),
                ("body_b", ctypes.c_size_t), ("point", ctypes.c_double * 3),
                ("normal", ctypes.c_double * 3), ("speed", ctypes.c_double),
                ("impulse", ctypes.c_double), ("effect", ctypes.c_size_t)]


class Impact(ctypes.Structure):
    """tb_impact (include/tumble/contact_events.h)."""
    _fields_ = [("t", ctypes.c_double), ("body_a", ctypes.c_size_t),
                ("body_b", ctypes.c_size_t), ("effect", ctypes.c_size_t),
                ("speed", ctypes.c_double), ("duration", ctypes.c_double),
                ("steps", ctypes.c_double)]


class UnresolvedImpacts(ctypes.Structure):
    """tb_unresolved_impacts (include/tumble/contact_events.h)."""
    _fields_ = [("watched", ctypes.c_bool), ("dt", ctypes.c_double),
                ("resolution", ctypes.c_double), ("count", ctypes.c_size_t),
                ("first", Impact), ("fastest", Impact)]


CONTACT_EVENT_FN = ctypes.CFUNCTYPE(None, ctypes.POINTER(ContactEvent), ctypes.c_void_p)


class ContactEventsDef(ctypes.Structure):
    _fields_ = [("fn", CONTACT_EVENT_FN), ("ctx", ctypes.c_void_p),
                ("hit_threshold", ctypes.c_double), ("pair_capacity", ctypes.c_size_t),
                ("internal_cookie", ctypes.c_int)]


class JointDef(ctypes.Structure):
    """tb_joint_def (include/tumble/joints.h)."""
    _fields_ = [
        ("type", ctypes.c_int),
        ("body_a", ctypes.c_size_t),
        ("body_b", ctypes.c_size_t),
        ("anchor", ctypes.c_double * 3),
        ("axis", ctypes.c_double * 3),
        ("has_limits", ctypes.c_int),
        ("limits", ctypes.c_double * 2),
        ("restitution", ctypes.c_double),
        ("motor", ctypes.c_int),
        ("motor_speed", ctypes.c_double),
        ("motor_target", ctypes.c_double),
        ("motor_max_force", ctypes.c_double),
        ("break_force", ctypes.c_double),
        ("break_torque", ctypes.c_double),
        ("soft_frequency", ctypes.c_double),
        ("soft_damping_ratio", ctypes.c_double),
        ("internal_cookie", ctypes.c_int),
    ]


#: tb_joint_motor_mode (include/tumble/joints.h) by the name Simulation.set_joint_motor takes
MOTOR_MODES = {"off": 0, "velocity": 1, "position": 2}


STRUCTS = {
    "tb_error": Error,
    "tb_integrator_def": IntegratorDef,
    "tb_run_def": RunDef,
    "tb_mass_properties": MassProperties,
    "tb_integrator_stats": IntegratorStats,
    "tb_accuracy_setting": AccuracySetting,
    "tb_accuracy_def": AccuracyDef,
    "tb_accuracy_result": AccuracyResult,
    "tb_accuracy_reference": AccuracyReference,
    "tb_writer_def": WriterDef,
    "tb_body_state": BodyState,
    "tb_contact_event": ContactEvent,
    "tb_contact_events_def": ContactEventsDef,
    "tb_impact": Impact,
    "tb_unresolved_impacts": UnresolvedImpacts,
    "tb_joint_def": JointDef,
}

FRAME_FN = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_size_t, ctypes.c_double, ctypes.c_void_p,
                            ctypes.c_void_p)
USER_EFFECT_FN = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_double, ctypes.c_void_p,
                                  ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_double),
                                  ctypes.c_void_p)
ACCURACY_FN = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_size_t, ctypes.POINTER(AccuracyResult),
                               ctypes.c_void_p)


def _find_library():
    """The libtumble.so the wheel ships beside this module; TUMBLE_LIBRARY, if set, overrides
    it (a developer's build-shared/libtumble.so); a source checkout without it falls back to
    the system's (after `cmake --install`)."""
    explicit = os.environ.get("TUMBLE_LIBRARY")
    if explicit:
        return explicit
    bundled = pathlib.Path(__file__).resolve().parent / "libtumble.so"
    if bundled.exists():
        return str(bundled)
    found = ctypes.util.find_library("tumble")
    if found is None:
        raise ImportError("libtumble not found: install the package with "
                          "`pip install ./bindings/python` (it builds and ships the library), "
                          "or set TUMBLE_LIBRARY to a libtumble.so built with "
                          "-DBUILD_SHARED_LIBS=ON")
    return found


def check_layout(layout, structs):
    """The ctypes structs against a layout printed by layout_probe.c: a list of mismatches
    ("tb_run_def.fps: offset 16 here, 24 in C"), empty when they agree."""
    mismatches = []
    for name, struct in structs.items():
        c = layout.get(name)
        if c is None:
            mismatches.append(f"{name}: not in the layout")
            continue
        if ctypes.sizeof(struct) != c["size"]:
            mismatches.append(f"{name}: size {ctypes.sizeof(struct)} here, {c['size']} in C")
        for field, _ in struct._fields_:
            offset = getattr(struct, field).offset
            if offset != c.get(field):
                mismatches.append(f"{name}.{field}: offset {offset} here, {c.get(field)} in C")
        extra = set(c) - {"size", "_"} - {f for f, _ in struct._fields_}
        mismatches += [f"{name}.{field}: in C, not declared here" for field in sorted(extra)]
    return mismatches


def _check_layout():
    """Refuses to run when the ctypes declarations disagree with the headers the shipped
    library was built from (layout.json, from the build): fields would be read as garbage."""
    if not LAYOUT_FILE.exists():
        return  # a source checkout: tests/test_layout.py checks against the probe
    mismatches = check_layout(json.loads(LAYOUT_FILE.read_text()), STRUCTS)
    if mismatches:
        raise ImportError("tumble's ctypes declarations disagree with the C headers it was "
                          "built with: " + "; ".join(mismatches))


def _declare(lib):
    c_double_p = ctypes.POINTER(ctypes.c_double)
    signatures = {
        "tb_version": (ctypes.c_char_p, []),
        "tb_status_name": (ctypes.c_char_p, [ctypes.c_int]),
        "tb_status_string": (ctypes.c_char_p, [ctypes.c_int]),
        "tb_method_name": (ctypes.c_char_p, [ctypes.c_int]),
        "tb_method_from_name": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_int)]),
        "tb_integrator_def_set_method": (ctypes.c_int, [ctypes.POINTER(IntegratorDef),
                                                         ctypes.c_int]),
        "tb_method_parse": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_int),
                                           ctypes.POINTER(Error)]),
        "tb_run_def_default": (RunDef, []),
        "tb_scene_load_string": (ctypes.c_int, [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p,
                                                ctypes.POINTER(ctypes.c_void_p),
                                                ctypes.POINTER(RunDef), ctypes.POINTER(Error)]),
        "tb_scene_load_file": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p),
                                              ctypes.POINTER(RunDef), ctypes.POINTER(Error)]),
        "tb_scene_destroy": (None, [ctypes.c_void_p]),
        "tb_scene_detail": (ctypes.c_char_p, [ctypes.c_void_p]),
        "tb_scene_body_count": (ctypes.c_size_t, [ctypes.c_void_p]),
        "tb_scene_ground_count": (ctypes.c_size_t, [ctypes.c_void_p]),
        "tb_scene_body_slot": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                              ctypes.POINTER(ctypes.c_size_t)]),
        "tb_scene_body_motion_kind": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                                     ctypes.POINTER(ctypes.c_int)]),
        "tb_scene_body_reaction": (ctypes.c_int, [ctypes.c_void_p, c_double_p, ctypes.c_size_t,
                                                  c_double_p, c_double_p]),
        "tb_scene_get_mass": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                             ctypes.POINTER(MassProperties)]),
        "tb_mass_tensor": (ctypes.c_int, [ctypes.POINTER(MassProperties), c_double_p]),
        "tb_scene_body_piece_count": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                                     ctypes.POINTER(ctypes.c_size_t)]),
        "tb_scene_body_name": (ctypes.c_char_p, [ctypes.c_void_p, ctypes.c_size_t]),
        "tb_scene_state_size": (ctypes.c_size_t, [ctypes.c_void_p]),
        "tb_scene_states_const": (c_double_p, [ctypes.c_void_p]),
        "tb_scene_body_shape_pose": (ctypes.c_int, [ctypes.c_void_p, c_double_p, ctypes.c_size_t,
                                                    c_double_p, c_double_p]),
        "tb_scene_body_velocity": (ctypes.c_int, [ctypes.c_void_p, c_double_p, ctypes.c_size_t,
                                                  c_double_p]),
        "tb_scene_body_angular_velocity": (ctypes.c_int, [ctypes.c_void_p, c_double_p,
                                                          ctypes.c_size_t, c_double_p]),
        "tb_scene_kinetic_energy": (ctypes.c_int, [ctypes.c_void_p, c_double_p, c_double_p]),
        "tb_scene_potential_energy": (ctypes.c_int, [ctypes.c_void_p, c_double_p, c_double_p]),
        "tb_scene_linear_momentum": (ctypes.c_int, [ctypes.c_void_p, c_double_p, c_double_p]),
        "tb_scene_angular_momentum": (ctypes.c_int, [ctypes.c_void_p, c_double_p, c_double_p,
                                                     c_double_p]),
        "tb_scene_run": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(RunDef), FRAME_FN,
                                        ctypes.c_void_p, ctypes.POINTER(IntegratorStats),
                                        ctypes.POINTER(Error)]),
        "tb_scene_set_sleeping": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_bool]),
        "tb_contact_events_def_default": (ContactEventsDef, []),
        "tb_scene_set_contact_events": (ctypes.c_int, [ctypes.c_void_p,
                                                       ctypes.POINTER(ContactEventsDef)]),
        "tb_scene_contact_events_status": (ctypes.c_int, [ctypes.c_void_p,
                                                          ctypes.POINTER(ctypes.c_size_t)]),
        "tb_contact_event_kind_name": (ctypes.c_char_p, [ctypes.c_int]),
        "tb_scene_asleep_count": (ctypes.c_int, [ctypes.c_void_p,
                                                 ctypes.POINTER(ctypes.c_size_t)]),
        "tb_scene_unresolved_impacts": (ctypes.c_int, [ctypes.c_void_p,
                                                       ctypes.POINTER(UnresolvedImpacts)]),
        "tb_method_is_adaptive": (ctypes.c_int, [ctypes.c_int]),
        "tb_accuracy_default_sweep": (ctypes.POINTER(AccuracySetting),
                                      [ctypes.POINTER(ctypes.c_size_t)]),
        "tb_accuracy_def_default": (AccuracyDef, []),
        "tb_scene_accuracy_sweep": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(RunDef),
                                                   ctypes.POINTER(AccuracyDef), ACCURACY_FN,
                                                   ctypes.c_void_p,
                                                   ctypes.POINTER(AccuracyResult),
                                                   ctypes.POINTER(AccuracyReference),
                                                   ctypes.POINTER(Error)]),
        "tb_accuracy_cheapest": (ctypes.c_size_t, [ctypes.POINTER(AccuracyResult),
                                                   ctypes.c_size_t, ctypes.c_double]),
        "tb_scene_frame_values": (ctypes.c_int, [ctypes.c_void_p, c_double_p, c_double_p]),
        "tb_run_frame_count": (ctypes.c_int, [ctypes.c_double, ctypes.c_double,
                                              ctypes.POINTER(ctypes.c_size_t),
                                              ctypes.POINTER(Error)]),
        "tb_run_output_frames": (ctypes.c_int, [ctypes.c_size_t, ctypes.c_double,
                                                ctypes.c_double, ctypes.POINTER(ctypes.c_size_t),
                                                ctypes.POINTER(Error)]),
        "tb_method_check_setting": (ctypes.c_int, [ctypes.c_int, ctypes.c_char_p,
                                                   ctypes.POINTER(Error)]),
        "tb_scene_states": (c_double_p, [ctypes.c_void_p]),
        "tb_scene_find_body": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_char_p,
                                              ctypes.POINTER(ctypes.c_size_t)]),
        "tb_scene_get_state": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                              ctypes.POINTER(BodyState)]),
        "tb_scene_set_state": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                              ctypes.POINTER(BodyState)]),
        "tb_scene_set_velocity": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t, c_double_p,
                                                 c_double_p]),
        "tb_scene_integrator_create": (ctypes.c_int, [ctypes.c_void_p,
                                                      ctypes.POINTER(IntegratorDef),
                                                      ctypes.c_double,
                                                      ctypes.POINTER(ctypes.c_void_p)]),
        "tb_integrator_advance": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_double]),
        "tb_integrator_step": (ctypes.c_int, [ctypes.c_void_p]),
        "tb_integrator_time": (ctypes.c_double, [ctypes.c_void_p]),
        "tb_integrator_reset": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_double]),
        "tb_integrator_get_stats": (ctypes.c_int, [ctypes.c_void_p,
                                                   ctypes.POINTER(IntegratorStats)]),
        "tb_integrator_detail": (ctypes.c_char_p, [ctypes.c_void_p]),
        "tb_integrator_destroy": (None, [ctypes.c_void_p]),
        "tb_scene_add_user_effect": (ctypes.c_int, [ctypes.c_void_p, USER_EFFECT_FN,
                                                    ctypes.c_void_p]),
        "tb_effect_add_force": (ctypes.c_int, [ctypes.c_void_p, c_double_p, c_double_p,
                                               ctypes.c_size_t, c_double_p, c_double_p]),
        "tb_effect_add_torque": (ctypes.c_int, [ctypes.c_void_p, c_double_p, ctypes.c_size_t,
                                                c_double_p]),
        "tb_joint_type_name": (ctypes.c_char_p, [ctypes.c_int]),
        "tb_scene_joint_count": (ctypes.c_size_t, [ctypes.c_void_p]),
        "tb_scene_joint_def": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                              ctypes.POINTER(JointDef)]),
        "tb_scene_joint_reaction": (ctypes.c_int, [ctypes.c_void_p, c_double_p, ctypes.c_size_t,
                                                   c_double_p, c_double_p]),
        "tb_scene_joint_error": (ctypes.c_int, [ctypes.c_void_p, c_double_p, ctypes.c_size_t,
                                                c_double_p, c_double_p]),
        "tb_scene_joint_broken": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                                 ctypes.POINTER(ctypes.c_bool)]),
        "tb_scene_project_joints": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_double,
                                                   c_double_p]),
        "tb_scene_joint_axial": (ctypes.c_int, [ctypes.c_void_p, c_double_p, ctypes.c_size_t,
                                                c_double_p, c_double_p, c_double_p]),
        "tb_scene_set_joint_motor": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                                    ctypes.c_int, ctypes.c_double,
                                                    ctypes.c_double]),
    }
    for name, (restype, argtypes) in signatures.items():
        function = getattr(lib, name)
        function.restype = restype
        function.argtypes = argtypes
    return lib


class _ByAddress:
    """The read-outs a frame calls, declared with plain addresses (ints) for their arrays:
    what the run's frame callback passes, without making a ctypes pointer object per array
    per frame (scene/_scene.py's _Recorder; the same C functions as above)."""

    def __init__(self, lib):
        p = ctypes.c_void_p

        def bind(name, restype, *argtypes):
            return ctypes.CFUNCTYPE(restype, *argtypes)((name, lib))

        self.states = bind("tb_scene_states_const", p, p)
        self.frame_values = bind("tb_scene_frame_values", ctypes.c_int, p, p, p)
        self.kinetic_energy = bind("tb_scene_kinetic_energy", ctypes.c_int, p, p, p)
        self.potential_energy = bind("tb_scene_potential_energy", ctypes.c_int, p, p, p)
        self.linear_momentum = bind("tb_scene_linear_momentum", ctypes.c_int, p, p, p)
        self.angular_momentum = bind("tb_scene_angular_momentum", ctypes.c_int, p, p, p, p)
        self.joint_reaction = bind("tb_scene_joint_reaction", ctypes.c_int, p, p,
                                   ctypes.c_size_t, p, p)
        self.joint_broken = bind("tb_scene_joint_broken", ctypes.c_int, p, ctypes.c_size_t, p)


def _check_version(lib, path):
    """Refuses a libtumble of another version than this package's: the ctypes declarations
    above describe this version's structs, and another's would be read as garbage."""
    lib.tb_version.restype = ctypes.c_char_p
    lib.tb_version.argtypes = []
    found = lib.tb_version().decode()
    if found != __version__:
        raise ImportError(f"{path} is libtumble {found}, but this tumble Python package is "
                          f"{__version__}: use the libtumble built from the same source "
                          f"(set TUMBLE_LIBRARY to its path)")
    return lib


_check_layout()
_path = _find_library()
# CDLL (not PyDLL): every foreign call releases the GIL while C runs, so other Python threads
# go on during a long run (tests/test_threads.py).
lib = _declare(_check_version(ctypes.CDLL(_path), _path))
by_address = _ByAddress(lib)
