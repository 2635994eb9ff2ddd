"""ctypes declarations of the C API the bindings use. Struct layouts are checked against the
headers by tests/test_layout.py (a C probe prints sizeof/offsetof from the real headers)."""

import ctypes
import ctypes.util
import os
import pathlib

from ._export import WriterDef
from ._version import __version__

DETAIL_SIZE = 256
STATE_SIZE = 13


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
    ]


class AccuracyReference(ctypes.Structure):
    _fields_ = [("error", ctypes.c_double), ("position_error", ctypes.c_double),
                ("angle_error", ctypes.c_double)]


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
}

FRAME_FN = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_size_t, ctypes.c_double, ctypes.c_void_p,
                            ctypes.c_void_p)
ACCURACY_FN = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_size_t, ctypes.POINTER(AccuracyResult),
                               ctypes.c_void_p)


def _find_library():
    """TUMBLE_LIBRARY if set; else a libtumble.so next to this package (a bundled copy); else
    the system's (after `cmake --install`)."""
    explicit = os.environ.get("TUMBLE_LIBRARY")
    if explicit:
        return explicit
    here = pathlib.Path(__file__).resolve().parent
    for name in ("libtumble.so", "libtumble.so.0", "libtumble.dylib"):
        if (here / name).exists():
            return str(here / name)
    found = ctypes.util.find_library("tumble")
    if found is None:
        raise OSError("libtumble not found: build tumble with -DBUILD_SHARED_LIBS=ON and set "
                      "TUMBLE_LIBRARY to the libtumble.so path, or install it")
    return found


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
        "tb_scene_get_mass": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_size_t,
                                             ctypes.POINTER(MassProperties)]),
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
    }
    for name, (restype, argtypes) in signatures.items():
        function = getattr(lib, name)
        function.restype = restype
        function.argtypes = argtypes
    return lib


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


_path = _find_library()
lib = _declare(_check_version(ctypes.CDLL(_path), _path))
