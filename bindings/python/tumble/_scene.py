"""Scenes (from files, dictionaries or a builder, _builder.py), runs that return every frame as
NumPy arrays, and the accuracy sweep."""

import ctypes
import json
import math
import os
from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np

from . import _events, _export, _joints, _native
from ._core import (_BAD_SCENE, _PARSE_ERROR, TumbleError, TumbleValueError, apply_settings,
                    deferred_interrupt, failure, lib, method_code, number, settings_failure,
                    stats_dict)


def _json_ready(value, name, path):
    """value with NumPy arrays and scalars as lists and Python numbers, for JSON. A NaN or an
    infinity has no JSON spelling (json.dumps wrote NaN, which the parser then refused as
    "invalid token" at a column of text the caller never wrote): it is refused here naming the
    field, in the loader's words."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, dict):
        return {key: _json_ready(item, name, f"{path}.{key}" if path else str(key))
                for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_ready(item, name, f"{path}[{k}]") for k, item in enumerate(value)]
    if isinstance(value, float) and not math.isfinite(value):
        raise TumbleValueError(_BAD_SCENE, f"{name}: {path}: must be a finite number, "
                                           f"got {value}")
    return value

@dataclass
class Frames:
    """A run's frames: F frames of N bodies, world frame (z up), SI units.

    t                 (F,) s
    position          (F, N, 3) m, the origin of each body's shape frame (the frame its shape
                      and tb_body_def.orientation are given in), not its centre of mass
    orientation       (F, N, 4) unit quaternion (w, x, y, z), shape frame -> world
    velocity          (F, N, 3) m/s, of the shape-frame origin (v + omega x (origin - x))
    angular_velocity  (F, N, 3) rad/s, world frame
    kinetic_energy    (F,) J, all bodies;  potential_energy (F,) J, gravity and springs
    linear_momentum   (F, 3) kg m/s, total;  angular_momentum (F, 3) kg m^2/s, total about
                      the world origin (about another point: angular_momentum_about)
    center_of_mass    (F, 3) m, of all bodies
    stats             what the integrator did (steps, derivative_evals, ...)
    events            the run's contact events (run(events=True)), a NumPy structured array of
                      EVENT_DTYPE in the order they happened; None when not asked for
    joint_force       (F, J, 3) N, joint_torque (F, J, 3) N m (about the anchor) and
                      joint_broken (F, J) bool: each joint's reaction on its first body, world
                      frame (run(joint_reactions=True)); None when not asked for

    The per-body arrays are views of one (F, N, 13) block, the layout of
    tb_scene_frame_values (include/tumble/scene.h)."""

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
    center_of_mass: np.ndarray
    stats: dict = field(default_factory=dict)
    #: the Scene the frames came from: its bodies' names and shapes, for the files below
    source: object = field(default=None, repr=False, compare=False)
    events: Optional[np.ndarray] = field(default=None, compare=False)
    joint_force: Optional[np.ndarray] = field(default=None, compare=False)
    joint_torque: Optional[np.ndarray] = field(default=None, compare=False)
    joint_broken: Optional[np.ndarray] = field(default=None, compare=False)

    def angular_momentum_about(self, point) -> np.ndarray:
        """Total angular momentum (F, 3), kg m^2/s, about `point`: a world point (3,) in m, or
        one per frame (F, 3) such as center_of_mass, the centre of mass of all bodies.
        L_point = L_origin - point x P, since L_origin = sum x_i x P_i + L_i."""
        point = np.broadcast_to(np.asarray(point, dtype=float), self.linear_momentum.shape)
        return self.angular_momentum - np.cross(point, self.linear_momentum)

    def to_file(self, path, format: Optional[str] = None, rotation: str = "cubic") -> None:
        """Writes the frames as they are in memory to path through the library's writer:
        format "csv", "npz", "glb", "gltf" or "usda" (default: from the extension); rotation
        "cubic" or "linear" glTF keys. docs/export.md describes the files (tumble's world is z up;
        glTF's root node turns it to y up). Raises TumbleError when the file cannot be
        written (none is left behind), ValueError for a format or rotation it does not know."""
        if self.source is None:
            raise ValueError("these frames have no source Scene: the names and shapes written "
                             "come from the scene they were run from")
        handle, _ = self.source._load()
        try:
            _export.write(lib, _native.Error, failure, self, handle, path, format, rotation)
        finally:
            lib.tb_scene_destroy(handle)

    def to_gltf(self, path, rotation: str = "cubic") -> None:
        """Animated glTF 2.0 for Blender and browsers: binary .glb, or .gltf text when path
        ends in .gltf; rotation keys "cubic" (following the spin) or "linear"."""
        gltf = str(path).lower().endswith(".gltf")
        self.to_file(path, "gltf" if gltf else "glb", rotation)

    def to_usd(self, path) -> None:
        """USD text (.usda) for usdview, Houdini and Omniverse: an Xform a body with its shape,
        translate and orient samples at every frame (time code k is frame k), z up, metres."""
        self.to_file(path, "usda")

    def to_npz(self, path) -> None:
        """NumPy .npz: t, position, orientation, velocity, angular_velocity, names, units."""
        self.to_file(path, "npz")

    def to_csv(self, path) -> None:
        """CSV with 17 significant digits: every number reads back exactly."""
        self.to_file(path, "csv")




def _read_scene_file(path):
    """(text, name, base directory) of a scene file: OSError if it cannot be read."""
    path = os.fspath(path)
    if not isinstance(path, str):
        path = os.fsdecode(path)
    with open(path, "rb") as f:
        text = f.read()
    directory = path.rsplit("/", 1)[0] + "/" if "/" in path else ""
    return text, path, directory


def dynamic_bodies(handle):
    """The ids of the scene's bodies that have a state (dynamic ones), in slot order: the
    rows of the state array (tb_scene_body_slot)."""
    ids, slot = [], ctypes.c_size_t()
    for i in range(lib.tb_scene_body_count(handle)):
        if lib.tb_scene_body_slot(handle, i, ctypes.byref(slot)) == 0 and slot.value != ctypes.c_size_t(-1).value:
            ids.append(i)
    return ids


#: A body's motion (tb_body_motion, include/tumble/body.h): Scene.motions' words, by code.
MOTIONS = ("dynamic", "static", "keyframed")


def body_motions(handle):
    """Each body's motion, "dynamic", "static" or "keyframed" (tb_scene_body_motion_kind)."""
    motions, code = [], ctypes.c_int()
    for i in range(lib.tb_scene_body_count(handle)):
        lib.tb_scene_body_motion_kind(handle, i, ctypes.byref(code))
        motions.append(MOTIONS[code.value])
    return motions


class _Recorder:
    """Collects each frame the C run hands over into one array allocated up front for the
    frame count the library gives (tb_run_output_frames): a frame costs one call that fills it
    (tb_scene_frame_values) and four for the totals, and no copy."""

    def __init__(self, handle, run, masses, on_frame=None, joints=0):
        # the library bounds the frames kept (TB_RUN_MAX_BODY_FRAMES) before anything is allocated
        count, error = ctypes.c_size_t(), _native.Error()
        bodies = lib.tb_scene_body_count(handle)
        status = lib.tb_run_output_frames(bodies, run.duration, run.fps, ctypes.byref(count),
                                          ctypes.byref(error))
        if status != 0:
            raise failure(status, error.message.decode())
        frames = count.value
        self.t = np.empty(frames)
        self.values = np.empty((frames, bodies, _native.FRAME_VALUES))
        # kinetic, potential, P[3], L[3] about the origin, centre of mass[3]
        self.totals = np.empty((frames, 11))
        self.bodies = bodies
        # the centre of mass of the bodies that move (those with a state, in slot order)
        self.dynamic = dynamic_bodies(handle)
        moving = np.asarray(masses)[self.dynamic] if self.dynamic else np.zeros(0)
        self.mass_fraction = moving / max(sum(moving), np.finfo(float).tiny)
        self.count = 0
        # each joint's force and torque (6) and broken flag per frame, when asked for
        self.joints = np.empty((frames, joints, 6)) if joints else None
        self.broken = np.zeros((frames, joints), dtype=np.bool_) if joints else None
        self.on_frame = on_frame
        self.failure = None
        self.interrupt = None  # the run's deferred_interrupt
        self._origin = np.zeros(3)
        self._values_address, self._values_stride = self.values.ctypes.data, self.values.strides[0]
        self._totals_address, self._totals_stride = self.totals.ctypes.data, self.totals.strides[0]
        self._y_address, self._x = None, None
        self.callback = _native.FRAME_FN(self._called)  # kept alive while the run lasts

    def _called(self, frame, t, scene, ctx):
        try:
            self._record(frame, t, scene)
            if self.interrupt is not None and self.interrupt.pending:
                raise KeyboardInterrupt
            if self.on_frame is not None:
                # read-only for good: a view of a read-only buffer cannot be made writable
                view = np.frombuffer(memoryview(self.values[frame]).toreadonly(),
                                     dtype=np.float64).reshape(self.values.shape[1:])
                self.on_frame(frame, t, view)
            return 0
        except BaseException as caught:  # cannot cross C: stop the run, re-raise afterwards
            self.failure = caught
            return 1

    def _record(self, k, t, scene):
        if not 0 <= k < len(self.t):  # the writes below go by address: never past the end
            raise IndexError(f"frame {k} of a run of {len(self.t)} frames")
        fast = _native.by_address  # addresses, not pointer objects: this runs every frame
        y = fast.states(scene)
        totals = self._totals_address + k * self._totals_stride
        fast.frame_values(scene, y, self._values_address + k * self._values_stride)
        fast.kinetic_energy(scene, y, totals)
        fast.potential_energy(scene, y, totals + 8)
        fast.linear_momentum(scene, y, totals + 16)
        fast.angular_momentum(scene, y, self._origin.ctypes.data, totals + 40)
        if y != self._y_address:  # the scene's array: it stays put during a run
            self._y_address = y
            slots = len(self.dynamic)
            n = slots * _native.STATE_SIZE
            array = np.frombuffer((ctypes.c_double * max(n, 1)).from_address(y), count=n)
            self._x = array.reshape(slots, _native.STATE_SIZE)[:, 0:3]
        self.totals[k, 8:11] = self.mass_fraction @ self._x
        if self.joints is not None:
            self._record_joints(k, scene, y)
        self.t[k] = t
        self.count = k + 1

    def _record_joints(self, k, scene, y):
        fast = _native.by_address
        for j in range(self.joints.shape[1]):
            row = self.joints[k, j]
            status = fast.joint_reaction(scene, y, j, row.ctypes.data, row.ctypes.data + 24)
            if status == 0:
                status = fast.joint_broken(scene, j, self.broken[k].ctypes.data + j)
            if status != 0:
                raise failure(status, lib.tb_scene_detail(scene).decode())

    def frames(self, source, stats):
        k = self.count
        values, totals = self.values[:k], self.totals[:k]
        frames = Frames(list(source.body_names), self.t[:k], values[..., 0:3], values[..., 3:7],
                        values[..., 7:10], values[..., 10:13], totals[:, 0], totals[:, 1],
                        totals[:, 2:5], totals[:, 5:8], totals[:, 8:11], stats_dict(stats),
                        source)
        if self.joints is not None:
            frames.joint_force = self.joints[:k, :, 0:3]
            frames.joint_torque = self.joints[:k, :, 3:6]
            frames.joint_broken = self.broken[:k]
        return frames


class Scene:
    """A scene description: bodies, effects, and its own integrator and output settings, in
    the scene-file format (docs/scene-format.md). The library checks it when the Scene is made
    (TumbleError naming the field). Each run() loads it afresh, so runs are independent and
    repeatable; a Scene pickles as its text.

    body_names          the bodies' names, in order (body i is index i everywhere)
    masses              each body's mass, kg (a static or keyframed body's is not used)
    motions             each body's motion: "dynamic", "static" (fixed in the world) or
                        "keyframed" (its pose follows its keys); the latter two have no state
    radius_of_gyration  each body's sqrt(I_max / M), m
    center_of_mass      each body's centre of mass in its shape frame, (3,) m
    inertia             each body's inertia tensor about its centre of mass in its shape
                        frame, (3, 3) kg m^2 (of a body of pieces: theirs combined)
    piece_counts        each body's number of convex pieces (0: no shape)
    joint_count         how many joints; joints: each one's type, bodies, anchor and axis;
                        joint_reaction(j), joint_error(j), joint_broken(j), joint_axial(j)
                        at the start
    run_settings        the file's method, dt (s), rtol, atol, max_steps, fps and duration (s)
    """

    def __init__(self, text: "bytes | str | os.PathLike", name: Optional[str] = None,
                 base_directory: Optional[str] = None):
        """A Scene from JSON text (bytes, or a str starting with "{"), or from a scene file's
        path (any other str, or an os.PathLike: as Scene.from_file); name labels its messages,
        base_directory is where files it names (OBJ meshes) are found. Scene.from_file and
        Scene.from_dict are the usual ways in. TypeError for anything else."""
        if isinstance(text, os.PathLike) or (isinstance(text, str) and
                                             not text.lstrip().startswith("{")):
            text, file_name, file_base = _read_scene_file(text)
            name = file_name if name is None else name
            base_directory = file_base if base_directory is None else base_directory
        elif isinstance(text, str):
            text = text.encode()
        elif isinstance(text, (bytearray, memoryview)):
            text = bytes(text)
        if not isinstance(text, bytes):
            raise TypeError(f"a Scene is made from JSON text (bytes or str) or a scene file's "
                            f"path, got {type(text).__name__}")
        if name is None:
            name = "<text>"
        if not isinstance(name, str) or not (base_directory is None or
                                             isinstance(base_directory, str)):
            raise TypeError("name and base_directory must be str")
        if b"\0" in text:  # ctypes would pass the text up to the NUL: refuse, as the CLI does
            raise TumbleError(_PARSE_ERROR, f"{name}: a NUL byte at offset {text.index(0)}: "
                                            f"a scene file is JSON text")
        self._text = text
        self._name = name
        self._base = base_directory
        handle, run = self._load()  # validate now: errors surface at construction
        self.body_names = [lib.tb_scene_body_name(handle, i).decode()
                           for i in range(lib.tb_scene_body_count(handle))]
        self.run_settings = {"method": lib.tb_method_name(run.integrator.method).decode(),
                             "dt": run.integrator.dt, "rtol": run.integrator.rtol,
                             "atol": run.integrator.atol,
                             "max_steps": run.integrator.max_steps, "fps": run.fps,
                             "duration": run.duration}
        self.radius_of_gyration = []
        #: each body's mass, kg
        self.masses = []
        self.center_of_mass, self.inertia, self.piece_counts = [], [], []
        #: the ids of the bodies with a state (dynamic ones), in the order of their slots
        self.dynamic_bodies = dynamic_bodies(handle)
        #: each body's motion: "dynamic", "static" or "keyframed"
        self.motions = body_motions(handle)
        for i in range(len(self.body_names)):
            mass = _native.MassProperties()
            lib.tb_scene_get_mass(handle, i, ctypes.byref(mass))
            moving = i in self.dynamic_bodies  # static, keyframed: infinite mass, no radius
            self.radius_of_gyration.append(
                float(np.sqrt(max(mass.moments) / mass.mass)) if moving else 0.0)
            self.masses.append(mass.mass)
            self.center_of_mass.append(np.array(mass.center[:]))
            tensor = (ctypes.c_double * 9)()
            lib.tb_mass_tensor(ctypes.byref(mass), tensor)
            self.inertia.append(np.array(tensor[:]).reshape(3, 3))
            count = ctypes.c_size_t()
            lib.tb_scene_body_piece_count(handle, i, ctypes.byref(count))
            self.piece_counts.append(count.value)
        #: how many joints the scene has (its "joints", docs/joints.md)
        self.joint_count = _joints.count(handle)
        #: each joint's type, bodies' names ("world" for the world), anchor and axis as given
        self.joints = [_joints.describe(handle, self.body_names, j)
                       for j in range(self.joint_count)]
        lib.tb_scene_destroy(handle)

    def __reduce__(self):  # pickled (Dask) as its text, reloaded and checked on arrival
        return (Scene, (self._text, self._name, self._base))

    @classmethod
    def coerce(cls, scene) -> "Scene":
        """A Scene from a Scene, a SceneBuilder (built with its settings), a scene-file path
        (str or os.PathLike) or a dict in the scene-file format; TypeError for anything else."""
        from ._builder import SceneBuilder  # here: the builder's module imports this one

        if isinstance(scene, Scene):
            return scene
        if isinstance(scene, SceneBuilder):
            return scene.build()
        if isinstance(scene, (str, os.PathLike)):
            return cls.from_file(scene)
        if isinstance(scene, dict):
            return cls.from_dict(scene)
        raise TypeError(f"a scene is a tumble.Scene, a path or a dict, got {type(scene).__name__}")

    @classmethod
    def from_file(cls, path: "str | os.PathLike") -> "Scene":
        """The scene in a JSON scene file (meshes it names are found beside it). OSError if
        it cannot be read, TumbleError (PARSE_ERROR with line and column, BAD_SCENE naming
        the field) if the library refuses it."""
        return cls(*_read_scene_file(path))

    @classmethod
    def from_dict(cls, description: dict, name: str = "<dict>",
                  base_directory: Optional[str] = None) -> "Scene":
        """The scene a dict in the scene-file format describes (keys "bodies", "effects",
        "integrator", "output"); name labels the library's messages."""
        return cls(json.dumps(_json_ready(description, name, "")).encode(), name,
                   base_directory)

    def _load(self):
        handle = ctypes.c_void_p()
        run = _native.RunDef()
        error = _native.Error()
        status = lib.tb_scene_load_string(self._text, self._name.encode(),
                                          self._base.encode() if self._base else None,
                                          ctypes.byref(handle), ctypes.byref(run),
                                          ctypes.byref(error))
        if status != 0:
            raise failure(status, error.message.decode())
        return handle, run

    def _at_start(self, read):
        handle, _ = self._load()
        try:
            return read(handle, lib.tb_scene_states(handle))
        finally:
            lib.tb_scene_destroy(handle)

    def joint_reaction(self, joint: int) -> tuple:
        """(force (3,) N, torque (3,) N m): what joint `joint` (an index, in the order of the
        file's "joints") puts on its first body at the start, world frame, the torque about
        the anchor (tb_scene_joint_reaction). Simulation.joint_reaction gives it as the
        simulation goes. TumbleValueError (OUT_OF_RANGE) for a joint the scene has not."""
        return self._at_start(lambda handle, y: _joints.reaction(handle, y, joint))

    def joint_error(self, joint: int) -> tuple:
        """(position error, velocity error) of the start on joint `joint`: the largest of its
        rows, m (or rad, as the sine of an angle) and m/s (rad/s) (tb_scene_joint_error)."""
        return self._at_start(lambda handle, y: _joints.error(handle, y, joint))

    def joint_broken(self, joint: int) -> bool:
        """Whether joint `joint` is broken at the start: never (tb_scene_joint_broken)."""
        return self._at_start(lambda handle, y: _joints.broken(handle, joint))

    def joint_axial(self, joint: int) -> tuple:
        """(coordinate rad or m, motor and stop loads N m or N) of hinge or slider `joint` at
        the start (tb_scene_joint_axial; Simulation.joint_axial tells more)."""
        return self._at_start(lambda handle, y: _joints.axial(handle, y, joint))

    def _impact(self, impact) -> dict:
        """A tb_impact as a dict, bodies by name ("ground" for a ground plane)."""
        def name(body):
            return "ground" if body == ctypes.c_size_t(-1).value else self.body_names[body]
        return {"t": impact.t, "body_a": name(impact.body_a), "body_b": name(impact.body_b),
                "speed": impact.speed, "duration": impact.duration, "steps": impact.steps}

    def run(self, method: Optional[str] = None, dt: Optional[float] = None,
            rtol: Optional[float] = None, atol: Optional[float] = None,
            fps: Optional[float] = None, duration: Optional[float] = None,
            on_frame: Optional[Callable[[int, float, np.ndarray], None]] = None,
            threads: Optional[int] = None, max_steps: Optional[int] = None,
            sleeping: Optional[bool] = None, events: bool = False,
            on_event: Optional[Callable[[dict], None]] = None,
            hit_speed: float = 0.0, joint_reactions: bool = False,
            project_joints: bool = False) -> "Frames":
        """Simulates the scene from its initial state for `duration` seconds (the file's settings
        unless given here: method "euler", "midpoint", "rk4", "rosenbrock", "cvode-adams",
        "cvode-bdf" or "ark-imex"; dt in s for the fixed-step methods, rtol and atol for the
        adaptive ones, frames per second fps) and returns
        every frame (t = k / fps, k = 0, 1, ...) as Frames. The whole run is one library call
        (tb_scene_run) that fills each frame in one more (tb_scene_frame_values); Python runs
        only between frames, where on_frame(k, t, values) is called if given (values: the frame's
        (bodies, 13) array, read-only). An option the method does not read is refused
        (ValueError). threads (fixed-step methods): how many threads share each step of a
        scene whose bodies do not interact (0: one per processor; default 1); the frames are
        the same bits for any count. max_steps: the steps allowed from one frame to the next,
        every method (the scene file's, default 100000). sleeping: whether islands of resting
        bodies sleep (default: the file's "sleeping", itself true by default;
        tb_scene_set_sleeping); stats["asleep"] says how many bodies were asleep at the end.
        stats["unresolved_impacts"]: how many impacts the fixed step was too long to resolve
        (tb_scene_unresolved_impacts: 0 where the step resolves every impact the scene can make,
        and under the adaptive methods), and stats["fastest_unresolved_impact"] the one that
        closed fastest (a dict: t in s, body_a, body_b names, speed in m/s, duration in s, steps)
        or None.
        events: keep the contact events (docs/events.md) in frames.events; on_event(event) is
        called with each as it happens (a dict of EVENT_DTYPE's fields), at a step boundary:
        an exception from it stops nothing, and is raised when the run ends. hit_speed (m/s):
        hits closing slower are left out (begins and ends never). joint_reactions: keep each
        joint's reaction on its first body at every frame in frames.joint_force, joint_torque
        and joint_broken (tb_scene_joint_reaction: a derivative evaluation a joint a frame).
        project_joints: project the start onto the joints first (positions, then velocities, to
        1e-12: tb_scene_project_joints, the CLI's --project-joints; TumbleError SOLVER_FAILED if
        it cannot). Raises TumbleError if the integrator refuses the settings or the run fails;
        a KeyboardInterrupt (Ctrl-C, seen at the next frame) or an exception from on_frame stops
        the run, and the frames made so far are on the exception's `frames` attribute."""
        for name, fn in (("on_frame", on_frame), ("on_event", on_event)):
            if fn is not None and not callable(fn):  # before the run, not at its first frame
                raise TypeError(f"{name} must be a function or None, got {type(fn).__name__}")
        handle, run = self._load()
        asleep, impacts = ctypes.c_size_t(), _native.UnresolvedImpacts()
        try:
            apply_settings(run, method, dt, rtol, atol, fps, duration, threads, max_steps)
            if project_joints:
                _joints.project(handle)
            if sleeping is not None:
                lib.tb_scene_set_sleeping(handle, bool(sleeping))
            recorder = _Recorder(handle, run, self.masses, on_frame,
                                 self.joint_count if joint_reactions else 0)
            listener = _events.Listener(handle, self.body_names, hit_speed, on_event) \
                if events or on_event is not None else None
            stats, error = _native.IntegratorStats(), _native.Error()
            with deferred_interrupt() as recorder.interrupt:
                status = lib.tb_scene_run(handle, ctypes.byref(run), recorder.callback, None,
                                          ctypes.byref(stats), ctypes.byref(error))
            lib.tb_scene_asleep_count(handle, ctypes.byref(asleep))
            lib.tb_scene_unresolved_impacts(handle, ctypes.byref(impacts))
        finally:
            lib.tb_scene_destroy(handle)
        frames = recorder.frames(self, stats)
        frames.stats["asleep"] = asleep.value
        frames.stats["unresolved_impacts"] = impacts.count
        frames.stats["fastest_unresolved_impact"] = \
            self._impact(impacts.fastest) if impacts.count > 0 else None
        if listener is not None:
            frames.events = listener.array() if events else None
            if recorder.failure is None and listener.failure is not None:
                recorder.failure = listener.failure
        if recorder.failure is None and recorder.interrupt.pending and status == 0:
            recorder.failure = KeyboardInterrupt()  # came after the last frame
        if recorder.failure is not None:
            recorder.failure.frames = frames
            raise recorder.failure
        if status != 0:
            failed = settings_failure(status, error.message.decode())
            failed.frames = frames
            raise failed
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
                energy_error=result.energy_error if ok else None,
                cpu_ms=1e3 * result.cpu_seconds, steps=result.steps,
                derivatives=result.derivative_evals,
                status=lib.tb_status_name(result.status).decode(),
                note=None if ok else result.detail.decode())


def _accuracy(self, target_error: float = 1e-3, sweep=ACCURACY_SWEEP) -> tuple:
    """Runs the scene with each integrator setting of `sweep` against cvode-bdf at rtol 1e-11
    (RK4 at an eighth of the default step where BDF fails; frames up to the horizon where two
    references agree to 1e-4 m: the library's tb_scene_accuracy_sweep, as `tumble accuracy`)
    and returns (rows, best):
    each row a dict with method, setting, error (the largest displacement |dx| + l angle of a
    body's points at its radius of gyration l, m), position_error (m), angle_error (rad),
    energy_error (J, at the last frame),
    cpu_ms, steps, derivatives, status and note (None, or the library's detail saying why the
    setting did not run); best is the cheapest row with error <= target_error, or None.
    Raises TumbleError when the reference run fails, with the library's reason."""
    target_error = number("target_error", target_error)
    if not (target_error > 0 and np.isfinite(target_error)):
        raise ValueError(f"target_error must be a finite number of metres > 0, got "
                         f"{target_error!r}")
    settings = (_native.AccuracySetting * max(len(sweep), 1))()
    for k, (method, setting) in enumerate(sweep):
        settings[k] = _native.AccuracySetting(method_code(method), number("setting", setting))
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
        raise failure(status, error.message.decode())
    rows = [_accuracy_row(results[k]) for k in range(len(sweep))]
    best = lib.tb_accuracy_cheapest(results, len(sweep), target_error)
    return rows, rows[best] if best < len(sweep) else None


Scene.accuracy = _accuracy
