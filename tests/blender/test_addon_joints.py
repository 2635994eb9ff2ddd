"""tumble for Blender, headless: Blender's rigid body constraints as tumble joints.

    blender -b --factory-startup --python tests/blender/test_addon_joints.py -- \
        --cli build/cli/tumble --out DIRECTORY [--zip build/tumble_blender.zip]

Run as test_addon.py is (its helpers; the add-on installed from its zip, tumble's Python package
from TUMBLE_PYTHON_PATH and TUMBLE_LIBRARY). Checks, each against what is known without tumble:
  * a rod hinged to a passive support, released 0.1 rad out, undamped: the add-on's keys equal `tumble run`
    on the add-on's scene file within 1e-6 m and 1e-4 degrees (Blender's single-precision keys),
    and its period is the compound pendulum's, 2 pi sqrt(I / (m g d)) (1 + a^2/16 + 11 a^4/3072),
    within 1e-5 (the crossings read from frames 1/120 s apart by linear interpolation, off by
    about dt (omega dt)^2 / 24 = 1e-7 s; the series' next term 2e-9);
  * where Blender's own simulation (Bullet) leaves the bodies, the add-on's bake agrees: a
    hinge's stop (the arm's angle at rest on it within 0.01 rad, Bullet's stops give a little)
    with either object first, a slider's stop (0.005 m), and the direction a MOTOR constraint
    drives a hinge and a slider (after 1 s at 3 rad/s and 0.5 m/s: the same way, the angle and
    the travel within 10% of Bullet's, which reaches the speed in a step where tumble's motor
    approaches it in 50 ms); a FIXED constraint under a weight breaks in both at 0.8 of the
    weight's impulse per substep and holds in both at 1.2;
  * the scene file says what Blender's panels say: each type's joint, anchor at the constraint
    object's location, axis its z (hinge) or x (slider), limits, break force and torque =
    breaking threshold x fps x substeps per frame (Bullet's impulse per substep), and no contact
    between the bodies of a constraint with Disable Collisions;
  * a GENERIC, GENERIC_SPRING or PISTON constraint, a constraint without its two objects and a
    MOTOR with no hinge or slider under it are refused, naming the object and the type.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import test_addon as base  # noqa: E402 (its helpers; its main runs only as a script)

import bpy  # noqa: E402
import numpy as np  # noqa: E402

check = base.check
G = 9.81
FPS = 120
LENGTH, WIDTH, MASS, AMPLITUDE = 1.0, 0.02, 1.0, 0.1


def constraint(name, kind, location, rotation, first, second):
    bpy.ops.object.empty_add(location=location, rotation=rotation)
    empty = bpy.context.object
    empty.name = name
    bpy.ops.rigidbody.constraint_add(type=kind)
    rbc = empty.rigid_body_constraint
    rbc.object1, rbc.object2 = first, second
    return rbc


def clear(scene, frames, fps=base.FPS):
    base.clear(scene, frames)
    scene.render.fps = fps
    scene.gravity = (0.0, 0.0, -G)


HINGE_Y = (-math.pi / 2, 0.0, 0.0)  # an empty turned so that its z axis is the world's y


def pendulum(scene):
    """A 1 m, 1 kg rod (2 cm square) hinged at its top end about y to a passive support above
    the pivot, released AMPLITUDE rad out; 6 s at 120 fps. Blender's default damping (0.04
    linear, 0.1 angular, which the add-on maps to drag) set to 0: it would lengthen the period
    by its damping ratio squared over 2."""
    clear(scene, 6 * FPS + 1, FPS)
    support = base.box("Support", (0.2, 0.2, 0.2), (0, 0, 1.2), kind="PASSIVE")
    s, c = math.sin(AMPLITUDE), math.cos(AMPLITUDE)
    rod = base.box("Rod", (WIDTH, WIDTH, LENGTH), (-0.5 * LENGTH * s, 0, 1.0 - 0.5 * LENGTH * c),
                   rotation=(0, AMPLITUDE, 0))
    rod.rigid_body.linear_damping = rod.rigid_body.angular_damping = 0.0
    constraint("Pivot", "HINGE", (0, 0, 1.0), HINGE_Y, rod, support)


def crossings(t, angle):
    up = np.nonzero((angle[:-1] < 0) & (angle[1:] >= 0))[0]
    return t[up] - angle[up] * (t[up + 1] - t[up]) / (angle[up + 1] - angle[up])


def pendulum_period(scene, args):
    pendulum(scene)
    base.bake_and_compare(scene, args, "pendulum")
    rows = base.read_csv(os.path.join(args.out, "pendulum.csv"))["Rod"]
    t = np.array([float(r["t"]) for r in rows])
    x, z = (np.array([float(r[k]) for r in rows]) for k in ("x", "z"))
    periods = np.diff(crossings(t, np.arctan2(-x, 1.0 - z)))
    d = LENGTH / 2
    inertia = MASS * (LENGTH**2 + WIDTH**2) / 12 + MASS * d**2
    expected = 2 * math.pi * math.sqrt(inertia / (MASS * G * d))
    expected *= 1 + AMPLITUDE**2 / 16 + 11 * AMPLITUDE**4 / 3072
    worst = float(np.max(np.abs(periods / expected - 1))) if len(periods) else math.inf
    check(len(periods) >= 2 and worst <= 1e-5,
          f"pendulum: {len(periods)} periods within {worst:.1e} of the compound pendulum's "
          f"{expected:.6f} s")


def simulate_both(scene, obj, frames):
    """(Bullet's, tumble's) pose (location, quaternion) of obj at the last frame: Blender's own
    simulation stepped frame by frame, then the add-on's bake read at that frame."""
    for frame in range(scene.frame_start, frames + 1):
        scene.frame_set(frame)
    bullet = (np.array(obj.matrix_world.translation), np.array(obj.matrix_world.to_quaternion()))
    scene.frame_set(1)
    check(bpy.ops.tumble.bake() == {"FINISHED"}, f"bake of {obj.name}")
    scene.frame_set(frames)
    baked = (np.array(obj.matrix_world.translation), np.array(obj.matrix_world.to_quaternion()))
    bpy.ops.tumble.free_bake()
    scene.frame_set(1)
    return bullet, baked


def turn_about_y(q):
    return 2 * math.atan2(q[2], q[0])


def limits_agree_with_bullet(scene):
    """A horizontal arm on a hinge about y with limits [-0.3, 0.5] rad falls onto one stop: the
    upper when the arm is object1, the lower when the support is (the angle is object1's turn
    against object2's). A block on a vertical slider with limits [-0.1, 0.25] m falls onto the
    stop its order says."""
    for first in ("Arm", "Base"):
        clear(scene, 48)
        support = base.box("Base", (0.2, 0.2, 0.2), (0, 0, 0.3), kind="PASSIVE")
        arm = base.box("Arm", (1, 0.05, 0.05), (0.5, 0, 0))
        pair = (arm, support) if first == "Arm" else (support, arm)
        rbc = constraint("Hinge", "HINGE", (0, 0, 0), HINGE_Y, *pair)
        rbc.use_limit_ang_z, rbc.limit_ang_z_lower, rbc.limit_ang_z_upper = True, -0.3, 0.5
        bullet, baked = simulate_both(scene, arm, 48)
        a, b = turn_about_y(bullet[1]), turn_about_y(baked[1])
        check(abs(a - b) <= 0.01 and abs(abs(b) - (0.5 if first == "Arm" else 0.3)) <= 0.01,
              f"hinge stop, {first} first: Bullet {a:.4f} rad, tumble {b:.4f} rad")
    for first in ("Block", "Base"):
        clear(scene, 48)
        support = base.box("Base", (0.2, 0.2, 0.2), (0, 0, 1.0), kind="PASSIVE")
        block = base.box("Block", (0.1, 0.1, 0.1), (0, 0.5, 0))
        pair = (block, support) if first == "Block" else (support, block)
        rbc = constraint("Slide", "SLIDER", (0, 0.5, 0), (0, -math.pi / 2, 0), *pair)
        rbc.use_limit_lin_x, rbc.limit_lin_x_lower, rbc.limit_lin_x_upper = True, -0.1, 0.25
        bullet, baked = simulate_both(scene, block, 48)
        check(abs(bullet[0][2] - baked[0][2]) <= 0.005,
              f"slider stop, {first} first: Bullet z {bullet[0][2]:.4f} m, tumble "
              f"{baked[0][2]:.4f} m")


def motors_agree_with_bullet(scene):
    """A MOTOR constraint (x along the hinge's z, or against it; either object first) spins a
    wheel the way Bullet spins it; one on a slider pushes the block Bullet's way."""
    for first, flip in (("Wheel", 1), ("Base", 1), ("Wheel", -1)):
        clear(scene, 24)
        support = base.box("Base", (0.2, 0.2, 0.2), (0, -0.5, 0), kind="PASSIVE")
        wheel = base.box("Wheel", (0.6, 0.1, 0.6), (0, 0, 0))
        constraint("Hinge", "HINGE", (0, 0, 0), HINGE_Y, wheel, support)
        pair = (wheel, support) if first == "Wheel" else (support, wheel)
        rbc = constraint("Motor", "MOTOR", (0, 0, 0), (0, 0, flip * math.pi / 2), *pair)
        rbc.use_motor_ang, rbc.motor_ang_target_velocity, rbc.motor_ang_max_impulse = True, 3, 50
        bullet, baked = simulate_both(scene, wheel, 24)
        a, b = turn_about_y(bullet[1]), turn_about_y(baked[1])
        check(a * b > 0 and abs(b / a - 1) <= 0.1,
              f"hinge motor, {first} first, x {'along' if flip > 0 else 'against'} the hinge: "
              f"Bullet turns {a:.3f} rad, tumble {b:.3f} rad")
    for first in ("Block", "Base"):
        clear(scene, 24)
        scene.gravity = (0.0, 0.0, 0.0)
        support = base.box("Base", (0.2, 0.2, 0.2), (0, 0, 1.0), kind="PASSIVE")
        block = base.box("Block", (0.1, 0.1, 0.1), (0, 0.5, 0))
        constraint("Slide", "SLIDER", (0, 0.5, 0), (0, 0, 0), block, support)
        pair = (block, support) if first == "Block" else (support, block)
        rbc = constraint("Motor", "MOTOR", (0, 0.5, 0), (0, 0, 0), *pair)
        rbc.use_motor_lin, rbc.motor_lin_target_velocity, rbc.motor_lin_max_impulse = True, 0.5, 50
        bullet, baked = simulate_both(scene, block, 24)
        a, b = bullet[0][0], baked[0][0]
        check(a * b > 0 and abs(b / a - 1) <= 0.1,
              f"slider motor, {first} first: Bullet moves {a:.3f} m, tumble {b:.3f} m")


def breaking_agrees_with_bullet(scene):
    """A 1 kg block held at its centre by a FIXED constraint to a passive post: its weight puts
    an impulse m g dt on the vertical row each substep (dt = 1 / (24 x 10) s), so Bullet breaks
    the constraint at once when the threshold is 0.8 of that, and never at 1.2; so does tumble
    with the add-on's break force threshold / dt (7.8 N and 11.8 N against 9.81 N)."""
    for factor in (0.8, 1.2):
        clear(scene, 12)
        scene.rigidbody_world.substeps_per_frame = 10
        post = base.box("Post", (0.2, 0.2, 0.2), (0, 0, 1.0), kind="PASSIVE")
        block = base.box("Block", (0.1, 0.1, 0.1), (0, 0.5, 1.0))
        block.rigid_body.linear_damping = block.rigid_body.angular_damping = 0.0
        rbc = constraint("Glue", "FIXED", (0, 0.5, 1.0), (0, 0, 0), block, post)
        rbc.use_breaking = True
        rbc.breaking_threshold = factor * MASS * G / (base.FPS * 10)
        bullet, baked = simulate_both(scene, block, 12)
        fell = [float(1.0 - p[0][2]) for p in (bullet, baked)]
        broken = factor < 1
        check(all((drop > 0.1) == broken for drop in fell),
              f"breaking at {factor} x m g dt: Bullet's block drops {fell[0]:.3f} m, tumble's "
              f"{fell[1]:.3f} m ({'broken' if broken else 'held'} expected)")


def file_says_what_blender_says(scene, args):
    """Every type, limits and breaking, read back from the exported file."""
    import json

    clear(scene, 10)
    scene.rigidbody_world.substeps_per_frame = 10
    post = base.box("Post", (0.2, 0.2, 2), (0, 0, 1), kind="PASSIVE")
    door = base.box("Door", (1, 0.05, 1.8), (0.6, 0, 1))
    lid = base.box("Lid", (0.3, 0.3, 0.05), (0.6, 0.2, 1.95))
    drawer = base.box("Drawer", (0.3, 0.3, 0.2), (-0.5, 0, 0.5))
    hinge = constraint("DoorHinge", "HINGE", (0.1, 0, 1), (0.2, 0, 0), door, post)
    hinge.use_limit_ang_z, hinge.limit_ang_z_lower, hinge.limit_ang_z_upper = True, -0.5, 1.5
    hinge.use_breaking, hinge.breaking_threshold = True, 2.0
    constraint("LidBall", "POINT", (0.6, 0.2, 1.9), (0, 0, 0), lid, door)
    slide = constraint("Rail", "SLIDER", (-0.3, 0, 0.5), (0, 0, 0.3), drawer, post)
    slide.use_limit_lin_x, slide.limit_lin_x_lower, slide.limit_lin_x_upper = True, -0.2, 0.1
    constraint("Weld", "FIXED", (0.6, 0.2, 1.9), (0, 0, 0), lid, door).enabled = False
    path = os.path.join(args.out, "constraints.json")
    check(bpy.ops.tumble.export_scene(filepath=path) == {"FINISHED"}, "constraints: export")
    with open(path) as file:
        data = json.load(file)
    joints = {tuple(j["bodies"]): j for j in data.get("joints", [])}
    door_hinge = joints.get(("Door", "Post"), {})
    z_axis = [0.0, -math.sin(0.2), math.cos(0.2)]  # the empty's z, turned 0.2 rad about x
    rail = joints.get(("Drawer", "Post"), {})
    ok = (len(joints) == 3 and door_hinge.get("type") == "hinge" and
          np.allclose(door_hinge["anchor"], [0.1, 0, 1], atol=1e-7) and
          np.allclose(door_hinge["axis"], z_axis, atol=1e-7) and
          np.allclose(door_hinge["limits"], [-0.5, 1.5], atol=1e-7) and
          door_hinge["break_force"] == door_hinge["break_torque"] == 2.0 * base.FPS * 10 and
          joints.get(("Lid", "Door"), {}).get("type") == "ball" and
          rail.get("type") == "slider" and
          np.allclose(rail["axis"], [math.cos(0.3), math.sin(0.3), 0], atol=1e-7) and
          np.allclose(rail["limits"], [-0.1, 0.2], atol=1e-7))
    check(ok, f"constraints: the file's joints are Blender's: {json.dumps(data.get('joints'))}")
    pairs = [set(e["bodies"]) for e in data["effects"] if e["type"] == "contact"]
    check(all(len(p) == 2 for p in pairs) and {"Door", "Post"} not in pairs and
          {"Lid", "Door"} not in pairs and {"Lid", "Post"} in pairs,
          f"constraints: no contact between jointed bodies: {pairs}")


def refusals(scene):
    for kind in ("GENERIC", "GENERIC_SPRING", "PISTON"):
        clear(scene, 5)
        crate = base.box("Crate", (0.2, 0.2, 0.2), (0, 0, 0.5))
        post = base.box("Post", (0.2, 0.2, 0.2), (0, 0, 1), kind="PASSIVE")
        constraint("Joint", kind, (0, 0, 0.75), (0, 0, 0), crate, post)
        base.refused(f"a {kind} constraint", "'Joint'", kind, "no counterpart")
    clear(scene, 5)
    base.box("Crate", (0.2, 0.2, 0.2), (0, 0, 0.5))
    constraint("Loose", "HINGE", (0, 0, 1), (0, 0, 0), None, None)
    base.refused("a constraint without its objects", "'Loose'", "HINGE", "two different objects")
    clear(scene, 5)
    crate = base.box("Crate", (0.2, 0.2, 0.2), (0, 0, 0.5))
    post = base.box("Post", (0.2, 0.2, 0.2), (0, 0, 1), kind="PASSIVE")
    constraint("Spin", "MOTOR", (0, 0, 0.75), (0, 0, 0), crate, post).use_motor_ang = True
    base.refused("a MOTOR on its own", "'Spin'", "MOTOR", "HINGE")


def main():
    args = base.arguments()
    os.makedirs(args.out, exist_ok=True)
    base.install(base.addon_zip(args), args.out)
    scene = bpy.context.scene
    pendulum_period(scene, args)
    limits_agree_with_bullet(scene)
    motors_agree_with_bullet(scene)
    breaking_agrees_with_bullet(scene)
    file_says_what_blender_says(scene, args)
    refusals(scene)
    print(f"test_addon_joints: {len(base.failures)} failures")
    sys.stdout.flush()
    os._exit(1 if base.failures else 0)


if __name__ == "__main__":
    base.run(main)
