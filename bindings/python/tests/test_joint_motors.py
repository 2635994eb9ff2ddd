"""A joint's motor changed between steps and its axial read-outs, through the bindings
(Simulation.set_joint_motor: tb_scene_set_joint_motor; joint_axial: tb_scene_joint_axial),
checked against statics and a constant torque's motion (docs/python.md, "Joints"; the C side's
tests/test_joint_motor_stops.c has the same door)."""

import math

import numpy as np
import pytest

import tumble

CAP = 2.0  # N m: the door motor's cap
MASS, WIDTH, THICK, HEIGHT = 20.0, 1.0, 0.05, 2.0
# about the hinge (its edge, z): m (w^2 + t^2) / 12 + m (w / 2)^2 = 6.6708 kg m^2
INERTIA = MASS * (WIDTH**2 + THICK**2) / 12 + MASS * (WIDTH / 2)**2
ALPHA = CAP / INERTIA  # rad/s^2: the cap's uniform angular acceleration
OPEN = math.pi / 2  # the upper stop
METHODS = [("rk4", {"dt": 1 / 240}), ("cvode-bdf", {"rtol": 1e-10})]


def door(motor=True, sleeping=None):
    """A 20 kg door, 1 x 0.05 x 2 m, at rest on a vertical hinge through its edge at x = 0,
    limits [0, 90 deg] (restitution 0), its velocity motor toward 1 rad/s under a 2 N m cap
    (none if not motor). Gravity is along the axis: it turns nothing about it. sleeping:
    as SceneBuilder.build (default on)."""
    b = tumble.SceneBuilder()
    b.add_body("door", shape={"type": "box", "size": [WIDTH, THICK, HEIGHT]}, mass=MASS,
               position=[WIDTH / 2, 0, 0])
    b.add_effect("gravity")
    fields = {"limits": [0, OPEN]}
    if motor:
        fields["motor"] = {"speed": 1.0, "max_torque": CAP}
    b.add_joint("hinge", "door", anchor=[0, 0, 0], axis=[0, 0, 1], **fields)
    return b.build(sleeping=sleeping)


def angle(sim):
    """The door's angle about z from its centre's position alone (not the library's read-out)."""
    return math.atan2(sim.position[0, 1], sim.position[0, 0])


@pytest.mark.parametrize("method, options", METHODS, ids=[m for m, _ in METHODS])
def test_a_door_motor_rests_on_its_stop_at_its_cap_and_leaves_when_reversed(method, options):
    # The motor asks 20/s (1 - omega) I, more than the cap until 0.985 rad/s, and the door
    # reaches its stop before that (at 0.971 rad/s, t1 = sqrt(pi / alpha) = 3.24 s): a constant
    # torque about a fixed axis, alpha t^2 / 2, which RK4 keeps to round-off (2.1e-13 rad
    # measured) and CVODE BDF to its rtol 1e-10 (3.6e-10): bound 1e-8 rad. On the stop
    # (restitution 0) nothing else acts about the axis, so statics says the stop takes exactly
    # the motor's push: motor +CAP and stop -CAP, checked to 1e-9 of the cap (the solve's
    # round-off; 0 measured); the joint's torque about z, their sum, 0 to the same; the door at
    # 90 degrees to the projection's 1e-12 rad and still. Reversed at 5 s (toward -1 rad/s, the
    # cap kept), the motor pulls it off at its cap: pi/2 - alpha (t - 5)^2 / 2 to 1e-8 rad
    # (1.4e-13 RK4, 1.2e-10 BDF), the stop's load 0: the integrator went on after the change
    # (CVODE restarted itself; under RK4 the door had fallen asleep on its stop, and the change
    # woke it).
    sim = tumble.Simulation(door(), method=method, **options)
    assert door().joint_axial(0) == (0.0, CAP, 0.0)  # at rest at the start: pushed at its cap
    for t in (1.0, 2.0, 3.0):
        sim.advance(t)
        coordinate, motor, stop = sim.joint_axial(0)
        assert abs(angle(sim) - 0.5 * ALPHA * t * t) <= 1e-8
        assert abs(coordinate - angle(sim)) <= 1e-12
        assert (motor, stop) == (CAP, 0.0)
    sim.advance(5.0)
    coordinate, motor, stop = sim.joint_axial(0)
    assert abs(coordinate - OPEN) <= 1e-12 and abs(angle(sim) - OPEN) <= 1e-12
    np.testing.assert_allclose(sim.angular_velocity[0], 0.0, rtol=0, atol=1e-9)
    assert abs(motor - CAP) <= 1e-9 * CAP
    assert abs(stop + CAP) <= 1e-9 * CAP
    assert abs(sim.joint_reaction(0)[1][2]) <= 1e-9 * CAP
    restarts = sim.stats["reinitializations"]
    sim.set_joint_motor(0, "velocity", -1.0)  # max_force None: the joint's 2 N m kept
    for t in (5.5, 6.0, 7.0):
        sim.advance(t)
        coordinate, motor, stop = sim.joint_axial(0)
        assert abs(angle(sim) - (OPEN - 0.5 * ALPHA * (t - 5.0)**2)) <= 1e-8
        assert abs(coordinate - angle(sim)) <= 1e-12
        assert abs(motor + CAP) <= 1e-9 * CAP and stop == 0.0
    if method == "cvode-bdf":
        assert sim.stats["reinitializations"] > restarts


@pytest.mark.parametrize("method, options", METHODS, ids=[m for m, _ in METHODS])
def test_a_position_motor_holds_its_target_and_an_off_motor_lets_the_door_coast(method, options):
    # A position servo asks (20/s)^2 (target - q) - 2 (20/s) rate, critically damped at 20/s.
    # From 0.15 rad at 1 s toward 0.6 rad under 50 N m it is capped at first (it asks
    # 400 x 0.45 I = 1200 N m), then within its cap; the error left decays as t e^(-20 t), below
    # 1e-20 rad by 4 s: the door is at its target to 1e-9 rad, and with nothing else about the
    # axis the motor's load there is 0 (1e-9 of the cap). Sleeping is off: a door at rest
    # within the sleep thresholds would freeze it at 7e-10 rad off (RK4; tumble's sleeping, not
    # the motor). Turned off, no torque acts about the axis: the spin given at the switch
    # stays to 1e-9 rad/s.
    sim = tumble.Simulation(door(sleeping=False), method=method, **options)
    sim.advance(1.0)
    sim.set_joint_motor(0, "position", 0.6, max_force=50.0)
    sim.advance(4.0)
    coordinate, motor, stop = sim.joint_axial(0)
    assert abs(angle(sim) - 0.6) <= 1e-9 and abs(coordinate - 0.6) <= 1e-9
    assert abs(motor) <= 1e-9 * 50.0 and stop == 0.0
    sim.set_joint_motor(0, "velocity", 0.2, max_force=50.0)
    sim.advance(5.0)  # spinning at 0.2 rad/s (reached within 0.2 e^(-20 s))
    sim.set_joint_motor(0, "off")
    spin = sim.angular_velocity[0, 2]
    assert abs(spin - 0.2) <= 1e-9
    sim.advance(5.5)
    assert abs(sim.angular_velocity[0, 2] - spin) <= 1e-9
    assert sim.joint_axial(0)[1:] == (0.0, 0.0)


def test_a_bad_motor_is_refused_naming_the_field_and_changes_nothing():
    # As the C library refuses it (tb_scene_set_joint_motor: motor_max_force > 0 and finite),
    # each with its detail; the state is left to the bit, and the motor too: the simulation
    # goes on exactly as a twin never asked (bit for bit, RK4).
    sim = tumble.Simulation(door(), method="rk4", dt=1 / 240)
    twin = tumble.Simulation(door(), method="rk4", dt=1 / 240)
    sim.advance(1.0)
    twin.advance(1.0)
    saved = sim.state.tobytes()
    for bad, status in ((0.0, "INVALID_ARGUMENT"), (-2.0, "INVALID_ARGUMENT"),
                        (float("nan"), "NOT_FINITE"), (float("inf"), "NOT_FINITE")):
        with pytest.raises(tumble.TumbleValueError) as caught:
            sim.set_joint_motor(0, "velocity", -1.0, max_force=bad)
        assert caught.value.status == status
        assert "motor_max_force" in caught.value.message, caught.value.message
        assert sim.state.tobytes() == saved
    with pytest.raises(tumble.TumbleValueError) as caught:
        sim.set_joint_motor(0, "position", float("nan"), max_force=CAP)
    assert "motor_target" in caught.value.message, caught.value.message
    with pytest.raises(ValueError, match="mode must be one of"):
        sim.set_joint_motor(0, "speed", 1.0)  # the scene file's key, not a mode
    with pytest.raises(TypeError):
        sim.set_joint_motor(0, "velocity", "1")
    with pytest.raises(tumble.TumbleValueError) as caught:
        sim.set_joint_motor(1, "velocity", 1.0, max_force=CAP)
    assert caught.value.status == "OUT_OF_RANGE"
    assert sim.state.tobytes() == saved
    assert sim.joint_axial(0) == twin.joint_axial(0)
    sim.advance(4.0)
    twin.advance(4.0)
    assert sim.state.tobytes() == twin.state.tobytes()


def test_joint_axial_refuses_a_joint_without_an_axis_and_a_motor_needs_a_cap():
    # A ball joint has no axial coordinate, and a joint made without a motor has no cap to
    # keep: the library refuses both (INVALID_ARGUMENT, naming what was wrong).
    b = tumble.SceneBuilder()
    b.add_body("bob", shape={"type": "sphere", "radius": 0.05}, mass=1.0, position=[0, 0, 0])
    b.add_joint("ball", "bob", anchor=[0, 0, 1])
    sim = tumble.Simulation(b.build(), method="rk4", dt=1e-3)
    with pytest.raises(tumble.TumbleValueError, match="only a hinge or slider"):
        sim.joint_axial(0)
    plain = tumble.Simulation(door(motor=False), method="rk4", dt=1 / 240)
    with pytest.raises(tumble.TumbleValueError, match="motor_max_force"):
        plain.set_joint_motor(0, "velocity", 1.0)
    plain.set_joint_motor(0, "velocity", 1.0, max_force=CAP)
    plain.advance(1.0)
    assert abs(angle(plain) - 0.5 * ALPHA) <= 1e-8  # the cap's alpha t^2 / 2 at 1 s

