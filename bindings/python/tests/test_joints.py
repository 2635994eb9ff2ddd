"""Joints through the bindings (issue 21): SceneBuilder.add_joint writes the scene format's
"joints", the physics they hold is checked against what mechanics knows, and a bad joint raises
with the library's message (docs/python.md, "Joints"; docs/joints.md, "From Python")."""

import json
import math

import numpy as np
import pytest

import tumble

G = 9.81
LENGTH, WIDTH, MASS = 1.0, 0.02, 1.0  # a rod 1 m long, 2 cm square, 1 kg


def rod_pendulum(angle, **joint):
    """A rod hanging from a hinge about y at the origin (its top end), turned by angle (rad)
    from the vertical."""
    b = tumble.SceneBuilder()
    centre = [-0.5 * LENGTH * math.sin(angle), 0.0, -0.5 * LENGTH * math.cos(angle)]
    b.add_body("rod", shape={"type": "box", "size": [WIDTH, WIDTH, LENGTH]}, mass=MASS,
               position=centre, orientation=[math.cos(angle / 2), 0, math.sin(angle / 2), 0])
    b.add_effect("gravity")
    b.add_joint("hinge", "rod", anchor=[0, 0, 0], axis=[0, 1, 0], **joint)
    return b


def crossings(t, angle):
    """Times the angle passes 0 going up, linearly interpolated between frames (at a crossing
    the angle's curvature is 0, so the interpolation's error is third order in the frame
    spacing: 1e-9 s at 1 ms)."""
    up = np.nonzero((angle[:-1] < 0) & (angle[1:] >= 0))[0]
    return t[up] - angle[up] * (t[up + 1] - t[up]) / (angle[up + 1] - angle[up])


def test_a_pendulum_swings_with_the_period_of_its_moment_of_inertia():
    # A compound pendulum: T = 2 pi sqrt(I / (m g d)), I = m (L^2 + w^2) / 12 + m d^2 about
    # the hinge, d = L / 2, with the amplitude's series T0 (1 + a^2/16 + 11 a^4/3072) for
    # a = 0.05 rad (the next term, a^6, is 2e-8). RK4 at 1 ms has a phase error of about
    # (omega dt)^4 = 1e-13 a period; the joint holds the rod exactly, so the period is the
    # mechanics' to 1e-6, the crossings' interpolation and the series well inside it.
    amplitude = 0.05
    frames = rod_pendulum(amplitude).build(fps=1000, duration=8.0).run(method="rk4", dt=1e-3)
    x, z = frames.position[:, 0, 0], frames.position[:, 0, 2]
    angle = np.arctan2(-x, -z)
    periods = np.diff(crossings(frames.t, angle))
    d = LENGTH / 2
    inertia = MASS * (LENGTH**2 + WIDTH**2) / 12 + MASS * d**2
    period = 2 * math.pi * math.sqrt(inertia / (MASS * G * d))
    period *= 1 + amplitude**2 / 16 + 11 * amplitude**4 / 3072
    assert len(periods) >= 3
    np.testing.assert_allclose(periods, period, rtol=1e-6)


def test_a_joint_holds_and_keeps_the_energy_over_a_swing():
    # Released horizontally (a = pi / 2): the rod's top stays on the hinge and the energy
    # stays, each to the tolerances the issue asks of the double pendulum (1e-12 m; 1e-5 of
    # m g L over the run at 1 ms, where RK4's own drift is far below it).
    sim = tumble.Simulation(rod_pendulum(math.pi / 2).build(), method="rk4", dt=1e-3)
    assert sim.joint_count == 1
    start = sim.run(duration=2.0, fps=100)
    energy = start.kinetic_energy + start.potential_energy
    assert np.max(np.abs(energy - energy[0])) < 1e-5 * MASS * G * LENGTH
    position_error, velocity_error = sim.joint_error(0)
    assert position_error < 1e-12 and velocity_error < 1e-9
    assert sim.joint_broken(0) is False


def test_the_reaction_of_a_hanging_rod_carries_its_weight():
    # At rest under the hinge: the joint pushes the rod up with m g and no torque about the
    # anchor (the weight acts on the vertical through it). Exact to rounding of the solve.
    scene = rod_pendulum(0.0).build()
    force, torque = scene.joint_reaction(0)
    np.testing.assert_allclose(force, [0, 0, MASS * G], atol=1e-9)
    np.testing.assert_allclose(torque, [0, 0, 0], atol=1e-9)
    position_error, velocity_error = scene.joint_error(0)
    assert position_error < 1e-12 and velocity_error == 0.0
    sim = tumble.Simulation(scene, method="rk4", dt=1e-3)
    sim.advance(0.5)
    force, _ = sim.joint_reaction(0)
    np.testing.assert_allclose(force, [0, 0, MASS * G], atol=1e-9)


def test_the_builder_writes_the_joints_the_scene_describes():
    b = rod_pendulum(0.0)
    b.add_body("weight", shape={"type": "sphere", "radius": 0.05}, mass=2.0,
               position=[0, 0, -1.1])
    b.add_joint("ball", ["weight", "rod"], anchor=np.array([0, 0, -1.0]))
    description = json.loads(json.dumps(b._description))
    assert description["joints"] == [
        {"type": "hinge", "bodies": ["rod"], "anchor": [0.0, 0.0, 0.0], "axis": [0.0, 1.0, 0.0]},
        {"type": "ball", "bodies": ["weight", "rod"], "anchor": [0.0, 0.0, -1.0]}]
    scene = b.build()
    assert scene.joint_count == 2
    assert scene.joints[0]["type"] == "hinge" and scene.joints[0]["bodies"] == ["rod", "world"]
    assert scene.joints[1]["type"] == "ball" and scene.joints[1]["bodies"] == ["weight", "rod"]
    assert scene.joints[1]["anchor"] == [0.0, 0.0, -1.0]
    assert scene.joint_broken(1) is False
    # the options go into the file in the scene format's words, as given
    options = rod_pendulum(0.0, limits=[-0.5, 0.5], restitution=0.3, break_force=100.0,
                           motor={"speed": 1.0, "max_torque": 2.0})
    assert options._description["joints"][0] == {
        "type": "hinge", "bodies": ["rod"], "anchor": [0.0, 0.0, 0.0], "axis": [0.0, 1.0, 0.0],
        "limits": [-0.5, 0.5], "restitution": 0.3, "break_force": 100.0,
        "motor": {"speed": 1.0, "max_torque": 2.0}}


@pytest.mark.parametrize("joint, message", [
    (dict(type="hinge", bodies="rod", anchor=[0, 0, 0], axis=[0, 0, 0]),
     "<builder>: joints[0].axis: must be 3 finite numbers, not all 0"),
    (dict(type="ball", bodies=["rod", "nothing"], anchor=[0, 0, 0]),
     "<builder>: joints[0].bodies[1]: no body is named \"nothing\""),
    (dict(type="rope", bodies="rod", anchor=[0, 0, 0]),
     "<builder>: joints[0].type: must be one of ball, hinge, slider, fixed, got \"rope\""),
    (dict(type="hinge", bodies="rod", anchor=[0, 0, 0], axis=[0, 1, 0],
          motor={"speed": 1.0, "max_force": 2.0}),
     "<builder>: joints[0].motor.max_force: unknown key"),
])
def test_a_bad_joint_raises_with_the_library_message(joint, message):
    b = tumble.SceneBuilder()
    b.add_body("rod", shape={"type": "box", "size": [WIDTH, WIDTH, LENGTH]}, mass=MASS)
    b.add_joint(**joint)
    with pytest.raises(tumble.TumbleError) as caught:
        b.build()
    assert caught.value.status == "BAD_SCENE"
    assert caught.value.message.startswith(message), caught.value.message


def test_a_joint_the_library_refuses_raises_its_own_message():
    # limits reversed: the library's check, its message after the joint's place
    b = rod_pendulum(0.0, limits=[0.5, -0.5])
    with pytest.raises(tumble.TumbleError) as caught:
        b.build()
    assert caught.value.status == "BAD_SCENE"
    assert caught.value.message.startswith("<builder>: joints[0]: "), caught.value.message
    assert "limits" in caught.value.message


def test_a_joint_index_is_checked():
    sim = tumble.Simulation(rod_pendulum(0.0).build(), method="rk4", dt=1e-3)
    with pytest.raises(tumble.TumbleValueError) as caught:
        sim.joint_reaction(1)
    assert caught.value.status == "OUT_OF_RANGE"
    with pytest.raises(IndexError):
        sim.joint_error(-1)
    with pytest.raises(TypeError):
        sim.joint_broken("0")


def test_the_reactions_of_a_run_are_newtons_for_the_swinging_rod():
    # run(joint_reactions=True): at every frame the hinge's force on the rod is what moves its
    # centre on its circle against gravity, F = m a - m g, with a = d (alpha t - omega^2 r)
    # (r from the hinge to the centre, t its turn by +90 degrees in the swing, alpha =
    # -(m g d / I) sin theta from the rod's equation of motion), and no torque (a planar swing
    # about a principal axis). To 1e-9 N: the frames' state is on the joint to 1e-15 m and the
    # solve exact to rounding.
    frames = rod_pendulum(1.0).build(fps=50, duration=2.0).run(method="rk4", dt=1e-3,
                                                               joint_reactions=True)
    assert frames.joint_force.shape == (101, 1, 3) and frames.joint_broken.shape == (101, 1)
    d = LENGTH / 2
    inertia = MASS * (LENGTH**2 + WIDTH**2) / 12 + MASS * d**2
    x, z = frames.position[:, 0, 0], frames.position[:, 0, 2]
    theta = np.arctan2(x, -z)
    r = np.stack([np.sin(theta), 0 * theta, -np.cos(theta)], axis=1)
    t = np.stack([np.cos(theta), 0 * theta, np.sin(theta)], axis=1)
    omega2 = frames.angular_velocity[:, 0, 1] ** 2
    alpha = -(MASS * G * d / inertia) * np.sin(theta)
    expected = MASS * d * (alpha[:, None] * t - omega2[:, None] * r) + [0, 0, MASS * G]
    np.testing.assert_allclose(frames.joint_force[:, 0], expected, atol=1e-9)
    np.testing.assert_allclose(frames.joint_torque[:, 0], 0.0, atol=1e-9)
    assert not frames.joint_broken.any()
    assert tumble.Scene.from_dict(json.loads(json.dumps(rod_pendulum(0.0)._description))) \
        .run(duration=0.1).joint_force is None  # only when asked for


def test_a_joint_breaks_when_its_pull_passes_the_limit():
    # A 2 kg ball on a 1 m rigid string passing the bottom at 2 m/s needs m (g + v^2 / L) =
    # 27.62 N from it; with break_force 25 N the string breaks at the first step: from then on
    # the joint reads broken with a zero reaction, and the ball flies free: from the frame at
    # 0.02 s on, its centre follows the free parabola from that frame's position and velocity
    # (RK4 is exact on a parabola: 1e-12 m).
    b = tumble.SceneBuilder()
    b.add_body("bob", shape={"type": "sphere", "radius": 0.05}, mass=2.0, position=[0, 0, 0],
               velocity=[2, 0, 0], angular_velocity=[0, -2, 0])
    b.add_effect("gravity")
    b.add_joint("ball", "bob", anchor=[0, 0, 1], break_force=25.0)
    sim = tumble.Simulation(b.build(), method="rk4", dt=1e-3)
    assert sim.joint_broken(0) is False
    frames = sim.run(duration=0.5, fps=50, joint_reactions=True)
    assert frames.joint_broken[0, 0] == False  # noqa: E712 (a NumPy bool)
    assert frames.joint_broken[1:, 0].all() and sim.joint_broken(0) is True
    np.testing.assert_array_equal(frames.joint_force[1:, 0], 0.0)
    dt = frames.t[1:] - frames.t[1]
    free = frames.position[1, 0] + np.outer(dt, frames.velocity[1, 0])
    free[:, 2] -= 0.5 * G * dt**2
    np.testing.assert_allclose(frames.position[1:, 0], free, atol=1e-12)


def test_a_door_stops_at_its_limit_and_comes_back_at_the_restitution():
    # A 20 kg door on a vertical hinge, limits [0, 90 deg] with restitution 0.5, pushed open
    # at 2 rad/s: nothing turns it but the stop, so it swings at 2 rad/s to 90 degrees (0.785
    # s) and comes back at -1 rad/s; RK4 keeps a constant rotation to round-off and the stop's
    # impulse is exact (1e-9 rad/s); no frame is past the stop (1e-12 rad, the projection's).
    b = tumble.SceneBuilder()
    b.add_body("door", shape={"type": "box", "size": [1.0, 0.05, 2.0]}, mass=20.0,
               position=[0.5, 0, 0], velocity=[0, 1.0, 0], angular_velocity=[0, 0, 2.0])
    b.add_joint("hinge", "door", anchor=[0, 0, 0], axis=[0, 0, 1], limits=[0, math.pi / 2],
                restitution=0.5)
    frames = b.build(fps=100, duration=1.5).run(method="rk4", dt=1 / 240)
    t, spin = frames.t, frames.angular_velocity[:, 0, 2]
    angle = np.arctan2(frames.position[:, 0, 1], frames.position[:, 0, 0])
    hit = (math.pi / 2) / 2.0
    np.testing.assert_allclose(spin[t < hit - 0.02], 2.0, atol=1e-9)
    np.testing.assert_allclose(spin[t > hit + 0.02], -1.0, atol=1e-9)
    assert angle.max() <= math.pi / 2 + 1e-12


def test_a_hinge_motor_spins_a_wheel_up_at_its_cap_then_holds_the_speed():
    # A 6 kg, 1 x 1 x 0.2 m wheel (I = 1 kg m^2 about z) with a velocity motor toward 10 rad/s
    # under 2 N m: the speed is the cap's 2 t until the motor's own approach (20/s times the
    # error) asks less than the cap (at 9.9 rad/s, 4.95 s), then reaches 10 rad/s within
    # 0.1 e^(-20 (t - 4.95)): 1e-9 rad/s on both, RK4 at 1/240 s (docs/joints.md, "Motors").
    b = tumble.SceneBuilder()
    b.add_body("wheel", shape={"type": "box", "size": [1.0, 1.0, 0.2]}, mass=6.0,
               position=[0, 0, 0])
    b.add_joint("hinge", "wheel", anchor=[0, 0, 0], axis=[0, 0, 1],
                motor={"speed": 10.0, "max_torque": 2.0})
    frames = b.build(fps=10, duration=8.0).run(method="rk4", dt=1 / 240)
    t, spin = frames.t, frames.angular_velocity[:, 0, 2]
    np.testing.assert_allclose(spin[t <= 4.9 + 1e-9], 2.0 * t[t <= 4.9 + 1e-9], atol=1e-9)
    np.testing.assert_allclose(spin[t >= 6.5 - 1e-9], 10.0, atol=1e-9)


STRING = 1.0  # m: a bob hung from the world 1 m above its centre by a ball joint


def bob_on_a_string(velocity=(0.0, 0.0, 0.0)):
    b = tumble.SceneBuilder()
    b.add_body("bob", shape={"type": "sphere", "radius": 0.05}, mass=2.0, position=[0, 0, 0],
               velocity=list(velocity))
    b.add_effect("gravity")
    b.add_joint("ball", "bob", anchor=[0, 0, STRING])
    return b.build()


def rotate(q, v):
    """v turned by the unit quaternion q = (w, x, y, z)."""
    w, u = q[0], np.asarray(q[1:])
    return v + 2 * np.cross(u, np.cross(u, v) + w * v)


def string_end(sim):
    """Where the bob's end of the string is and how fast it moves, from the bob's state alone
    (its centre, orientation, velocity and angular velocity): the point 1 m above the centre in
    the bob's frame at the start, where the joint was made with the bob's frame the world's."""
    arm = rotate(sim.quaternion[0], np.array([0.0, 0.0, STRING]))
    velocity = sim.velocity[0] + np.cross(sim.angular_velocity[0], arm)
    return sim.position[0] + arm, velocity


def test_project_joints_puts_a_start_off_the_joint_back_on_it():
    # The bob moved 1 mm sideways and 2 mm up, and given 0.3 m/s along the string: its end of
    # the string is off the anchor. The projection (tb_scene_project_joints, the CLI's
    # --project-joints) puts the string's end back on the anchor (0, 0, 1) and its velocity to
    # 0 (a ball joint to the world holds the point still), each to the library's 1e-12,
    # checked here from the bob's own state, not from the library's joint error.
    sim = tumble.Simulation(bob_on_a_string(), method="rk4", dt=1e-3)
    sim.set_state("bob", position=[1e-3, 0.0, 2e-3], momentum=[0.0, 0.0, -0.6])
    before = sim.joint_error(0)
    assert before[0] > 1e-3 and before[1] > 0.2  # off by about 2.2 mm and 0.3 m/s
    left = sim.project_joints()
    assert left < 1e-12
    end, velocity = string_end(sim)
    np.testing.assert_allclose(end, [0.0, 0.0, STRING], rtol=0, atol=1e-12)
    np.testing.assert_allclose(velocity, 0.0, rtol=0, atol=1e-12)
    position_error, velocity_error = sim.joint_error(0)
    assert position_error < 1e-12 and velocity_error < 1e-12
    sim.advance(0.1)  # and it steps from there, on the joint
    assert max(sim.joint_error(0)) < 1e-12


def test_project_joints_refuses_a_tolerance_it_cannot_meet_and_changes_nothing():
    # As the C library refuses (SOLVER_FAILED, naming the joint): 1e-300 is below the
    # round-off a hinge's rows leave (about 1e-19 here); the state is left as it was, to the
    # bit. Without a projection the start stays off.
    sim = tumble.Simulation(rod_pendulum(0.3).build(), method="rk4", dt=1e-3)
    sim.set_state("rod", position=sim.position[0] + [1.3e-3, 0.7e-3, -0.9e-3])
    saved = sim.state.copy()
    with pytest.raises(tumble.TumbleError) as caught:
        sim.project_joints(1e-300)
    assert caught.value.status == "SOLVER_FAILED"
    assert caught.value.message.startswith("joints[0]: the projection left an error"), \
        caught.value.message
    assert sim.state.tobytes() == saved.tobytes()
    assert sim.joint_error(0)[0] > 1e-3
    with pytest.raises(tumble.TumbleValueError):
        sim.project_joints(-1.0)
    with pytest.raises(TypeError):
        sim.project_joints("0")


def test_project_joints_at_the_start_of_a_run_and_a_simulation():
    # A scene file's positions are on its joints; its velocities need not be: the bob starts
    # at 1 m/s down the string and 0.5 m/s sideways without turning (the string's end moves;
    # tests/scenes/joint_off_start.json, which `tumble check` refuses, is the first half).
    # Asked to, Scene.run and Simulation project the start first, by the least change of
    # M |dv|^2 + I |dw|^2 that stops the string's end: the speed along the string goes, and
    # the sideways speed u splits between the bob's centre and its turn about it as the
    # inverse mass and inertia say, v_x = u (L^2 / I) / (1 / M + L^2 / I) and w_y = -v_x / L
    # (I = 2/5 M r^2 = 0.002 kg m^2: v_x = 0.4995 m/s). Without it the first frame is the
    # file's start.
    scene = bob_on_a_string(velocity=(0.5, 0.0, -1.0))
    plain = scene.run(method="rk4", dt=1e-3, fps=100, duration=0.05)
    np.testing.assert_array_equal(plain.velocity[0, 0], [0.5, 0.0, -1.0])
    mass, inertia = 2.0, 0.4 * 2.0 * 0.05**2
    v_x = 0.5 * (STRING**2 / inertia) / (1 / mass + STRING**2 / inertia)
    projected = scene.run(method="rk4", dt=1e-3, fps=100, duration=0.05, project_joints=True)
    np.testing.assert_allclose(projected.velocity[0, 0], [v_x, 0.0, 0.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(projected.angular_velocity[0, 0], [0.0, -v_x / STRING, 0.0],
                               rtol=0, atol=1e-12)
    sim = tumble.Simulation(scene, method="rk4", dt=1e-3, project_joints=True)
    assert max(sim.joint_error(0)) < 1e-12
    np.testing.assert_allclose(sim.velocity[0], [v_x, 0.0, 0.0], rtol=0, atol=1e-12)
    sim.advance(0.05)
    np.testing.assert_allclose(sim.position, projected.position[-1], rtol=0, atol=1e-15)
