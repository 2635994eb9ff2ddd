"""Python bindings for tumble, a rigid-body simulation library.

    import tumble
    scene = tumble.Scene.from_file("examples/scenes/sliding_block.json")
    frames = scene.run(method="rk4", dt=1/480)
    frames.position[:, 0, 0]        # x of body 0 at every frame, m

Scenes come from files, from dictionaries in the scene-file format (docs/scene-format.md), or
from a SceneBuilder.

Errors, by one rule: what the library refuses raises TumbleError with the library's status and
message, e.g. "scene.json: bodies[0].mass: must be > 0, got -1"; when what it refused is an
argument's value (INVALID_ARGUMENT, NOT_FINITE, OUT_OF_RANGE, UNSTABLE_STEP) the exception is
also a ValueError. An argument of the wrong type raises TypeError, and a value the bindings
refuse before calling the library (an option that does not apply to the method) ValueError.
A file that cannot be read raises OSError.
"""

import copy
import ctypes
import json
import numbers
from dataclasses import dataclass, field

import numpy as np

from . import _export, _native
from ._native import lib

_export.declare(lib, _native.Error)

__all__ = ["Scene", "SceneBuilder", "Frames", "TumbleError", "TumbleValueError", "METHODS",
           "ACCURACY_SWEEP", "__version__"]

from ._version import __version__  # noqa: E402 (equal to the library's: _native checks it)

_PARSE_ERROR = -14  # TB_STATUS_PARSE_ERROR (include/tumble/status.h)

library_version = lib.tb_version().decode()

METHODS = ("euler", "midpoint", "rk4", "cvode-adams", "cvode-bdf")


class TumbleError(Exception):
    """A tumble call failed. `status` is the status name (e.g. "BAD_SCENE"), `message` the
    library's detail naming what was wrong."""

    def __init__(self, status, message):
        self.status = lib.tb_status_name(status).decode()
        self.message = message
        super().__init__(f"{self.status}: {message}")


class TumbleValueError(TumbleError, ValueError):
    """The library refused an argument's value: a TumbleError, and a ValueError as Python's
    conventions have it."""


_VALUE_STATUSES = {"INVALID_ARGUMENT", "NOT_FINITE", "OUT_OF_RANGE", "UNSTABLE_STEP"}


def _failure(status, message):
    """The exception for a library status: TumbleValueError for a refused value."""
    name = lib.tb_status_name(status).decode()
    return (TumbleValueError if name in _VALUE_STATUSES else TumbleError)(status, message)


def _number(name, value):
    """A float from a real number; TypeError for anything else (a string, None, a bool)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, got {type(value).__name__} {value!r}")
    return float(value)


def _method_code(method):
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {type(method).__name__} {method!r}")
    code, error = ctypes.c_int(), _native.Error()
    status = lib.tb_method_parse(method.encode(), ctypes.byref(code), ctypes.byref(error))
    if status != 0:
        raise _failure(status, error.message.decode())
    return code.value


@dataclass
class Frames:
    """A run's frames: F frames of N bodies, world frame, SI units. position and orientation
    are the pose of each body's shape frame (quaternion w, x, y, z), velocity that frame
    origin's velocity, angular_velocity in rad/s. Energies and momenta are totals per frame."""

    names: list
    t: np.ndarray
    position: np.ndarray
    orientation: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray
    kinetic_energy: np.ndarray
    potential_energy: np.ndarray
    linear_momentum: np.ndarray
    angular_momentum: np.ndarray
    stats: dict = field(default_factory=dict)
    #: the Scene the frames came from: its bodies' names and shapes, for the files below
    source: object = field(default=None, repr=False, compare=False)

    def to_file(self, path, format=None, rotation="cubic"):
        """Writes the frames as they are in memory to path through the library's writer:
        format "csv", "npz", "glb" or "gltf" (default: from the extension); rotation "cubic"
        or "linear" glTF keys. docs/export.md describes the files (tumble's world is z up;
        glTF's root node turns it to y up). Raises TumbleError when the file cannot be
        written (none is left behind), ValueError for a format or rotation it does not know."""
        if self.source is None:
            raise ValueError("these frames have no source Scene: the names and shapes written "
                             "come from the scene they were run from")
        handle, _ = self.source._load()
        try:
            _export.write(lib, _native.Error, _failure, self, handle, self.source._text,
                          self.source._base, path, format, rotation)
        finally:
            lib.tb_scene_destroy(handle)

    def to_gltf(self, path, rotation="cubic"):
        """Animated glTF 2.0 for Blender and browsers: binary .glb, or .gltf text when path
        ends in .gltf; rotation keys "cubic" (following the spin) or "linear"."""
        gltf = str(path).lower().endswith(".gltf")
        self.to_file(path, "gltf" if gltf else "glb", rotation)

    def to_npz(self, path):
        """NumPy .npz: t, position, orientation, velocity, angular_velocity, names, units."""
        self.to_file(path, "npz")

    def to_csv(self, path):
        """CSV with 17 significant digits: every number reads back exactly."""
        self.to_file(path, "csv")


def _stats_dict(stats):
    return {name: getattr(stats, name) for name, _ in _native.IntegratorStats._fields_}


class _Recorder:
    """Collects each frame the C run hands over. Frames are appended as they come, so the
    library alone decides how many there are (and refuses a run with too many)."""

    def __init__(self, bodies):
        self.bodies = bodies
        self.t, self.position, self.orientation = [], [], []
        self.velocity, self.angular_velocity = [], []
        self.kinetic, self.potential, self.P, self.L = [], [], [], []
        self.failure = None

    def __call__(self, frame, t, scene, ctx):
        try:
            self._record(t, scene)
            return 0
        except BaseException as failure:  # cannot cross C: stop the run, re-raise afterwards
            self.failure = failure
            return 1

    def _record(self, t, scene):
        y = lib.tb_scene_states_const(scene)
        p = ctypes.POINTER(ctypes.c_double)
        as_ptr = lambda array: array.ctypes.data_as(p)
        position, q = np.zeros((self.bodies, 3)), np.zeros((self.bodies, 4))
        v, w = np.zeros((self.bodies, 3)), np.zeros((self.bodies, 3))
        for i in range(self.bodies):
            lib.tb_scene_body_shape_pose(scene, y, i, as_ptr(position[i]), as_ptr(q[i]))
            lib.tb_scene_body_velocity(scene, y, i, as_ptr(v[i]))
            lib.tb_scene_body_angular_velocity(scene, y, i, as_ptr(w[i]))
            center = np.ctypeslib.as_array(y, shape=(13 * (i + 1),))[13 * i:13 * i + 3]
            v[i] += np.cross(w[i], position[i] - center)  # velocity of the shape origin
        self.t.append(t)
        self.position.append(position)
        self.orientation.append(q)
        self.velocity.append(v)
        self.angular_velocity.append(w)
        value = ctypes.c_double()
        lib.tb_scene_kinetic_energy(scene, y, ctypes.byref(value))
        self.kinetic.append(value.value)
        lib.tb_scene_potential_energy(scene, y, ctypes.byref(value))
        self.potential.append(value.value)
        P, L = np.zeros(3), np.zeros(3)
        lib.tb_scene_linear_momentum(scene, y, as_ptr(P))
        lib.tb_scene_angular_momentum(scene, y, as_ptr(np.zeros(3)), as_ptr(L))
        self.P.append(P)
        self.L.append(L)

    def frames(self, names, stats):
        shaped = lambda rows, *shape: np.array(rows).reshape((len(self.t),) + shape)
        b = self.bodies
        return Frames(names, np.array(self.t), shaped(self.position, b, 3),
                      shaped(self.orientation, b, 4), shaped(self.velocity, b, 3),
                      shaped(self.angular_velocity, b, 3), np.array(self.kinetic),
                      np.array(self.potential), shaped(self.P, 3), shaped(self.L, 3),
                      _stats_dict(stats))


class Scene:
    """A scene description. Each run() loads it afresh, so runs are independent and
    repeatable."""

    def __init__(self, text, name, base_directory=None):
        self._text = text
        self._name = name
        self._base = base_directory
        handle, run = self._load()  # validate now: errors surface at construction
        self.body_names = [lib.tb_scene_body_name(handle, i).decode()
                           for i in range(lib.tb_scene_body_count(handle))]
        self.run_settings = {"method": lib.tb_method_name(run.integrator.method).decode(),
                             "dt": run.integrator.dt, "rtol": run.integrator.rtol,
                             "atol": run.integrator.atol, "fps": run.fps,
                             "duration": run.duration}
        self.radius_of_gyration = []
        for i in range(len(self.body_names)):
            mass = _native.MassProperties()
            lib.tb_scene_get_mass(handle, i, ctypes.byref(mass))
            self.radius_of_gyration.append(float(np.sqrt(max(mass.moments) / mass.mass)))
        lib.tb_scene_destroy(handle)

    @classmethod
    def from_file(cls, path):
        path = str(path)
        with open(path, "rb") as f:
            text = f.read()
        if b"\0" in text:  # ctypes would pass the text up to the NUL: refuse, as the CLI does
            raise TumbleError(_PARSE_ERROR, f"{path}: a NUL byte at offset {text.index(0)}: "
                                            f"a scene file is JSON text")
        directory = path.rsplit("/", 1)[0] + "/" if "/" in path else ""
        return cls(text, path, directory)

    @classmethod
    def from_dict(cls, description, name="<dict>", base_directory=None):
        return cls(json.dumps(description).encode(), name, base_directory)

    def _load(self):
        handle = ctypes.c_void_p()
        run = _native.RunDef()
        error = _native.Error()
        status = lib.tb_scene_load_string(self._text, self._name.encode(),
                                          self._base.encode() if self._base else None,
                                          ctypes.byref(handle), ctypes.byref(run),
                                          ctypes.byref(error))
        if status != 0:
            raise _failure(status, error.message.decode())
        return handle, run

    def _apply(self, run, method, dt, rtol, atol, fps, duration):
        """The run's settings with the given ones instead; as the CLI, an option that the
        method does not read is refused (ValueError), not ignored."""
        if method is not None:
            # the fields the new method does not read go back to their defaults
            lib.tb_integrator_def_set_method(ctypes.byref(run.integrator), _method_code(method))
        adaptive = bool(lib.tb_method_is_adaptive(run.integrator.method))
        name = lib.tb_method_name(run.integrator.method).decode()
        for option, value, applies in (("dt", dt, not adaptive), ("rtol", rtol, adaptive),
                                       ("atol", atol, adaptive)):
            if value is None:
                continue
            if not applies:
                kind = "adaptive (cvode-*)" if option != "dt" else "fixed-step"
                raise ValueError(f"{option} applies to {kind} methods, and the method is {name}")
            setattr(run.integrator, option, _number(option, value))
        run.fps = _number("fps", fps) if fps is not None else run.fps
        run.duration = _number("duration", duration) if duration is not None else run.duration

    def run(self, method=None, dt=None, rtol=None, atol=None, fps=None, duration=None):
        """Simulates the scene (with the file's settings unless given here) and returns its
        Frames. Raises TumbleError if the integrator refuses the settings or the run fails."""
        handle, run = self._load()
        try:
            self._apply(run, method, dt, rtol, atol, fps, duration)
            recorder = _Recorder(lib.tb_scene_body_count(handle))
            callback = _native.FRAME_FN(recorder)
            stats, error = _native.IntegratorStats(), _native.Error()
            status = lib.tb_scene_run(handle, ctypes.byref(run), callback, None,
                                      ctypes.byref(stats), ctypes.byref(error))
        finally:
            lib.tb_scene_destroy(handle)
        if recorder.failure is not None:
            raise recorder.failure
        if status != 0:
            raise _failure(status, error.message.decode())
        frames = recorder.frames(self.body_names, stats)
        frames.source = self
        return frames


def _default_sweep():
    count = ctypes.c_size_t()
    settings = lib.tb_accuracy_default_sweep(ctypes.byref(count))
    return tuple((lib.tb_method_name(settings[k].method).decode(), settings[k].setting)
                 for k in range(count.value))


#: The sweep of Scene.accuracy and `tumble accuracy` (the library's default): steps per
#: second for the fixed-step methods, rtol for CVODE.
ACCURACY_SWEEP = _default_sweep()


def _accuracy_row(result):
    ok = result.status == 0
    return dict(method=lib.tb_method_name(result.method).decode(), setting=result.setting,
                error=result.error if ok else None,
                position_error=result.position_error if ok else None,
                angle_error=result.angle_error if ok else None,
                cpu_ms=1e3 * result.cpu_seconds, steps=result.steps,
                derivatives=result.derivative_evals,
                status=lib.tb_status_name(result.status).decode(),
                note=None if ok else result.detail.decode())


def _accuracy(self, target_error=1e-3, sweep=ACCURACY_SWEEP):
    """Runs the scene with each integrator setting of `sweep` against cvode-bdf at rtol 1e-11
    (the library's tb_scene_accuracy_sweep, as `tumble accuracy`) and returns (rows, best):
    each row a dict with method, setting, error (the largest displacement |dx| + l angle of a
    body's points at its radius of gyration l, m), position_error (m), angle_error (rad),
    cpu_ms, steps, derivatives, status and note (None, or the library's detail saying why the
    setting did not run); best is the cheapest row with error <= target_error, or None.
    Raises TumbleError when the reference run fails, with the library's reason."""
    target_error = _number("target_error", target_error)
    settings = (_native.AccuracySetting * max(len(sweep), 1))()
    for k, (method, setting) in enumerate(sweep):
        settings[k] = _native.AccuracySetting(_method_code(method), _number("setting", setting))
    handle, run = self._load()
    try:
        definition = lib.tb_accuracy_def_default()
        definition.settings, definition.setting_count = settings, len(sweep)
        results = (_native.AccuracyResult * max(len(sweep), 1))()
        reference, error = _native.AccuracyReference(), _native.Error()
        status = lib.tb_scene_accuracy_sweep(handle, ctypes.byref(run), ctypes.byref(definition),
                                             _native.ACCURACY_FN(), None, results,
                                             ctypes.byref(reference), ctypes.byref(error))
    finally:
        lib.tb_scene_destroy(handle)
    if status != 0:
        raise _failure(status, error.message.decode())
    rows = [_accuracy_row(results[k]) for k in range(len(sweep))]
    best = lib.tb_accuracy_cheapest(results, len(sweep), target_error)
    return rows, rows[best] if best < len(sweep) else None


Scene.accuracy = _accuracy


class SceneBuilder:
    """Builds a scene in code, in the scene-file format's words:

        b = tumble.SceneBuilder()
        b.add_body("ball", shape={"type": "sphere", "radius": 0.1}, mass=1, position=[0, 0, 2])
        b.add_effect("gravity")
        scene = b.build(method="rk4", dt=1/240, fps=60, duration=2)
    """

    def __init__(self):
        self._description = {"bodies": [], "effects": []}

    def add_body(self, name, **fields):
        self._description["bodies"].append({"name": name, **fields})
        return self

    def add_effect(self, type, **fields):
        self._description["effects"].append({"type": type, **fields})
        return self

    def build(self, fps=None, duration=None, **integrator):
        description = copy.deepcopy(self._description)
        if integrator:
            description["integrator"] = integrator
        output = {k: v for k, v in (("fps", fps), ("duration", duration)) if v is not None}
        if output:
            description["output"] = output
        return Scene.from_dict(description, name="<builder>")
