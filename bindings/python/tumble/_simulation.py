"""An interactive simulation: a scene with its integrator, stepped by the caller, its state
live in NumPy, in the shape of MuJoCo's MjData."""

import ctypes
from typing import Callable, Optional, Sequence, Union

import numpy as np

from . import _joints, _native
from ._core import (_active, apply_settings, as_pointer, deferred_interrupt, failure, lib,
                    number, settings_failure, stats_dict)
from ._builder import SceneBuilder  # noqa: F401 (hints)
from ._scene import Frames, Scene, _Recorder  # noqa: F401 (hints)

Body = Union[int, str]
#: A user force: force(t, state) -> forces, or (forces, torques). state is the (N, 13) state
#: the derivative is evaluated at (read-only; x, q, P, L per body with a state, the rows of
#: Simulation.state, in Simulation.dynamic_bodies' order);
#: forces (N, 3) in N act at each body's centre of mass, torques (N, 3) in N m, both in the
#: world frame. Rows of zeros cost nothing more; anything else (None, a tuple of another
#: length, complex numbers) fails the step with an error naming it.
ForceFunction = Callable[[float, np.ndarray], object]


class Simulation:
    """A scene being simulated, stepped by the caller: the C library's tb_scene with a
    tb_integrator on it (include/tumble/scene.h, ode.h), in the shape of MuJoCo's MjData.

        sim = tumble.Simulation("examples/scenes/dzhanibekov.json", method="rk4", dt=1/1000)
        sim.advance(2.0)                 # to t = 2 s
        sim.angular_velocity[0]          # rad/s, world frame
        sim.set_velocity(0, angular_velocity=[0, 20, 0.1])   # the integrator restarts
        frames = sim.run(duration=1.0)   # 1 s more, every frame, as Scene.run

    Construction: scene is a Scene, a SceneBuilder, a scene-file path or a dict in the
    scene-file format;
    method one of tumble.METHODS ("euler", "midpoint", "rk4", "cvode-adams", "cvode-bdf",
    "rosenbrock", "ark-imex"), dt (s) for the fixed-step methods, rtol and atol for the adaptive
    ones (the scene file's integrator unless given; an option the method does not read is a
    ValueError, as in the CLI); threads
    (fixed-step methods, bodies that do not interact) shares each step among threads, with the
    same bits for any count (0: one per processor; default 1); max_steps (every method) the
    steps one advance() or step() may take (the scene file's, default 100000: advance(5.0) at
    a step of 1e-5 s needs max_steps=500000 or more, else TumbleError TOO_MANY_STEPS before any
    step). A fixed step beyond the scene's stability limit is refused (TumbleValueError,
    UNSTABLE_STEP). project_joints: project the start onto the joints first, positions then
    velocities, to 1e-12 (tb_scene_project_joints; the CLI's --project-joints), TumbleError
    SOLVER_FAILED if it cannot; project_joints(tolerance) does it at any time.

    State (N bodies with a state, the dynamic ones, in the order of dynamic_bodies, their ids:
    every body but the static and keyframed ones, which have no state; world frame, z up, SI
    units). These are live views of the library's own state array, no copies: they change as
    the simulation advances, and they are read-only so that every change goes through the
    library, which checks it and restarts the integrator (assign to the property, or use
    set_state / set_velocity):

        state             (N, 13) per body x[3] q[4] P[3] L[3]
        position          (N, 3) m, centre of mass
        quaternion        (N, 4) unit (w, x, y, z), body (principal) frame -> world
        momentum          (N, 3) kg m/s, P = M v
        angular_momentum  (N, 3) kg m^2/s, L about the body's centre of mass

    Derived read-outs (new arrays): velocity (N, 3) m/s of the centre of mass (P / M);
    angular_velocity (N, 3) rad/s (omega = R I_body^-1 R^T L); frame_values() the shape-frame
    pose and velocities of every body, static and keyframed ones included (bodies, 13), as a
    Frames frame holds them; reaction(body) what the bodies put on a static or keyframed body;
    joint_count, joint_reaction(j), joint_error(j), joint_broken(j), joint_axial(j) the scene's
    joints; set_joint_motor(j, mode, value, max_force) changes a hinge's or slider's motor.

    Stepping releases the GIL while C runs. Ctrl-C raises KeyboardInterrupt when advance() or
    step() returns (at the next derivative evaluation when Python forces act) and at every
    frame of run() (with the frames so far on the exception); an exception raised by a user force stops the step (the
    state stays at the last good step) and is raised again from advance() or step().

    Lifetimes: the views stay valid as long as they are referenced (they keep the simulation
    alive); the library frees the scene when the last reference goes.
    """

    def __init__(self, scene: Union[Scene, "SceneBuilder", str, dict], method: Optional[str] = None,
                 dt: Optional[float] = None, rtol: Optional[float] = None,
                 atol: Optional[float] = None, forces: Sequence[ForceFunction] = (),
                 threads: Optional[int] = None, max_steps: Optional[int] = None,
                 project_joints: bool = False):
        self.scene = Scene.coerce(scene)
        self._handle, run = self.scene._load()
        self._integrator = ctypes.c_void_p()
        self._user_effects = []  # the ctypes callbacks, alive as long as the scene
        self._failure = None
        try:
            apply_settings(run, method, dt, rtol, atol, threads=threads, max_steps=max_steps)
            self._run = run
            self.bodies = lib.tb_scene_body_count(self._handle)
            self._views()
            if (callable(forces) or isinstance(forces, (str, bytes, dict))
                    or not hasattr(forces, "__iter__")):
                raise TypeError(f"forces must be a list of force functions force(t, state), "
                                f"got {type(forces).__name__}")
            for force in forces:
                self._add_user_effect(force)
            if project_joints:  # before the integrator, which keeps its own copy (CVODE)
                _joints.project(self._handle)
            self._create_integrator(0.0)
        except BaseException:
            self._free()
            raise
        self._initial = self._y.copy()

    # --- lifetime ---------------------------------------------------------------------------

    def _views(self):
        n = lib.tb_scene_state_size(self._handle)
        address = ctypes.cast(lib.tb_scene_states(self._handle), ctypes.c_void_p).value
        buffer = (ctypes.c_double * max(n, 1)).from_address(address)
        buffer.simulation = self  # a view keeps the simulation (and so the scene) alive
        self._address = address
        self._y_writable = np.frombuffer(buffer, dtype=np.float64, count=n)
        # the public views stand on a read-only buffer, so that no view of them can be made
        # writable (flags.writeable = True raises): every change goes through the library
        self._y = np.frombuffer(memoryview(buffer).toreadonly(), dtype=np.float64, count=n)
        #: the ids of the bodies the state's rows are (dynamic ones, in slot order)
        self.dynamic_bodies = list(self.scene.dynamic_bodies)
        #: each body's motion: "dynamic", "static" or "keyframed" (Scene.motions)
        self.motions = list(self.scene.motions)
        slots = len(self.dynamic_bodies)
        self._state = self._y[:_native.STATE_SIZE * slots].reshape(slots, _native.STATE_SIZE)
        self._masses = np.array(self.scene.masses)[self.dynamic_bodies]

    def _create_integrator(self, t0):
        if self._integrator:
            lib.tb_integrator_destroy(self._integrator)
            self._integrator = ctypes.c_void_p()
        status = lib.tb_scene_integrator_create(self._handle, ctypes.byref(self._run.integrator),
                                                t0, ctypes.byref(self._integrator))
        if status != 0:
            raise settings_failure(status, lib.tb_scene_detail(self._handle).decode())

    def _free(self):
        if getattr(self, "_integrator", None):
            lib.tb_integrator_destroy(self._integrator)
            self._integrator = ctypes.c_void_p()
        if getattr(self, "_handle", None):
            lib.tb_scene_destroy(self._handle)
            self._handle = None

    def __del__(self):
        try:
            self._free()
        except (AttributeError, TypeError):  # at interpreter exit the module may be gone
            pass

    def __repr__(self):
        return (f"<tumble.Simulation of {self.bodies} bodies at t = {self.t:g} s, "
                f"{self.method}>")

    # --- settings and time ----------------------------------------------------------------

    @property
    def method(self) -> str:
        """The integration method ("rk4", "cvode-adams", ...)."""
        return lib.tb_method_name(self._run.integrator.method).decode()

    @property
    def t(self) -> float:
        """The simulation's time, s."""
        return lib.tb_integrator_time(self._integrator)

    @property
    def stats(self) -> dict:
        """What the integrator has done since it was made (steps, derivative_evals, ...;
        tb_integrator_stats). Adding a force makes a new integrator, and the counts restart."""
        stats = _native.IntegratorStats()
        lib.tb_integrator_get_stats(self._integrator, ctypes.byref(stats))
        return stats_dict(stats)

    @property
    def body_names(self) -> list:
        """The bodies' names; body i of every array is the i-th."""
        return list(self.scene.body_names)

    def body(self, body: Body) -> int:
        """A body's index from its index or its name (TumbleError OUT_OF_RANGE if none)."""
        if isinstance(body, str):
            found = ctypes.c_size_t()
            status = lib.tb_scene_find_body(self._handle, body.encode(), ctypes.byref(found))
            if status != 0:
                raise failure(status, lib.tb_scene_detail(self._handle).decode())
            return found.value
        if isinstance(body, bool) or not isinstance(body, (int, np.integer)):
            raise TypeError(f"a body is an index or a name, got {type(body).__name__}")
        if not 0 <= body < self.bodies:
            raise IndexError(f"body {body}: the scene has {self.bodies} bodies")
        return int(body)

    # --- stepping -------------------------------------------------------------------------

    def _check(self, status, interrupt=None):
        if interrupt is not None and interrupt.pending:
            self._failure = None
            raise KeyboardInterrupt
        if self._failure is not None:
            caught, self._failure = self._failure, None
            raise caught
        if status != 0:
            message = lib.tb_integrator_detail(self._integrator).decode()
            if lib.tb_status_name(status) == b"TOO_MANY_STEPS":
                message += " (Simulation(..., max_steps=N) or the scene file's max_steps)"
            raise failure(status, message)

    def advance(self, t: float) -> None:
        """Advances to time t (s, not before the current time). Fixed-step methods take whole
        steps of dt, the last one shortened to land on t; CVODE steps as its error control
        decides and interpolates to t, so the times asked for do not change its steps. On
        failure (TumbleError naming it and its time) the state is that of the last good step."""
        t = number("t", t)
        with deferred_interrupt() as interrupt:
            status = lib.tb_integrator_advance(self._integrator, t)
        self._check(status, interrupt)

    def step(self) -> float:
        """Takes one step (dt for fixed-step methods, one internal CVODE step); returns the
        new time, s."""
        with deferred_interrupt() as interrupt:
            status = lib.tb_integrator_step(self._integrator)
        self._check(status, interrupt)
        return self.t

    def reset(self) -> None:
        """Back to the scene's initial state at t = 0 (the integrator restarts)."""
        self._y_writable[:] = self._initial
        self._restart(0.0)

    def _restart(self, t):
        status = lib.tb_integrator_reset(self._integrator, t)
        if status != 0:
            raise failure(status, lib.tb_integrator_detail(self._integrator).decode())

    def run(self, duration: Optional[float] = None, fps: Optional[float] = None,
            on_frame: Optional[Callable[[int, float, np.ndarray], None]] = None,
            joint_reactions: bool = False) -> Frames:
        """Advances for `duration` seconds from the current time t0, recording a frame at
        t0 + k / fps for k = 0, 1, ... (the scene file's output settings unless given), and
        returns them as Frames (as Scene.run; from t0 = 0 and the initial state it gives the
        same frames, bit for bit). on_frame(k, t, values) is called after each frame. A
        KeyboardInterrupt (Ctrl-C) or an exception from on_frame or a user force stops the run,
        and the frames so far are on the exception's `frames`. joint_reactions: keep each
        joint's reaction and broken flag at every frame (as Scene.run)."""
        run = _native.RunDef()
        ctypes.memmove(ctypes.byref(run), ctypes.byref(self._run), ctypes.sizeof(run))
        apply_settings(run, fps=fps, duration=duration)
        recorder = _Recorder(self._handle, run, self.scene.masses,
                             joints=self.joint_count if joint_reactions else 0)
        frame_count = len(recorder.t)
        t0 = self.t
        try:
            with deferred_interrupt() as interrupt:
                for k in range(frame_count):
                    t = t0 + k / run.fps
                    if k > 0:
                        self.advance(t)
                    recorder._record(k, t, self._handle)
                    if on_frame is not None:
                        on_frame(k, t, recorder.values[k].copy())
                    if interrupt.pending:
                        raise KeyboardInterrupt
        except BaseException as caught:
            caught.frames = recorder.frames(self.scene, self._stats_struct())
            raise
        return recorder.frames(self.scene, self._stats_struct())

    def _stats_struct(self):
        stats = _native.IntegratorStats()
        lib.tb_integrator_get_stats(self._integrator, ctypes.byref(stats))
        return stats

    # --- the live state -------------------------------------------------------------------

    @property
    def state(self) -> np.ndarray:
        """(N, 13) x[3] q[4] P[3] L[3] per body: a live, read-only view."""
        return self._state

    @property
    def position(self) -> np.ndarray:
        """(N, 3) centre-of-mass positions, m, world frame: a live, read-only view."""
        return self._state[:, 0:3]

    @position.setter
    def position(self, value):
        self._set_part(0, 3, "position", value)

    @property
    def quaternion(self) -> np.ndarray:
        """(N, 4) unit quaternions (w, x, y, z), body (principal) frame -> world: a live,
        read-only view. Assigned ones must be unit to 1e-4 (then normalised)."""
        return self._state[:, 3:7]

    @quaternion.setter
    def quaternion(self, value):
        self._set_part(3, 7, "quaternion", value)

    @property
    def momentum(self) -> np.ndarray:
        """(N, 3) linear momenta P = M v, kg m/s, world frame: a live, read-only view."""
        return self._state[:, 7:10]

    @momentum.setter
    def momentum(self, value):
        self._set_part(7, 10, "momentum", value)

    @property
    def angular_momentum(self) -> np.ndarray:
        """(N, 3) angular momenta about each centre of mass, kg m^2/s, world frame: a live,
        read-only view."""
        return self._state[:, 10:13]

    @angular_momentum.setter
    def angular_momentum(self, value):
        self._set_part(10, 13, "angular_momentum", value)

    @property
    def velocity(self) -> np.ndarray:
        """(N, 3) centre-of-mass velocities v = P / M, m/s, world frame (a new array)."""
        return self.momentum / self._masses[:, None]

    @property
    def angular_velocity(self) -> np.ndarray:
        """(N, 3) angular velocities omega = R I_body^-1 R^T L, rad/s, world frame (a new
        array, from the library's read-out)."""
        return self.frame_values()[:, 10:13]

    def frame_values(self) -> np.ndarray:
        """(N, 13) per body: shape-frame origin (m), shape -> world quaternion, the origin's
        velocity (m/s), angular velocity (rad/s), all world frame: what a Frames frame holds
        (tb_scene_frame_values)."""
        values = np.empty((self.bodies, _native.FRAME_VALUES))
        self._check(lib.tb_scene_frame_values(self._handle, as_pointer(self._y),
                                              as_pointer(values)))
        return values

    def reaction(self, body: Body) -> tuple:
        """(force (3,) N, torque (3,) N m): what the other bodies put on a static or keyframed
        body through the scene's effects (contact, springs) at the current state and time,
        world frame, the torque about its shape-frame origin: what holding it on its path
        costs (tb_scene_body_reaction). A dynamic body is refused (TumbleValueError)."""
        i = self.body(body)
        force, torque = np.empty(3), np.empty(3)
        status = lib.tb_scene_body_reaction(self._handle, as_pointer(self._y), i,
                                            as_pointer(force), as_pointer(torque))
        if status != 0:
            raise failure(status, lib.tb_scene_detail(self._handle).decode())
        return force, torque

    # --- joints (include/tumble/joints.h) -------------------------------------------------

    @property
    def joint_count(self) -> int:
        """How many joints the scene has (its "joints"; Scene.joints describes them)."""
        return _joints.count(self._handle)

    def joint_reaction(self, joint: int) -> tuple:
        """(force (3,) N, torque (3,) N m): what joint `joint` (an index, in the order of the
        scene's "joints") puts on its first body at the current state, world frame, the torque
        about its anchor; the second body gets the opposite; 0 once broken
        (tb_scene_joint_reaction). TumbleValueError (OUT_OF_RANGE) for a joint the scene has
        not."""
        return _joints.reaction(self._handle, self._y, joint)

    def joint_error(self, joint: int) -> tuple:
        """(position error, velocity error): how far the current state is off joint `joint`,
        the largest of its rows, m (or rad, as the sine of an angle) and m/s (rad/s)
        (tb_scene_joint_error)."""
        return _joints.error(self._handle, self._y, joint)

    def joint_broken(self, joint: int) -> bool:
        """Whether joint `joint` has broken in the run so far (tb_scene_joint_broken)."""
        return _joints.broken(self._handle, joint)

    def joint_axial(self, joint: int) -> tuple:
        """(coordinate, motor, stop) of hinge or slider `joint` at the current state
        (tb_scene_joint_axial): its angle about the axis, rad, or travel along it, m, from the
        pose when the joint was made; the motor's and the stop's load on that axis, N m for a
        hinge, N for a slider, positive driving the coordinate up on the first body, each 0
        when not acting (a motor pushing into a stop that holds pushes at its cap, the stop
        taking it). TumbleValueError (INVALID_ARGUMENT) for a ball or fixed joint."""
        return _joints.axial(self._handle, self._y, joint)

    def set_joint_motor(self, joint: int, mode: str, value: float = 0.0,
                        max_force: Optional[float] = None) -> None:
        """Sets hinge or slider `joint`'s motor from the current time on
        (tb_scene_set_joint_motor): mode "off", "velocity" (value the speed, rad/s or m/s,
        the scene file's motor "speed") or "position" (value the target, rad or m from the pose
        when the joint was made, its "target"), at most max_force (N m for a hinge, N for a
        slider, > 0; None keeps the joint's cap). The integrator goes on stepping (CVODE
        restarts itself); reset() puts back the state, not the motor. A refusal raises
        TumbleValueError with the library's detail naming the field (motor_max_force,
        motor_speed, motor_target), TumbleError UNSUPPORTED for a soft joint made without limits
        or a motor, ValueError for an unknown mode; nothing changes."""
        _joints.set_motor(self._handle, joint, mode, value, max_force)

    def project_joints(self, tolerance: float = 0.0) -> float:
        """Projects the current state onto the joints, positions by the mass-weighted least
        change, then velocities, as after every step (tb_scene_project_joints), and restarts
        the integrator from it; returns the largest joint error left (m or rad, m/s or rad/s).
        tolerance: the largest error accepted, 0 for the library's 1e-12. A state the
        projection cannot bring within it raises TumbleError (SOLVER_FAILED, naming the joint
        and its error) and changes nothing."""
        left = _joints.project(self._handle, tolerance)
        self._restart(self.t)
        return left

    def set_state(self, body: Body, position=None, quaternion=None, momentum=None,
                  angular_momentum=None) -> None:
        """Sets parts of one body's state (the others kept): position (3,) m, quaternion (4,)
        unit (w, x, y, z), momentum (3,) kg m/s, angular_momentum (3,) kg m^2/s, world frame.
        The library checks it (finite, unit quaternion within 1e-4) and changes nothing on
        failure (TumbleValueError); the integrator restarts from it."""
        i = self.body(body)
        new = self._state[self._slot(i)].copy()
        for start, stop, name, value in ((0, 3, "position", position),
                                         (3, 7, "quaternion", quaternion),
                                         (7, 10, "momentum", momentum),
                                         (10, 13, "angular_momentum", angular_momentum)):
            if value is not None:
                new[start:stop] = _vector(name, value, stop - start)
        self._set_states({i: new})

    def set_velocity(self, body: Body, velocity=None, angular_velocity=None) -> None:
        """Sets one body's centre-of-mass velocity (m/s) and/or angular velocity (rad/s), world
        frame, as P = M v and L = I(t) omega at its current orientation
        (tb_scene_set_velocity); the other is kept. The integrator restarts."""
        i = self.body(body)
        slot = self._slot(i)
        v = self.velocity[slot] if velocity is None else _vector("velocity", velocity, 3)
        w = (self.angular_velocity[slot] if angular_velocity is None
             else _vector("angular_velocity", angular_velocity, 3))
        saved = self._y_writable.copy()
        status = lib.tb_scene_set_velocity(self._handle, i, as_pointer(np.ascontiguousarray(v)),
                                           as_pointer(np.ascontiguousarray(w)))
        if status != 0:
            raise failure(status, lib.tb_scene_detail(self._handle).decode())
        try:  # a velocity the integrator refuses to start from (its guard) is put back
            self._restart(self.t)
        except Exception:
            self._y_writable[:] = saved
            raise

    def _set_part(self, start, stop, name, value):
        array = np.asarray(value, dtype=float) if _is_numeric(value) else None
        if array is None:
            raise TypeError(f"{name} must be an array of numbers, got {type(value).__name__}")
        rows = len(self.dynamic_bodies)
        try:
            array = np.broadcast_to(array, (rows, stop - start))
        except ValueError:
            raise ValueError(f"{name} must have shape ({rows}, {stop - start}), got "
                             f"{array.shape}") from None
        new = self._state.copy()
        new[:, start:stop] = array
        self._set_states({i: new[k] for k, i in enumerate(self.dynamic_bodies)})

    def _slot(self, i):
        """Body i's row of the state; a body without a state (static) is refused as the
        library refuses it."""
        if i in self.dynamic_bodies:
            return self.dynamic_bodies.index(i)
        # the library's own refusal, naming the body and its kind (it changes nothing)
        status = lib.tb_scene_set_state(self._handle, i, ctypes.byref(_native.BodyState()))
        raise failure(status, lib.tb_scene_detail(self._handle).decode())

    def _set_states(self, states):
        """Each body's new state through tb_scene_set_state; all or nothing: on a refusal the
        bodies already set are put back bit for bit, and the error names the body. The restart
        checks the new state as a start (two bodies deep inside each other, a body deep in a
        ground plane: refused, naming them, and the state put back)."""
        saved = self._y_writable.copy()
        for i, values in states.items():
            s = _native.BodyState.from_buffer_copy(np.ascontiguousarray(values).tobytes())
            status = lib.tb_scene_set_state(self._handle, i, ctypes.byref(s))
            if status != 0:
                message = lib.tb_scene_detail(self._handle).decode()
                self._y_writable[:] = saved
                raise failure(status, f"body {i} ({self.scene.body_names[i]}): {message}")
        try:
            self._restart(self.t)
        except Exception:
            self._y_writable[:] = saved
            raise

    # --- user forces ----------------------------------------------------------------------

    def add_force(self, force: ForceFunction) -> None:
        """Adds a force computed in Python at every derivative evaluation: force(t, state) ->
        forces (N, 3), or (forces, torques) with torques (N, 3); see ForceFunction. This is
        slow next to the library's own effects: each evaluation calls Python (docs/
        performance.md measures it). Adding one makes a new integrator at the current time
        (CVODE restarts; the statistics count afresh)."""
        self._add_user_effect(force)
        self._create_integrator(self.t)

    def _add_user_effect(self, force):
        if not callable(force):
            raise TypeError(f"a force is a callable force(t, state), got {type(force).__name__}")
        ids, handle = list(self.dynamic_bodies), self._handle
        bodies = len(ids)

        def effect(t, scene, y, dydt, ctx):
            try:
                if _active and _active[-1].pending:
                    raise KeyboardInterrupt
                # read-only for good (a read-only buffer): the force may not change the state
                size = bodies * _native.STATE_SIZE
                buffer = (ctypes.c_double * size).from_address(ctypes.addressof(y.contents))
                state = np.frombuffer(memoryview(buffer).toreadonly(),
                                      dtype=np.float64).reshape(bodies, _native.STATE_SIZE)
                _apply_loads(handle, y, dydt, state, force(t, state), ids)
                return 0
            except BaseException as caught:  # cannot cross C: fail the step, raise after it
                self._failure = caught
                return -1

        callback = _native.USER_EFFECT_FN(effect)
        status = lib.tb_scene_add_user_effect(self._handle, callback, None)
        if status != 0:
            raise failure(status, lib.tb_scene_detail(self._handle).decode())
        self._user_effects.append(callback)


def _apply_loads(handle, y, dydt, state, loads, ids):
    bodies = len(ids)
    if isinstance(loads, tuple) and len(loads) != 2:
        raise ValueError(f"a force function returns forces (N, 3) or a tuple (forces, torques), "
                         f"got a tuple of {len(loads)}")
    forces, torques = loads if isinstance(loads, tuple) else (loads, None)
    if forces is None and not isinstance(loads, tuple):
        raise TypeError("a force function returns forces (N, 3) or a tuple (forces, torques), "
                        "got None")
    for name, array in (("forces", forces), ("torques", torques)):
        if array is None:
            continue
        if not _is_numeric(array):
            kind = (f"an array of {array.dtype}" if isinstance(array, np.ndarray)
                    else type(array).__name__)
            raise TypeError(f"a force function's {name} must be an array of real numbers, got "
                            f"{kind}")
        array = np.ascontiguousarray(array, dtype=float)
        if array.shape != (bodies, 3):
            raise ValueError(f"a force function's {name} must have shape ({bodies}, 3), got "
                             f"{array.shape}")
        for i in np.flatnonzero(np.any(array != 0.0, axis=1)).tolist():
            if name == "forces":
                point = np.ascontiguousarray(state[i, 0:3])
                status = lib.tb_effect_add_force(handle, y, dydt, ids[i], as_pointer(array[i]),
                                                 as_pointer(point))
            else:
                status = lib.tb_effect_add_torque(handle, dydt, ids[i], as_pointer(array[i]))
            if status != 0:
                raise failure(status, lib.tb_scene_detail(handle).decode())


def _is_numeric(value):
    try:
        return np.asarray(value).dtype.kind in "iuf"
    except (TypeError, ValueError):
        return False


def _vector(name, value, length):
    if not _is_numeric(value):
        raise TypeError(f"{name} must be {length} numbers, got {type(value).__name__} {value!r}")
    array = np.asarray(value, dtype=float)
    if array.shape != (length,):
        raise ValueError(f"{name} must have {length} components, got shape {array.shape}")
    return array
