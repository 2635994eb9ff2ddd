"""Unresolved impacts in a run's stats (tb_scene_unresolved_impacts): head_on_balls' one impact
(1 kg at 2 m/s on 3 kg at rest, 0.4 m apart: it touches at t = 0.2 s at 2 m/s, pushing for
0.78 ms) is counted at rosenbrock's 1/240 s and named; at RK4's default step none is."""

import pytest

import tumble


def test_a_step_too_long_for_the_impact_counts_it(scenes):
    frames = tumble.Scene.from_file(scenes / "head_on_balls.json").run(
        method="rosenbrock", dt=1 / 240, duration=0.5)
    assert frames.stats["unresolved_impacts"] == 1
    impact = frames.stats["fastest_unresolved_impact"]
    assert (impact["body_a"], impact["body_b"]) == ("light", "heavy")
    assert impact["t"] == pytest.approx(0.2, abs=1e-9)  # free motion: the cubic is exact
    assert impact["speed"] == pytest.approx(2.0, abs=1e-9)
    assert impact["steps"] == pytest.approx(impact["duration"] * 240, rel=1e-12)
    assert impact["steps"] < 1


def test_a_resolving_step_counts_none(scenes):
    frames = tumble.Scene.from_file(scenes / "head_on_balls.json").run(duration=0.3)
    assert frames.stats["unresolved_impacts"] == 0
    assert frames.stats["fastest_unresolved_impact"] is None
