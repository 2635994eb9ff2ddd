"""Static and keyframed bodies from Python: their kinds, their rows in the frames, a box lifted
by a keyframed platform, and the platform's reaction (docs/python.md)."""

import numpy as np
import pytest

import tumble

G = 9.81  # the gravity effect's default, m/s^2
PENETRATION = 1e-5  # the contact's static deflection under a body's own weight, m
BOX_MASS = 500 * 0.2 ** 3  # density times volume, kg
A_MAX = 5.0  # the platform's largest acceleration, m/s^2 (the keys below)

# The platform (top at z = 0 at rest) holds still for 0.2 s, speeds up at 5 m/s^2 to 1 m/s
# (0.1 m in 0.2 s), rises at 1 m/s for 0.5 s, slows at 5 m/s^2 to rest 0.7 m up at t = 1.1 s
# and stays there: cubic keys with their velocities, which reproduce these quadratic and
# linear pieces exactly. Slowing at 5 m/s^2 < g, the box on it never leaves it.
TIMES = [0.0, 0.2, 0.4, 0.9, 1.1]
HEIGHTS = [0.0, 0.0, 0.1, 0.6, 0.7]  # the platform's top, m
SPEEDS = [0.0, 0.0, 1.0, 1.0, 0.0]


def platform_scene(builder=False):
    centre = np.array(HEIGHTS) - 0.05  # a 0.1 m thick slab
    b = tumble.SceneBuilder()
    if builder:
        b.add_keyframed_body("platform", TIMES, [[0, 0, z] for z in centre],
                             velocity=[[0, 0, v] for v in SPEEDS],
                             shape={"type": "box", "size": [1, 1, 0.1]})
    else:  # the scene format's words
        keys = [{"t": t, "position": [0, 0, z], "orientation": [1, 0, 0, 0],
                 "velocity": [0, 0, v]} for t, z, v in zip(TIMES, centre, SPEEDS)]
        b.add_body("platform", motion="keyframed", shape={"type": "box", "size": [1, 1, 0.1]},
                   interpolation="cubic", keys=keys)
    b.add_body("table", motion="static", shape={"type": "box", "size": [0.6, 0.6, 0.4]},
               position=[2, 0, 0.2], orientation=[0.96, 0, 0, 0.28])
    b.add_body("box", shape={"type": "box", "size": [0.2, 0.2, 0.2]}, density=500,
               position=[0, 0, 0.1])
    b.add_effect("gravity")
    b.add_effect("contact", penetration=PENETRATION)
    return b.build(method="cvode-bdf", rtol=1e-8, fps=20, duration=2.0)


def test_body_kinds_are_read_from_the_scene():
    scene = platform_scene()
    assert scene.motions == ["keyframed", "static", "dynamic"]
    sim = tumble.Simulation(scene)
    assert sim.motions == scene.motions
    assert sim.dynamic_bodies == [2]  # the only body with a state row
    assert sim.state.shape == (1, 13)


def test_a_keyframed_platform_lifts_a_box_within_the_static_deflection():
    # The box's centre rides 0.1 m above the platform's top, sunk by the contact's deflection:
    # its weight M (g + a) on the contact of stiffness M g / PENETRATION sinks it by
    # PENETRATION (1 + a / g) in equilibrium, and at most twice that under a step of load (the
    # dynamic amplification of a damped oscillator is at most 2); it never lifts off (sink > 0
    # after the first frame, where it touches at zero depth). At rest again 0.9 s after the
    # platform stops, the sink is the static deflection (10%, the measure).
    frames = platform_scene().run()
    top = frames.position[:, 0, 2] + 0.05
    sink = top + 0.1 - frames.position[:, 2, 2]
    bound = 2 * PENETRATION * (1 + A_MAX / G)
    assert np.all(sink[1:] > 0), sink.min()
    assert np.all(sink <= bound), sink.max()
    assert abs(sink[-1] - PENETRATION) <= 0.1 * PENETRATION
    # the platform's frames are its keys at the key times (frame k at t = k / 20)
    for t, z in zip(TIMES, HEIGHTS):
        k = int(round(t * 20))
        assert frames.t[k] == pytest.approx(t, abs=1e-15)
        assert top[k] == pytest.approx(z, abs=1e-12)
    assert frames.position[-1, 2, 2] == pytest.approx(0.8, abs=bound)


def test_the_builder_makes_the_same_keyframed_body_as_the_scene_format():
    by_hand, built = platform_scene().run(), platform_scene(builder=True).run()
    assert np.array_equal(by_hand.position, built.position)
    assert np.array_equal(by_hand.orientation, built.orientation)


def test_the_reaction_of_a_platform_at_rest_is_the_box_weight():
    # At rest (t = 2 s, 0.9 s after the platform stopped) the box presses the platform down
    # with its weight M g, straight down, and no torque about the platform's centre (the box
    # sits centred); the contact's residual ringing and friction anchors leave less than 1e-6
    # of it (the damped ring decays by e^-(zeta omega t) over 0.9 s, omega = sqrt(g / 1e-5)).
    sim = tumble.Simulation(platform_scene())
    sim.advance(2.0)
    force, torque = sim.reaction("platform")
    weight = BOX_MASS * G
    assert force == pytest.approx([0, 0, -weight], abs=1e-6 * weight)
    assert np.abs(torque).max() <= 1e-6 * weight * 0.1
    assert np.array_equal(sim.reaction("table")[0], np.zeros(3))  # nothing touches it
    with pytest.raises(tumble.TumbleValueError) as caught:
        sim.reaction("box")
    assert '"box"' in caught.value.message and "dynamic" in caught.value.message


def test_a_static_table_has_a_row_in_the_frames_and_never_moves():
    frames = platform_scene().run()
    assert frames.names[1] == "table"
    assert np.all(frames.position[:, 1] == [2, 0, 0.2])
    q = np.array([0.96, 0, 0, 0.28])
    assert np.allclose(frames.orientation[:, 1], q, rtol=0, atol=1e-15)
    assert np.all(frames.velocity[:, 1] == 0) and np.all(frames.angular_velocity[:, 1] == 0)
