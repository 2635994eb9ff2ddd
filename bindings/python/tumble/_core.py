"""What every part of the package shares: the library handle, its exceptions and the checks of
arguments made before calling it."""

import contextlib
import ctypes
import numbers
import re
import signal
import threading


from . import _export, _native
from ._native import lib

_export.declare(lib, _native.Error)

DOUBLE_P = ctypes.POINTER(ctypes.c_double)


def as_pointer(array):
    """A C double* into a contiguous float64 NumPy array (no copy)."""
    return array.ctypes.data_as(DOUBLE_P)


_PARSE_ERROR = -14  # TB_STATUS_PARSE_ERROR (include/tumble/status.h)
_BAD_SCENE = -15  # TB_STATUS_BAD_SCENE

library_version = lib.tb_version().decode()

METHODS = ("euler", "midpoint", "rk4", "cvode-adams", "cvode-bdf", "rosenbrock",
           "ark-imex")


class TumbleError(Exception):
    """A tumble call failed. `status` is the status name (e.g. "BAD_SCENE"), `message` the
    library's detail naming what was wrong. A run that failed part-way keeps the frames made
    before the failure in `frames` (a Frames, or None)."""

    def __init__(self, status, message):
        self.status = lib.tb_status_name(status).decode()
        self.message = message
        self.frames = None
        super().__init__(f"{self.status}: {message}")


class TumbleValueError(TumbleError, ValueError):
    """The library refused an argument's value: a TumbleError, and a ValueError as Python's
    conventions have it."""


_VALUE_STATUSES = {"INVALID_ARGUMENT", "NOT_FINITE", "OUT_OF_RANGE", "UNSTABLE_STEP"}


def failure(status, message):
    """The exception for a library status: TumbleValueError for a refused value."""
    name = lib.tb_status_name(status).decode()
    return (TumbleValueError if name in _VALUE_STATUSES else TumbleError)(status, message)


# "integrator: def.rtol: must be in [1e-15, 1)": the library names the C field of tb_integrator_def
_SETTING_FIELD = re.compile(r"\bintegrator: def\.(dt|rtol|atol|threads|max_steps):")


def settings_failure(status, message):
    """failure() for a run made with apply_settings' arguments: a refused setting is named as
    the caller typed it (rtol), not as the C field it fills (integrator: def.rtol)."""
    return failure(status, _SETTING_FIELD.sub(r"\1:", message))


def number(name, value):
    """A float from a real number; TypeError for anything else (a string, None, a bool)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, got {type(value).__name__} {value!r}")
    return float(value)


def method_code(method):
    """The tb_method of a name (\"rk4\"), by the library's parser."""
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {type(method).__name__} {method!r}")
    code, error = ctypes.c_int(), _native.Error()
    status = lib.tb_method_parse(method.encode(), ctypes.byref(code), ctypes.byref(error))
    if status != 0:
        raise failure(status, error.message.decode())
    return code.value




def stats_dict(stats):
    """tb_integrator_stats as a dict: steps, derivative_evals, failed_steps, ..."""
    return {name: getattr(stats, name) for name, _ in _native.IntegratorStats._fields_}


_INT_MAX = 2**(8 * ctypes.sizeof(ctypes.c_int) - 1) - 1  # tb_integrator_def.threads
_LONG_MAX = 2**(8 * ctypes.sizeof(ctypes.c_long) - 1) - 1  # tb_integrator_def.max_steps


def whole_number(name, value, low, high):
    """An int from an integral value in [low, high]; TypeError for anything else, ValueError out
    of range (a C int or long would truncate it: 2**32 + 1 threads became 1)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an int, got {type(value).__name__} {value!r}")
    if not low <= value <= high:
        raise ValueError(f"{name} must be from {low} to {high}, got {value}")
    return int(value)


def check_setting(method, setting):
    """ValueError if the method (a tb_method) does not read the setting: the library's method
    table decides (tb_method_check_setting), as it does for scene files and the CLI."""
    error = _native.Error()
    status = lib.tb_method_check_setting(method, setting.encode(), ctypes.byref(error))
    if status != 0:
        raise ValueError(f"{setting} {error.message.decode()}")


def apply_settings(run, method=None, dt=None, rtol=None, atol=None, fps=None, duration=None,
                   threads=None, max_steps=None):
    """A tb_run_def with the given settings instead of its own; as the CLI and scene files, an
    option that the method does not read is refused (ValueError), not ignored."""
    if method is not None:
        # the fields the new method does not read go back to their defaults
        lib.tb_integrator_def_set_method(ctypes.byref(run.integrator), method_code(method))
    code = run.integrator.method
    for option, value in (("dt", dt), ("rtol", rtol), ("atol", atol), ("threads", threads),
                          ("max_steps", max_steps)):
        if value is not None:
            check_setting(code, option)
    for option, value in (("dt", dt), ("rtol", rtol), ("atol", atol)):
        if value is not None:
            setattr(run.integrator, option, number(option, value))
    if threads is not None:  # 0: one per processor
        run.integrator.threads = whole_number("threads", threads, 0, _INT_MAX)
    if max_steps is not None:
        run.integrator.max_steps = whole_number("max_steps", max_steps, 1, _LONG_MAX)
    run.fps = number("fps", fps) if fps is not None else run.fps
    run.duration = number("duration", duration) if duration is not None else run.duration


class _Interrupt:
    """Whether Ctrl-C came while C code ran (see deferred_interrupt)."""

    def __init__(self):
        self.pending = False

    def note(self, signum, frame):
        self.pending = True


_active = []  # the deferred_interrupt in force, innermost last


@contextlib.contextmanager
def deferred_interrupt():
    """While a library call runs (calling Python back only at frames or derivatives), Ctrl-C
    is noted instead of raised at once: raised on entry to a ctypes callback it would be lost
    (ctypes reports and drops it). Callbacks look at `pending` and stop the call; after it,
    the caller raises KeyboardInterrupt. Nested uses share the outermost one. Only the main thread with Python's own SIGINT
    handler is changed; elsewhere nothing is deferred."""
    if _active:
        yield _active[-1]
        return
    interrupt = _Interrupt()
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield interrupt
        return
    previous = signal.signal(signal.SIGINT, interrupt.note)
    _active.append(interrupt)
    try:
        yield interrupt
    finally:
        _active.pop()
        signal.signal(signal.SIGINT, previous)

