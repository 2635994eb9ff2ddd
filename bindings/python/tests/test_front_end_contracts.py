"""What the bindings promise at their edges (docs/robustness.md F55-F64, F121-F123, F128): read-only views stay
read-only, an ensemble returns a failed item in its place, counts a C int or long cannot hold
are refused, a run's frames are bounded before anything is allocated, every way of naming a
scene works or says why not, and the step budget is every method's and can be raised."""

import json
import pathlib

import numpy as np
import pytest

import tumble

G = 9.81


def ball(**integrator):
    description = {"bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1},
                               "mass": 2.0, "position": [0, 0, 1], "velocity": [1, 0, 5]}],
                   "effects": [{"type": "gravity"}],
                   "output": {"fps": 10, "duration": 0.2}}
    if integrator:
        description["integrator"] = integrator
    return description


# --- read-only views ---------------------------------------------------------------------------

def test_the_state_views_cannot_be_made_writable():
    # Before: the views were flagged read-only over the library's writable buffer, and
    # flags.writeable = True succeeded, so a write went round the library's checks.
    sim = tumble.Simulation(ball(), method="rk4", dt=0.01)
    before = sim.state.copy()
    for view in (sim.state, sim.position, sim.quaternion, sim.momentum, sim.angular_momentum):
        with pytest.raises(ValueError):
            view.flags.writeable = True
        with pytest.raises(ValueError):
            view[...] = 0.0
    assert np.array_equal(sim.state, before)


def test_a_force_and_a_frame_callback_see_read_only_arrays():
    seen = []

    def force(t, state):
        try:
            state.flags.writeable = True
            seen.append("force: writable")
        except ValueError:
            seen.append("force: read-only")
        return np.zeros((1, 3))

    def on_frame(k, t, values):
        try:
            values.flags.writeable = True
            seen.append("frame: writable")
        except ValueError:
            seen.append("frame: read-only")

    sim = tumble.Simulation(ball(), method="rk4", dt=0.01, forces=[force])
    sim.advance(0.01)
    tumble.Scene.from_dict(ball()).run(method="rk4", dt=0.01, on_frame=on_frame)
    assert set(seen) == {"force: read-only", "frame: read-only"}


# --- ensembles ---------------------------------------------------------------------------------

def test_run_many_returns_an_item_whose_scene_does_not_load_in_its_place(tmp_path):
    # Before: errors="return" raised for an item whose scene failed to load.
    missing = tmp_path / "missing.json"
    bad = {"bodies": [{"name": "a", "mass": -1, "inertia": [1, 1, 1]}]}
    items = [ball(), str(missing), bad, (ball(), {"dt": "fast"})]
    results = tumble.run_many(items, method="rk4", dt=0.01, errors="return", workers=2)
    assert isinstance(results[0], tumble.Frames)
    assert isinstance(results[1], FileNotFoundError)
    assert isinstance(results[2], tumble.TumbleError) and results[2].status == "BAD_SCENE"
    assert isinstance(results[3], TypeError)
    with pytest.raises(FileNotFoundError):
        tumble.run_many(items, method="rk4", dt=0.01, workers=2)


# --- counts the C types cannot hold --------------------------------------------------------------

@pytest.mark.parametrize("threads", [2**31, 2**32 + 1, 2**40, -1])
def test_threads_a_c_int_cannot_hold_are_refused(threads):
    # Before: 2**32 + 1 became 1 thread and 2**40 became 0 (one per processor), silently.
    scene = tumble.Scene.from_dict(ball())
    with pytest.raises(ValueError, match=f"threads must be from 0 to {2**31 - 1}, got {threads}"):
        scene.run(method="rk4", dt=0.01, threads=threads)
    with pytest.raises(ValueError, match="threads must be from 0"):
        tumble.Simulation(scene, method="rk4", dt=0.01, threads=threads)
    result = tumble.run_many([scene], method="rk4", dt=0.01, threads=threads, errors="return")
    assert isinstance(result[0], ValueError)


@pytest.mark.parametrize("max_steps", [0, -5, 2**63])
def test_a_step_budget_out_of_range_is_refused(max_steps):
    with pytest.raises(ValueError, match="max_steps must be from 1 to"):
        tumble.Scene.from_dict(ball()).run(method="rk4", dt=0.01, max_steps=max_steps)


# --- frames ------------------------------------------------------------------------------------

def test_a_run_too_long_to_keep_is_refused_before_anything_is_allocated():
    # 1e9 frames of one body passed the library's frame count, and the recorder then asked
    # NumPy for 104 GB (MemoryError). The library bounds the body-frames a run keeps (1e8).
    scene = tumble.Scene.from_dict(ball())
    fps, duration = 60.0, 1e9 / 60.0
    for run in (lambda: scene.run(method="rk4", dt=0.01, fps=fps, duration=duration),
                lambda: tumble.Simulation(scene, method="rk4", dt=0.01).run(duration, fps)):
        with pytest.raises(tumble.TumbleValueError, match="TB_RUN_MAX_BODY_FRAMES"):
            run()


# --- scenes named every way ----------------------------------------------------------------------

def test_a_scene_is_made_from_a_path_a_pathlike_or_json_text(tmp_path, scenes):
    # Before: Scene(str) raised ctypes.ArgumentError.
    path = scenes / "tumbling_box.json"
    text = path.read_text()
    made = [tumble.Scene(str(path)), tumble.Scene(pathlib.Path(path)), tumble.Scene(text),
            tumble.Scene(text.encode(), "box"), tumble.Scene.from_file(path)]
    for scene in made:
        assert scene.body_names == made[-1].body_names
        assert scene.masses == made[-1].masses
    for wrong in (42, None, ["{}"]):
        with pytest.raises(TypeError, match="a Scene is made from JSON text"):
            tumble.Scene(wrong)
    with pytest.raises(FileNotFoundError):
        tumble.Scene(str(tmp_path / "nowhere.json"))
    with pytest.raises(tumble.TumbleError) as caught:
        tumble.Scene(json.dumps({"bodies": [{"name": "a", "mass": -1}]}))
    assert caught.value.status == "BAD_SCENE"


@pytest.mark.parametrize("target", [-1.0, 0.0, float("nan"), float("inf")])
def test_an_accuracy_target_that_is_not_a_positive_length_is_refused(target):
    # Before: target_error=-1 ran the whole sweep and found no setting meeting it.
    with pytest.raises(ValueError, match="target_error must be a finite number of metres > 0"):
        tumble.Scene.from_dict(ball()).accuracy(target_error=target)


# --- the step budget ---------------------------------------------------------------------------

def test_a_long_fixed_step_advance_runs_with_a_raised_budget():
    # 2 s at dt = 1e-5 s is 200 000 RK4 steps, past the default budget of 100 000: refused
    # before any step (state unchanged), then run with max_steps from Python or from the scene
    # file, which the loader refused for rk4 before. RK4 integrates the parabola exactly; the
    # round-off of 2e5 steps stays below 1e-8 m.
    sim = tumble.Simulation(ball(), method="rk4", dt=1e-5)
    before = sim.state.copy()
    with pytest.raises(tumble.TumbleError, match="more than max_steps = 100000.*max_steps=N"):
        sim.advance(2.0)
    assert np.array_equal(sim.state, before) and sim.t == 0.0
    for sim in (tumble.Simulation(ball(), method="rk4", dt=1e-5, max_steps=200_001),
                tumble.Simulation(ball(method="rk4", dt=1e-5, max_steps=200_001))):
        assert sim.scene.run_settings["max_steps"] in (100_000, 200_001)
        sim.advance(2.0)
        assert sim.t == 2.0
        np.testing.assert_allclose(sim.position[0], [2.0, 0, 1 + 5 * 2 - G * 4 / 2], atol=1e-8)


@pytest.mark.parametrize("method", tumble.METHODS)
def test_every_method_takes_a_step_budget(method):
    # The method table says max_steps is every method's (tb_method_check_setting). Frames 0.1 s
    # apart at dt 0.01 s are 10 fixed steps: a budget of 8 refuses them before the first frame
    # (the run allows one step of slack at the boundary); 50 runs every method.
    scene = tumble.Scene.from_dict(ball())
    assert scene.run(method=method, max_steps=50).t[-1] == pytest.approx(0.2)
    if method in ("euler", "midpoint", "rk4", "rosenbrock"):
        with pytest.raises(tumble.TumbleError, match="more than max_steps = 8"):
            scene.run(method=method, dt=0.01, max_steps=8)


# --- a refused change changes nothing; a force function's return named (F121, F122) -----------

def test_a_velocity_the_integrator_refuses_is_put_back():
    # Before: tb_scene_set_velocity took 1e308 rad/s, the integrator's restart refused it
    # (UNSTABLE_STEP: the guard's step for such a spin), and the error was raised with the
    # velocity left in the state. A failed call leaves the state as it was, bit for bit.
    sim = tumble.Simulation(ball(), method="rk4", dt=0.01)
    sim.advance(0.05)
    before = sim.state.copy()
    with pytest.raises(tumble.TumbleError, match="UNSTABLE_STEP"):
        sim.set_velocity("ball", angular_velocity=[0, 0, 1e308])
    assert np.array_equal(sim.state, before)
    sim.advance(0.1)  # and the simulation goes on from it: free flight, z = z0 + vz t - g t^2/2
    assert sim.position[0, 2] == pytest.approx(1 + 5 * 0.1 - 0.5 * G * 0.1 ** 2, abs=1e-12)


@pytest.mark.parametrize("returned, error, words", [
    (None, TypeError, "got None"),
    ((np.zeros((1, 3)),) * 3, ValueError, "got a tuple of 3"),
    ((np.zeros((1, 3)),), ValueError, "got a tuple of 1"),
    ({"force": 1.0}, TypeError, "forces must be an array of real numbers, got dict"),
    (np.zeros((1, 3)) + 1j, TypeError, "got an array of complex128"),
    ((np.zeros((1, 3)), "up"), TypeError, "torques must be an array of real numbers, got str"),
])
def test_a_force_function_returning_something_else_is_named(returned, error, words):
    # Before: None was taken as no force, a complex array lost its imaginary part with a
    # warning, and the rest failed with Python's own words ("too many values to unpack").
    sim = tumble.Simulation(ball(), method="rk4", dt=0.01, forces=[lambda t, state: returned])
    before = sim.state.copy()
    with pytest.raises(error, match=words):
        sim.advance(0.05)
    assert np.array_equal(sim.state, before)  # the failed step left the state where it was


@pytest.mark.parametrize("call, error, words", [
    (lambda b: b.add_keyframed_body("lift", [[0, 1]], [[0, 0, 0], [0, 0, 1]]), ValueError,
     r"t must be one time per key \(K,\), got shape \(1, 2\)"),
    (lambda b: b.add_keyframed_body("lift", [0, 1, 2], [[0, 0, 0], [0, 0, 1]]), ValueError,
     r"position must have shape \(3, 3\) for 3 keys"),
    (lambda b: b.add_keyframed_body("lift", [0, 1], [[0, 0], [0, 1]]), ValueError,
     r"position must have shape \(2, 3\)"),
    (lambda b: b.add_keyframed_body("lift", [0, 1], [0, 0, 0], velocity=[[0, 0, 1]] * 3),
     ValueError, r"velocity must have shape \(2, 3\)"),
    (lambda b: b.add_keyframed_body("lift", [], []), ValueError, "at least one key"),
    (lambda b: b.add_keyframed_body("lift", "01", [0, 0, 0]), TypeError,
     "t must be real numbers"),
    (lambda b: b.add_keyframed_body("lift", [0, 1j], [0, 0, 0]), TypeError,
     "t must be real numbers, got an array of complex128"),
    (lambda b: b.set_body_pieces("ball", {"type": "sphere", "radius": 0.1}), TypeError,
     "pieces must be a sequence of shapes"),
    (lambda b: b.set_body_pieces("ball", [{"type": "sphere", "radius": 0.1}, 5]), TypeError,
     r"pieces\[1\] must be a shape"),
])
def test_a_builder_call_of_the_wrong_shape_or_type_is_named(call, error, words):
    # Before: NumPy's broadcasting words ("operands could not be broadcast together with
    # remapped shapes"), "float() argument must be ...", "dictionary update sequence element
    # #0 has length 1", and t = [[0, 1]] read as one key; each now names the argument.
    builder = tumble.SceneBuilder()
    builder.add_body("ball", shape={"type": "sphere", "radius": 0.1}, mass=1.0)
    with pytest.raises(error, match=words):
        call(builder)


def test_a_callback_that_is_not_a_function_is_named_before_the_run():
    # Before: Simulation(forces=f) with f a function failed as "'function' object is not
    # iterable", and Scene.run(on_frame=5) ran up to its first frame to fail as "'int' object is
    # not callable"; both now name the argument, and the run does not start.
    with pytest.raises(TypeError, match="forces must be a list of force functions"):
        tumble.Simulation(ball(), method="rk4", dt=0.01, forces=lambda t, state: np.zeros((1, 3)))
    scene = tumble.Scene.from_dict(ball())
    for name in ("on_frame", "on_event"):
        with pytest.raises(TypeError, match=f"{name} must be a function or None, got int"):
            scene.run(method="rk4", dt=0.01, **{name: 5})
