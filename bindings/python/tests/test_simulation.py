"""tumble.Simulation: stepping a scene by hand, its live state in NumPy, changes the library
checks, Python forces, and interrupted runs that keep their frames."""

import os
import signal
import threading

import numpy as np
import pytest

import tumble

G = 9.81


def thrown_ball(z=1.0, vz=5.0):
    return tumble.Scene.from_dict({
        "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "mass": 2.0,
                    "position": [0, 0, z], "velocity": [1, 0, vz]}],
        "effects": [{"type": "gravity"}]})


def test_a_body_moved_into_another_is_refused_and_put_back():
    # F26: the position assigned after the integrator exists is checked as a start is: 0.15 m
    # inside the other ball (10 penetrations allow 8 micrometres) is refused, naming both
    # bodies, and the state stays as it was, bit for bit; apart again they stay at rest.
    ball = {"shape": {"type": "sphere", "radius": 0.1}, "mass": 1.0}
    scene = {"bodies": [dict(ball, name="a", position=[-0.5, 0, 0]),
                        dict(ball, name="b", position=[0.5, 0, 0])],
             "effects": [{"type": "contact"}]}
    for method, setting in (("rk4", {"dt": 0}), ("cvode-bdf", {"rtol": 1e-8})):  # dt 0: default
        sim = tumble.Simulation(tumble.Scene.from_dict(scene), method=method, **setting)
        sim.advance(0.01)
        before = sim.state.copy()
        with pytest.raises(tumble.TumbleValueError) as caught:
            sim.position = [[-0.5, 0, 0], [-0.45, 0, 0]]
        assert '0 ("a") and 1 ("b")' in caught.value.message
        assert np.array_equal(sim.state, before)
        sim.advance(0.02)
        assert np.array_equal(sim.velocity, np.zeros((2, 3)))


def free_ball():
    return {"bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1},
                        "mass": 2.0}]}


@pytest.mark.parametrize("method, setting", [("rk4", {"dt": 1 / 240}),
                                             ("cvode-adams", {"rtol": 1e-8})])
def test_run_from_the_start_gives_scene_runs_frames_bit_for_bit(scenes, method, setting):
    # The same integrator stepped to the same frame times through the same library calls:
    # nothing may differ, not one bit (tb_scene_run vs advance() per frame).
    path = scenes / "dzhanibekov.json"
    simulated = tumble.Simulation(path, method=method, **setting).run(duration=2.0)
    ran = tumble.Scene.from_file(path).run(method=method, duration=2.0, **setting)
    for name in ("t", "position", "orientation", "velocity", "angular_velocity",
                 "kinetic_energy", "angular_momentum"):
        assert np.array_equal(getattr(simulated, name), getattr(ran, name)), name
    assert simulated.stats["steps"] == ran.stats["steps"]


def test_views_are_live_zero_copy_and_follow_the_parabola():
    # RK4 integrates x0 + v0 t - g t^2 / 2 exactly: round-off only (1e-12 m). A view taken
    # before advancing shows the new state: it is the library's array, not a copy.
    sim = tumble.Simulation(thrown_ball(), method="rk4", dt=1 / 240)
    position, momentum = sim.position, sim.momentum
    assert np.shares_memory(position, sim.state)
    sim.advance(0.75)
    t = sim.t
    assert t == 0.75
    np.testing.assert_allclose(position[0], [t, 0, 1 + 5 * t - G * t**2 / 2], atol=1e-12)
    np.testing.assert_allclose(momentum[0], 2.0 * np.array([1, 0, 5 - G * t]), atol=1e-12)
    np.testing.assert_allclose(sim.velocity[0], [1, 0, 5 - G * t], atol=1e-12)


def test_a_builder_makes_a_simulation():
    builder = tumble.SceneBuilder()
    builder.add_body("ball", shape={"type": "sphere", "radius": 0.1}, mass=1.0,
                     velocity=[0, 0, 2])
    sim = tumble.Simulation(builder, method="rk4", dt=0.01)
    sim.advance(1.0)
    assert sim.position[0, 2] == pytest.approx(2.0, abs=1e-12)  # no force: x = v t


def test_step_takes_one_fixed_step():
    sim = tumble.Simulation(thrown_ball(), method="rk4", dt=0.01)
    assert sim.step() == pytest.approx(0.01, abs=1e-15)
    sim.step(), sim.step()
    assert sim.t == pytest.approx(0.03, abs=1e-15)
    assert sim.stats["steps"] == 3


def test_views_are_read_only_and_changes_go_through_the_library():
    sim = tumble.Simulation(thrown_ball(), method="rk4", dt=1 / 240)
    with pytest.raises(ValueError, match="read-only"):
        sim.position[0, 2] = 3.0
    # dropped from rest at 5 m: z = 5 - g t^2 / 2 (RK4 exact)
    sim.position = [[0, 0, 5]]
    sim.set_velocity("ball", velocity=[0, 0, 0])
    sim.advance(0.5)
    np.testing.assert_allclose(sim.position[0], [0, 0, 5 - G * 0.25 / 2], atol=1e-12)


def test_a_changed_state_restarts_cvode_from_it():
    # Under CVODE the new velocity must be what the next steps start from (the integrator is
    # told and restarts): z(t1 + s) = z1 + 3 s - g s^2 / 2, to rtol 1e-10 (1e-8 m).
    sim = tumble.Simulation(thrown_ball(), method="cvode-adams", rtol=1e-10)
    sim.advance(0.4)
    z1 = sim.position[0, 2]
    sim.set_velocity(0, velocity=[0, 0, 3])
    sim.advance(0.9)
    assert sim.position[0, 2] == pytest.approx(z1 + 3 * 0.5 - G * 0.25 / 2, abs=1e-8)
    assert sim.position[0, 0] == pytest.approx(0.4, abs=1e-8)


def test_a_refused_change_changes_nothing():
    sim = tumble.Simulation(thrown_ball(), method="rk4", dt=1 / 240)
    sim.advance(0.1)
    before = sim.state.copy()
    with pytest.raises(tumble.TumbleError) as caught:
        sim.quaternion = [[2, 0, 0, 0]]  # not a unit quaternion
    assert isinstance(caught.value, ValueError)
    assert "body 0 (ball)" in caught.value.message
    with pytest.raises(tumble.TumbleValueError):
        sim.set_state(0, position=[0, np.nan, 0])
    with pytest.raises(ValueError, match="shape"):
        sim.momentum = np.zeros((2, 3))
    with pytest.raises(TypeError):
        sim.position = "up"
    with pytest.raises(TypeError):
        sim.set_velocity(0, velocity=["a", "b", "c"])
    assert np.array_equal(sim.state, before)
    assert sim.t == pytest.approx(0.1)


def test_bad_arguments_follow_pythons_conventions():
    with pytest.raises(ValueError, match="rtol applies to adaptive"):
        tumble.Simulation(thrown_ball(), method="rk4", rtol=1e-6)
    with pytest.raises(ValueError, match="dt applies to fixed-step"):
        tumble.Simulation(thrown_ball(), method="cvode-bdf", dt=0.01)
    with pytest.raises(TypeError):
        tumble.Simulation(42)
    sim = tumble.Simulation(thrown_ball(), method="rk4", dt=1 / 240)
    with pytest.raises(TypeError):
        sim.advance("soon")
    sim.advance(0.5)
    with pytest.raises(tumble.TumbleError) as caught:
        sim.advance(0.25)  # back in time: the library refuses
    assert "0.25" in caught.value.message
    with pytest.raises(tumble.TumbleError) as caught:
        sim.body("nobody")
    assert caught.value.status == "OUT_OF_RANGE"
    with pytest.raises(IndexError):
        sim.set_state(3, position=[0, 0, 0])


def test_a_python_spring_force_oscillates_at_sqrt_k_over_m():
    # F = -k x at the centre of mass, k = 200 N/m, m = 2 kg: x(t) = 0.1 cos(10 t); RK4 at 1 ms
    # over 1 s: error ~ (h omega)^4 omega t x0 = 1e-5 * ... well under 1e-8 m.
    scene = free_ball()
    scene["bodies"][0]["position"] = [0.1, 0, 0]
    calls = [0]

    def spring(t, state):
        calls[0] += 1
        return -200.0 * state[:, 0:3]

    sim = tumble.Simulation(scene, method="rk4", dt=1e-3, forces=[spring])
    sim.advance(1.0)
    assert sim.position[0, 0] == pytest.approx(0.1 * np.cos(10.0), abs=1e-8)
    assert calls[0] == 4 * 1000  # one call per derivative evaluation


def test_a_python_torque_adds_angular_momentum_linearly():
    # A constant torque tau: L(t) = tau t exactly under any Runge-Kutta method.
    sim = tumble.Simulation(free_ball(), method="rk4", dt=0.01)
    sim.add_force(lambda t, state: (np.zeros((1, 3)), np.array([[0.0, 0.0, 0.3]])))
    sim.advance(2.0)
    np.testing.assert_allclose(sim.angular_momentum[0], [0, 0, 0.6], atol=1e-13)


def test_an_exception_in_a_force_stops_the_step_and_is_raised():
    def failing(t, state):
        if t > 0.5:
            raise RuntimeError("force model broke")
        return np.zeros((1, 3))

    sim = tumble.Simulation(free_ball(), method="rk4", dt=0.01, forces=[failing])
    with pytest.raises(RuntimeError, match="force model broke"):
        sim.advance(1.0)
    assert 0.49 < sim.t <= 0.51  # the last good step
    with pytest.raises(ValueError, match=r"shape \(1, 3\)"):
        tumble.Simulation(free_ball(), method="rk4", dt=0.01,
                          forces=[lambda t, s: np.zeros(3)]).advance(0.1)


def test_keyboard_interrupt_from_a_frame_callback_keeps_the_frames():
    def interrupt(k, t, values):
        if k == 10:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt) as caught:
        thrown_ball().run(method="rk4", dt=1 / 240, fps=60, duration=2.0, on_frame=interrupt)
    frames = caught.value.frames
    assert len(frames.t) == 11
    np.testing.assert_allclose(frames.t, np.arange(11) / 60, rtol=0, atol=1e-15)
    t = frames.t
    np.testing.assert_allclose(frames.position[:, 0, 2], 1 + 5 * t - G * t**2 / 2, atol=1e-12)

    sim = tumble.Simulation(thrown_ball(), method="rk4", dt=1 / 240)
    with pytest.raises(KeyboardInterrupt) as caught:
        sim.run(duration=2.0, fps=60, on_frame=interrupt)
    assert len(caught.value.frames.t) == 11


@pytest.fixture
def sigint_raises():
    # A process started in the background by a non-interactive shell inherits SIGINT ignored,
    # and Python then installs no KeyboardInterrupt handler: these tests set Python's own.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_ctrl_c_during_a_long_run_keeps_the_frames_so_far(sigint_raises):
    # SIGINT from another thread while the main thread is in tb_scene_run: Python's handler
    # runs at the next frame callback, the run stops, and the frames so far are kept.
    scene = tumble.Scene.from_dict({
        "bodies": [{"name": f"b{i}", "shape": {"type": "box", "size": [0.1, 0.2, 0.4]},
                    "density": 700, "position": [float(i), 0, 0],
                    "angular_velocity": [0.3, 5.0, 0.2]} for i in range(300)]})
    started = threading.Event()
    timer = threading.Thread(target=lambda: (started.wait(), __import__("time").sleep(0.2),
                                             os.kill(os.getpid(), signal.SIGINT)))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as caught:
            scene.run(method="rk4", dt=1e-3, fps=60, duration=60.0,
                      on_frame=lambda k, t, v: started.set())
    finally:
        timer.join()
    frames = caught.value.frames
    assert 1 < len(frames.t) < 3601
    np.testing.assert_allclose(frames.t, np.arange(len(frames.t)) / 60, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(frames.orientation, axis=2), 1.0, atol=1e-12)


def test_ctrl_c_stops_an_advance_at_the_next_python_force(sigint_raises):
    # With a Python force the library calls back at every derivative: Ctrl-C stops the step
    # there (the state stays at the last good step) instead of after 1e5 steps.
    sim = tumble.Simulation(free_ball(), method="rk4", dt=1e-3,
                            forces=[lambda t, state: np.zeros((1, 3))])
    timer = threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.advance(99.0)
    finally:
        timer.cancel()
    assert 0 < sim.t < 99.0
    sim.advance(sim.t + 0.01)  # and it goes on from there


def test_a_view_keeps_the_simulation_alive(scenes):
    # The views point into memory the library owns: the last reference to a view, not to the
    # Simulation, decides when it is freed (else reading it would read freed memory).
    import gc
    position = tumble.Simulation(scenes / "tumbling_box.json").position
    gc.collect()
    np.testing.assert_array_equal(position, [[0.0, 0.0, 1.0]])
    assert position.base is not None


def test_reset_goes_back_to_the_start_bit_for_bit(scenes):
    # A scene with ground contact: the state includes the friction states beyond 13 per body.
    sim = tumble.Simulation(scenes / "sliding_block.json")
    start = sim._y.copy()
    first = sim.run(duration=0.5)
    sim.reset()
    assert sim.t == 0.0 and np.array_equal(sim._y, start)
    again = sim.run(duration=0.5)
    assert np.array_equal(first.position, again.position)


def test_reset_runs_a_scene_with_friction_slots_again_as_the_first(sliding_boxes):
    # Boxes sliding and coming to rest on each other and on the ground hold slots of the friction
    # pools, whose map is kept beside the state: reset() starts it again (tb_integrator_reset to
    # an earlier time), so the run again is the first, the anchors' states too. Before, the map
    # was the first run's, and CVODE BDF ended elsewhere (tests/test_run_again.c in C).
    b = sliding_boxes()
    sim = tumble.Simulation(b.build(method="cvode-bdf", rtol=1e-4, fps=50, duration=0.08))
    first = sim.run()
    end = sim._y.copy()
    sim.reset()
    again = sim.run()
    assert np.array_equal(end, sim._y)
    assert np.array_equal(first.position, again.position)


def test_threads_share_a_step_and_change_no_bit():
    # The library shares the chunks of a step of bodies that do not interact among threads,
    # the same chunks for any count (include/tumble/ode.h): every bit must agree.
    scene = tumble.Scene.from_dict({
        "bodies": [{"name": f"b{i}", "shape": {"type": "box", "size": [0.1, 0.2, 0.4]},
                    "density": 700, "position": [float(i), 0, 0],
                    "angular_velocity": [0.3, 5.0 + 0.01 * i, 0.2]} for i in range(600)],
        "effects": [{"type": "gravity"}]})
    one = scene.run(method="rk4", dt=1 / 240, duration=0.5, threads=1)
    two = scene.run(method="rk4", dt=1 / 240, duration=0.5, threads=2)
    assert np.array_equal(one.orientation, two.orientation)
    assert np.array_equal(one.position, two.position)
    sim = tumble.Simulation(scene, method="rk4", dt=1 / 240, threads=0)
    assert np.array_equal(sim.run(duration=0.5).angular_velocity, one.angular_velocity)
    with pytest.raises(ValueError, match="threads applies to fixed-step"):
        scene.run(method="cvode-adams", threads=2)
    with pytest.raises(TypeError):
        scene.run(threads=1.5)
    with pytest.raises(ValueError, match="from 0 to"):
        scene.run(threads=-1)


def test_a_static_table_has_no_state_row_and_carries_a_ball():
    # A static body (no state, infinite mass): the live state has one row per dynamic body, in
    # dynamic_bodies' order; frames and frame_values have a row for every body. The ball
    # dropped 1 cm onto the table rests with its centre sunk by the contact's static
    # deflection M g / k = penetration (1 mm), to 2 % (its bounce has died out after 1 s).
    scene = tumble.Scene.from_dict({
        "bodies": [{"name": "table", "motion": "static",
                    "shape": {"type": "box", "size": [1.2, 0.8, 0.75]}, "position": [0, 0, 0.375]},
                   {"name": "ball", "shape": {"type": "sphere", "radius": 0.05}, "mass": 1.0,
                    "position": [0.1, 0, 0.81]}],
        "effects": [{"type": "gravity"},
                    {"type": "contact", "penetration": 1e-3, "presliding": 1e-4}]})
    sim = tumble.Simulation(scene, method="rk4", dt=0)
    assert sim.dynamic_bodies == [1]
    assert sim.state.shape == (1, 13)
    sim.advance(1.0)
    assert abs(sim.position[0, 2] - (0.75 + 0.05 - 1e-3)) < 0.02 * 1e-3
    values = sim.frame_values()
    assert values.shape == (2, 13)
    assert np.array_equal(values[0, 0:7], [0, 0, 0.375, 1, 0, 0, 0])
    with pytest.raises(tumble.TumbleValueError) as caught:
        sim.set_state("table", position=[0, 0, 1])
    assert '"table"' in caught.value.message and "static" in caught.value.message
    frames = scene.run(method="rk4", dt=0)
    assert frames.position.shape[1] == 2
    assert np.all(frames.position[:, 0, 2] == 0.375)
