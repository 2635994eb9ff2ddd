"""Contact events through the bindings (docs/events.md, docs/python.md): a ball dropped on the
ground hits at the free-fall time and speed; on_event sees what frames.events keeps; hit_speed
filters hits; a bad threshold is refused."""

import math

import numpy as np
import pytest

import tumble


def dropped_ball(height=0.3, radius=0.05):
    b = tumble.SceneBuilder()
    b.add_body("ball", shape={"type": "sphere", "radius": radius}, mass=0.5,
               position=[0, 0, height])
    b.add_effect("gravity")
    b.add_effect("ground", restitution=0.5)
    return b.build(fps=30, duration=0.6)


@pytest.mark.parametrize("method, settings", [("rk4", {}), ("cvode-adams", {"rtol": 1e-8})])
def test_the_first_hit_is_at_the_free_fall_time_and_speed(method, settings):
    # h = 0.25 m from the ball's lowest point to the ground: t = sqrt(2 h / g), v = sqrt(2 g h).
    # RK4 integrates the fall exactly and the locator carries the free cubic to its zero; CVODE
    # stops on the root; at rtol 1e-8 its error in the fall bounds it (1e-6 s, m/s):
    # tests/test_contact_events_api.c measures both.
    frames = dropped_ball().run(method=method, events=True, **settings)
    g, h = 9.81, 0.25
    events = frames.events
    assert events.dtype == tumble.EVENT_DTYPE
    hit = events[events["kind"] == "hit"][0]
    assert hit["body_a"] == "ball" and hit["body_b"] == "ground"
    assert hit["t"] == pytest.approx(math.sqrt(2 * h / g), abs=1e-6)
    assert hit["speed"] == pytest.approx(math.sqrt(2 * g * h), abs=1e-6)
    np.testing.assert_array_equal(hit["normal"], [0.0, 0.0, -1.0])
    assert np.all(np.diff(events["t"]) >= 0)
    ends = events[events["kind"] == "end"]
    assert len(ends) >= 1 and np.all(ends["impulse"] > 0)


def test_on_event_sees_every_kept_event_and_hit_speed_filters_hits():
    seen = []
    scene = dropped_ball()
    all_events = scene.run(method="rk4", events=True).events
    frames = scene.run(method="rk4", events=True, on_event=seen.append, hit_speed=1.5)
    assert [e["t"] for e in seen] == list(frames.events["t"])
    hits = frames.events[frames.events["kind"] == "hit"]
    assert len(hits) == 1 and hits[0]["speed"] >= 1.5  # the first, at 2.2 m/s; then 1.1 m/s
    assert np.sum(all_events["kind"] == "hit") > 1
    assert np.sum(all_events["kind"] == "begin") == np.sum(frames.events["kind"] == "begin")
    assert scene.run(method="rk4").events is None


def test_a_bad_hit_speed_is_refused():
    # named by the argument the caller gave, not by the C field behind it
    with pytest.raises(tumble.TumbleValueError, match="hit_speed") as refused:
        dropped_ball().run(method="rk4", events=True, hit_speed=-1.0)
    assert "hit_threshold" not in str(refused.value)
    with pytest.raises(tumble.TumbleError, match="hit_speed"):
        dropped_ball().run(method="rk4", events=True, hit_speed=float("nan"))
    with pytest.raises(TypeError):
        dropped_ball().run(method="rk4", events=True, hit_speed="fast")


def test_an_exception_in_on_event_is_raised_after_the_run():
    def boom(event):
        raise RuntimeError("no")

    with pytest.raises(RuntimeError, match="no") as raised:
        dropped_ball().run(method="rk4", on_event=boom)
    assert len(raised.value.frames.t) == 19  # the run went on to its end


def test_a_body_named_ground_beside_a_ground_plane_is_refused():
    # events name a ground plane "ground": a static box of that name beside a plane would read as
    # the plane in every row; the run is refused before it starts, naming the body (as the CLI's
    # --events does). Without a plane the name is the box's alone, and the run goes.
    def scene(plane):
        b = tumble.SceneBuilder()
        b.add_body("ground", motion="static", shape={"type": "box", "size": [2, 2, 0.1]},
                   position=[0, 0, 0.5])
        b.add_body("ball", shape={"type": "sphere", "radius": 0.1}, mass=1, position=[0, 0, 1])
        b.add_effect("gravity").add_effect("contact")
        if plane:
            b.add_effect("ground")
        return b.build(fps=30, duration=0.5)
    with pytest.raises(ValueError, match=r'body 0 is named "ground", the name the events give'):
        scene(True).run(events=True)
    hits = scene(False).run(events=True).events
    assert {"ball", "ground"} == {hits[0]["body_a"], hits[0]["body_b"]}
