"""The same physics checks as the C suite, in miniature, through the bindings."""

import math

import numpy as np
import pytest

import tumble


def ball(**fields):
    return dict(shape={"type": "sphere", "radius": 0.1}, mass=1.0, **fields)


def test_projectile_follows_the_exact_parabola():
    # RK4 is exact on x0 + v0 t + g t^2 / 2: round-off only.
    b = tumble.SceneBuilder()
    b.add_body("ball", **ball(position=[0, 0, 1], velocity=[2, 0, 5]))
    b.add_effect("gravity")
    frames = b.build(fps=30, duration=1.0).run(method="rk4", dt=1 / 240)
    t = frames.t
    assert frames.position.shape == (31, 1, 3)
    np.testing.assert_allclose(frames.position[:, 0, 0], 2 * t, atol=1e-12)
    np.testing.assert_allclose(frames.position[:, 0, 2], 1 + 5 * t - 0.5 * 9.81 * t**2,
                               atol=1e-12)
    energy = frames.kinetic_energy + frames.potential_energy
    np.testing.assert_allclose(energy, np.full_like(energy, energy[0]), rtol=1e-12)


def test_spring_oscillates_at_sqrt_k_over_m():
    # x(t) = 1 + 0.1 cos(10 t) for k = 200 N/m, m = 2 kg; RK4 at 1 ms: 1e-9 m.
    b = tumble.SceneBuilder()
    b.add_body("ball", shape={"type": "sphere", "radius": 0.1}, mass=2.0, position=[1.1, 0, 0])
    b.add_effect("spring", body_a="ball", point_b=[0, 0, 0], stiffness=200, rest_length=1.0)
    frames = b.build(fps=50, duration=3.0).run(method="rk4", dt=1e-3)
    np.testing.assert_allclose(frames.position[:, 0, 0], 1 + 0.1 * np.cos(10 * frames.t),
                               atol=1e-9)


def test_torque_free_body_keeps_L_and_energy_with_cvode():
    # No torque: L is exact; energy within the global bound N rtol of CVODE.
    b = tumble.SceneBuilder()
    b.add_body("top", mass=1.0, inertia=[1, 2, 3], angular_velocity_body=[1.5, 0, 1])
    frames = b.build(fps=24, duration=10.0).run(method="cvode-adams", rtol=1e-8)
    L = frames.angular_momentum
    np.testing.assert_allclose(L, np.broadcast_to(L[0], L.shape), atol=1e-12)
    drift = abs(frames.kinetic_energy[-1] / frames.kinetic_energy[0] - 1)
    assert drift < frames.stats["steps"] * 1e-8
    assert frames.stats["steps"] > 0 and frames.stats["derivative_evals"] >= frames.stats["steps"]
    q = frames.orientation[:, 0]
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-15)


def test_example_scene_block_stops_where_friction_says(scenes):
    # v^2 / (2 mu_k g), Coulomb's: the friction law caps the force at mu N with no build-up
    # lag (docs/effects.md): to 1 mm.
    frames = tumble.Scene.from_file(scenes / "sliding_block.json").run()
    expected = 9 / (2 * 0.4 * 9.81)
    assert frames.position[-1, 0, 0] == pytest.approx(expected, abs=1e-3)
    assert frames.names == ["block"]


def test_runs_are_repeatable():
    scene = tumble.Scene.from_dict({"bodies": [dict(name="b", **ball(angular_velocity=[1, 2, 3]))],
                                    "effects": [{"type": "gravity"}]})
    a, b = scene.run(duration=1), scene.run(duration=1)
    assert np.array_equal(a.position, b.position) and np.array_equal(a.orientation, b.orientation)


def test_accuracy_sweep_finds_a_setting_that_meets_the_budget(scenes):
    # The recommended setting's error is within the budget, errors fall as the setting
    # tightens for RK4 (order 4), and every method of the sweep appears.
    rows, best = tumble.Scene.from_file(scenes / "tumbling_box.json").accuracy(target_error=1e-6)
    assert best is not None and best["error"] <= 1e-6
    rk4 = [r["error"] for r in rows if r["method"] == "rk4"]
    assert rk4[0] > rk4[1] > 0
    assert {r["method"] for r in rows} == set(tumble.METHODS)


def _order(rows, method, coarse, fine):
    """The observed order of convergence between two step rates of a method: log of the error
    ratio over log of the step ratio."""
    error = {r["setting"]: r["error"] for r in rows if r["method"] == method}
    return math.log(error[coarse] / error[fine]) / math.log(fine / coarse)


def test_accuracy_errors_converge_at_each_methods_order(scenes):
    # The sweep runs in the library (tb_scene_accuracy_sweep), the same function `tumble
    # accuracy` calls. A box thrown under gravity: its centre's parabola is exact for every
    # method, so the error is the rotation's, and it must fall as h^p with the method's order
    # p: Euler 1, midpoint 2, RK4 4 (within 0.3: the step rates are 4x apart, and at the
    # coarser one the error is not yet purely the leading term).
    rows, _ = tumble.Scene.from_file(scenes / "tumbling_box.json").accuracy()
    assert abs(_order(rows, "euler", 1000, 4000) - 1) < 0.3
    assert abs(_order(rows, "midpoint", 240, 1000) - 2) < 0.3
    assert abs(_order(rows, "rk4", 60, 240) - 4) < 0.3
    assert [(r["method"], r["setting"]) for r in rows] == list(tumble.ACCURACY_SWEEP)


def test_accuracy_rows_run_as_fresh_runs_do(sliding_boxes):
    # Each row of the sweep runs from the scene's start after the reference runs and the rows
    # before it: on boxes that hold friction slots, a row takes the steps and evaluations of a
    # run of its own from a new scene (the library starts the slot map again at every run;
    # before, the rows ran on the map the reference left: 796 BDF steps where a run takes 810).
    b = sliding_boxes(side=False)
    scene = b.build(fps=50, duration=0.08)
    sweep = [("cvode-bdf", 1e-4), ("cvode-adams", 1e-4)]
    rows, _ = scene.accuracy(sweep=sweep)
    for row, (method, rtol) in zip(rows, sweep):
        stats = scene.run(method=method, rtol=rtol).stats
        assert row["status"] == "OK"
        assert (row["steps"], row["derivatives"]) == (stats["steps"], stats["derivative_evals"])


def test_accuracy_names_the_reason_when_the_reference_fails():
    # A spring of 1e300 N/m: CVODE's corrector cannot converge; the library's detail (CVODE's
    # flag) arrives, not "the reference run failed".
    scene = tumble.Scene.from_dict({
        "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1,
                    "position": [1.1, 0, 0]}],
        "effects": [{"type": "spring", "body_a": "ball", "point_b": [0, 0, 0],
                     "stiffness": 1e300, "rest_length": 1}],
        "output": {"fps": 10, "duration": 1}})
    with pytest.raises(tumble.TumbleError, match=r"reference run \(cvode-bdf at rtol 1e-11\) "
                                                 r"failed: CVODE"):
        scene.accuracy()


def test_accuracy_reports_a_refused_setting_with_the_librarys_reason():
    # A stiff spring (k/m = 1e6, omega = 1000 rad/s): Euler at 240 steps/s (h omega = 4.2) is
    # beyond every explicit method's stability limit and refused; BDF runs.
    scene = tumble.Scene.from_dict({
        "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1,
                    "position": [1.01, 0, 0]}],
        "effects": [{"type": "spring", "body_a": "ball", "point_b": [0, 0, 0],
                     "stiffness": 1e6, "rest_length": 1}],
        "output": {"fps": 10, "duration": 0.2}})
    rows, _ = scene.accuracy(sweep=[("euler", 240), ("cvode-bdf", 1e-6)])
    assert rows[0]["status"] == "UNSTABLE_STEP" and "stability limit" in rows[0]["note"]
    assert rows[1]["status"] == "OK" and rows[1]["note"] is None
