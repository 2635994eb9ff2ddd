"""Python bindings for tumble, a rigid-body simulation library.

    import tumble
    scene = tumble.Scene.from_file("examples/scenes/sliding_block.json")
    frames = scene.run(method="rk4", dt=1/480)
    frames.position[:, 0, 0]        # x of body 0 at every frame, m

Scenes come from files, from dictionaries in the scene-file format (docs/scene-format.md), or
from a SceneBuilder. Every error raises TumbleError with the library's message, e.g.
"scene.json: bodies[0].mass: must be > 0, got -1".
"""

import copy
import ctypes
import json
import time
from dataclasses import dataclass, field

import numpy as np

from . import _native
from ._native import lib

__all__ = ["Scene", "SceneBuilder", "Frames", "TumbleError", "METHODS", "ACCURACY_SWEEP",
           "__version__"]

#: The package's version; tests/test_layout.py requires it to equal the C library's.
__version__ = "0.1.0"
library_version = lib.tb_version().decode()

METHODS = ("euler", "midpoint", "rk4", "cvode-adams", "cvode-bdf")


class TumbleError(Exception):
    """A tumble call failed. `status` is the status name (e.g. "BAD_SCENE"), `message` the
    library's detail naming what was wrong."""

    def __init__(self, status, message):
        self.status = lib.tb_status_name(status).decode()
        self.message = message
        super().__init__(f"{self.status}: {message}")


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


def _stats_dict(stats):
    return {name: getattr(stats, name) for name, _ in _native.IntegratorStats._fields_}


class _Recorder:
    """Collects each frame the C run hands over into preallocated arrays."""

    def __init__(self, frames, bodies):
        self.count = 0
        self.names = []
        self.t = np.zeros(frames)
        self.position = np.zeros((frames, bodies, 3))
        self.orientation = np.zeros((frames, bodies, 4))
        self.velocity = np.zeros((frames, bodies, 3))
        self.angular_velocity = np.zeros((frames, bodies, 3))
        self.kinetic = np.zeros(frames)
        self.potential = np.zeros(frames)
        self.P = np.zeros((frames, 3))
        self.L = np.zeros((frames, 3))
        self.failure = None

    def __call__(self, frame, t, scene, ctx):
        try:
            self._record(frame, t, scene)
            return 0
        except Exception as failure:  # cannot cross C: stop the run, re-raise afterwards
            self.failure = failure
            return 1

    def _record(self, k, t, scene):
        y = lib.tb_scene_states_const(scene)
        p = ctypes.POINTER(ctypes.c_double)
        as_ptr = lambda array: array.ctypes.data_as(p)
        self.t[k] = t
        for i in range(self.position.shape[1]):
            position, q = np.zeros(3), np.zeros(4)
            v, w = np.zeros(3), np.zeros(3)
            lib.tb_scene_body_shape_pose(scene, y, i, as_ptr(position), as_ptr(q))
            lib.tb_scene_body_velocity(scene, y, i, as_ptr(v))
            lib.tb_scene_body_angular_velocity(scene, y, i, as_ptr(w))
            arm = position - np.ctypeslib.as_array(y, shape=(13 * (i + 1),))[13 * i:13 * i + 3]
            self.position[k, i], self.orientation[k, i] = position, q
            self.velocity[k, i], self.angular_velocity[k, i] = v + np.cross(w, arm), w
        value = ctypes.c_double()
        lib.tb_scene_kinetic_energy(scene, y, ctypes.byref(value))
        self.kinetic[k] = value.value
        lib.tb_scene_potential_energy(scene, y, ctypes.byref(value))
        self.potential[k] = value.value
        P, L = np.zeros(3), np.zeros(3)
        lib.tb_scene_linear_momentum(scene, y, as_ptr(P))
        lib.tb_scene_angular_momentum(scene, y, as_ptr(np.zeros(3)), as_ptr(L))
        self.P[k], self.L[k] = P, L
        self.count = k + 1


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
            raise TumbleError(status, error.message.decode())
        return handle, run

    def _apply(self, run, method, dt, rtol, atol, fps, duration):
        if method is not None:
            code = ctypes.c_int()
            if lib.tb_method_from_name(method.encode(), ctypes.byref(code)) != 0:
                raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
            # the fields the new method does not read go back to their defaults
            lib.tb_integrator_def_set_method(ctypes.byref(run.integrator), code.value)
        for name, value in (("dt", dt), ("rtol", rtol), ("atol", atol)):
            if value is not None:
                setattr(run.integrator, name, float(value))
        run.fps = float(fps) if fps is not None else run.fps
        run.duration = float(duration) if duration is not None else run.duration

    def run(self, method=None, dt=None, rtol=None, atol=None, fps=None, duration=None):
        """Simulates the scene (with the file's settings unless given here) and returns its
        Frames. Raises TumbleError if the integrator refuses the settings or the run fails."""
        handle, run = self._load()
        try:
            self._apply(run, method, dt, rtol, atol, fps, duration)
            frames = int(np.floor(run.duration * run.fps + 1e-9)) + 1 if run.fps > 0 else 1
            recorder = _Recorder(max(frames, 1), lib.tb_scene_body_count(handle))
            callback = _native.FRAME_FN(recorder)
            stats, error = _native.IntegratorStats(), _native.Error()
            status = lib.tb_scene_run(handle, ctypes.byref(run), callback, None,
                                      ctypes.byref(stats), ctypes.byref(error))
        finally:
            lib.tb_scene_destroy(handle)
        if recorder.failure is not None:
            raise recorder.failure
        if status != 0:
            raise TumbleError(status, error.message.decode())
        n = recorder.count
        return Frames(self.body_names, recorder.t[:n], recorder.position[:n],
                      recorder.orientation[:n], recorder.velocity[:n],
                      recorder.angular_velocity[:n], recorder.kinetic[:n],
                      recorder.potential[:n], recorder.P[:n], recorder.L[:n],
                      _stats_dict(stats))


#: The sweep of Scene.accuracy and `tumble accuracy`: steps per second for the fixed-step
#: methods, rtol for CVODE.
ACCURACY_SWEEP = ([("euler", s) for s in (240, 1000, 4000)] +
                  [("midpoint", s) for s in (60, 240, 1000)] +
                  [("rk4", s) for s in (60, 240, 1000, 4000)] +
                  [(m, r) for m in ("cvode-adams", "cvode-bdf") for r in (1e-3, 1e-5, 1e-7, 1e-9)])


def _errors(frames, reference, lengths):
    """Largest position error (m), angle error (rad) and displacement |dx| + l angle (m)."""
    dx = np.linalg.norm(frames.position - reference.position, axis=2)
    p, r = frames.orientation, reference.orientation
    # the rotation r* p between them: its vector part has length sin(angle / 2); atan2 keeps
    # full precision near zero, where arccos of the dot product would not
    w = np.sum(r * p, axis=2)
    v = r[..., :1] * p[..., 1:] - p[..., :1] * r[..., 1:] - np.cross(r[..., 1:], p[..., 1:])
    angle = 2 * np.arctan2(np.linalg.norm(v, axis=2), np.abs(w))
    return float(dx.max()), float(angle.max()), float((dx + np.asarray(lengths) * angle).max())


def _accuracy(self, target_error=1e-3, sweep=ACCURACY_SWEEP):
    """Runs the scene with each integrator setting of `sweep` against cvode-bdf at rtol 1e-11
    (as `tumble accuracy` does) and returns (rows, best): each row a dict with method,
    setting, error (the largest displacement |dx| + l angle of a body's points at its radius
    of gyration l, m), position_error (m), angle_error (rad), cpu_ms, derivatives, and note
    (None, or why the setting did not run); best is the cheapest row with error <= target."""
    reference = self.run(method="cvode-bdf", rtol=1e-11, atol=0.0)
    rows = []
    for method, setting in sweep:
        options = {"rtol": setting, "atol": 0.0} if method.startswith("cvode") else \
            {"dt": 1.0 / setting}
        start = time.process_time()
        try:
            frames = self.run(method=method, **options)
        except TumbleError as failure:
            rows.append(dict(method=method, setting=setting, note=failure.message))
            continue
        position, angle, error = _errors(frames, reference, self.radius_of_gyration)
        rows.append(dict(method=method, setting=setting, error=error, position_error=position,
                         angle_error=angle, cpu_ms=1e3 * (time.process_time() - start),
                         derivatives=frames.stats["derivative_evals"], note=None))
    ok = [r for r in rows if r["note"] is None and r["error"] <= target_error]
    return rows, min(ok, key=lambda r: r["cpu_ms"]) if ok else None


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
