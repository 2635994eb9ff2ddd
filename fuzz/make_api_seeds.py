#!/usr/bin/env python3
"""Writes the hand-made seed inputs of the C-API fuzz target into fuzz/corpus/api/, and the
hand-made regression inputs of findings whose fuzzer-found reproducer no longer reads as the
same calls into fuzz/regressions/api/.

Each seed is a small program in the byte encoding fuzz_api.c reads (one byte a choice; see
operate() and the fuzz_op_* functions): a sphere or a box under gravity with an integrator of
each method advanced a second, a spring pair, a box on a ground plane, a run with a frame
callback. They give the fuzzer complete scenes to mutate from. Rerun after changing the
encoding: python3 fuzz/make_api_seeds.py
"""
import os
import struct

KEEP = 0xFF  # maybe()/maybe_vector(): >= 64 keeps the default
OP_BODY, OP_EFFECT, OP_CONTACT, OP_STATE, OP_MASS, OP_INTEGRATOR, OP_ADVANCE, OP_RUN = 0, 2, 4, 5, 6, 7, 8, 10


def size(value_tenths):
    """fuzz_size: a byte below 160 is 0.1 + (byte % 32) / 10."""
    return bytes([value_tenths - 1])


def sphere_body(kilograms_tenths=10, radius_tenths=5, name=0):
    # kind 0 sphere, mode 0 given, value, 3 sizes, name byte, 4 maybe_vectors kept
    return bytes([OP_BODY, 0, 0]) + size(kilograms_tenths) + size(radius_tenths) * 3 + \
        bytes([name, KEEP, KEEP, KEEP, KEEP])


def box_body(position_z_byte=None):
    body = bytes([OP_BODY, 1, 0]) + size(20) + size(10) + size(5) + size(3) + bytes([0])
    if position_z_byte is None:
        return body + bytes([KEEP, KEEP, KEEP, KEEP])
    # position from three fuzz_double bytes (selector < 64: (b & 63) / 8 - 4)
    return body + bytes([0, 32, 32, position_z_byte, KEEP, KEEP, KEEP])


def gravity():
    return bytes([OP_EFFECT, 0, KEEP])


def integrator(method, max_steps=255, slot=0):
    # slot, method, 5 kept doubles, max_steps (8 bytes, % 500 + 1), options, selector 0x20
    return bytes([OP_INTEGRATOR, slot, method, KEEP, KEEP, KEEP, KEEP, KEEP]) + \
        struct.pack(">Q", max_steps - 1) + bytes([0, 0x20])


def advance(slot=0, eighths=8):
    return bytes([OP_ADVANCE, slot, 0, 0, eighths])


def spring(body_a=0, body_b=1):
    # kind 4: body_a id byte, world-or-body byte (odd: world), body_b id, two kept points,
    # stiffness size, kept damping and rest length
    return bytes([OP_EFFECT, 4, body_a, 0, body_b, KEEP, KEEP]) + size(20) + bytes([KEEP, KEEP])


def ground():
    return bytes([OP_EFFECT, 5] + [KEEP] * 9)


def box_contacts(body=0):
    # source 1 (box generator), 3 sizes, capacity 8, body id, support 4
    return bytes([OP_CONTACT, 1]) + size(10) + size(10) + size(10) + bytes([8, body, 4])


def run(method, frame_kind=0, at_frame=3):
    # integrator settings, fps byte (10 + n), duration byte (n / 4), kept fps and duration,
    # frame kind, frame, callback byte
    return bytes([OP_RUN, method, KEEP, KEEP, KEEP, KEEP, KEEP]) + struct.pack(">Q", 254) + \
        bytes([0, 20, 4, KEEP, KEEP, frame_kind, at_frame, 0xFF])


SCENE = bytes([0])  # create_scene: default capacities, renormalisation on
SEEDS = {
    "sphere_gravity_euler": SCENE + sphere_body() + gravity() + integrator(0) + advance(),
    "sphere_gravity_midpoint": SCENE + sphere_body() + gravity() + integrator(1) + advance(),
    "sphere_gravity_rk4": SCENE + sphere_body() + gravity() + integrator(2) + advance(),
    "sphere_gravity_adams": SCENE + sphere_body() + gravity() + integrator(3) + advance(),
    "sphere_gravity_bdf": SCENE + sphere_body() + gravity() + integrator(4) + advance(),
    "spring_pair_bdf": SCENE + sphere_body() + sphere_body(name=200) + spring() +
    integrator(4) + advance(),
    "box_on_ground_rk4": SCENE + box_body() + box_contacts() + ground() + gravity() +
    integrator(2) + advance(eighths=4),
    "run_rk4_cancel": SCENE + sphere_body() + gravity() + run(2, frame_kind=1),
    "run_adams_add_body": SCENE + sphere_body() + gravity() + run(3, frame_kind=2),
    "run_bdf_add_ground": SCENE + box_body() + box_contacts() + gravity() + run(4, frame_kind=3),
}

def null_arguments(which):
    """operate() 11, an even byte: fuzz_op_null_arguments, probe `which` (0-23); every probe
    ends with tb_effect_add_force/_torque given NULL and the derivative given a NULL state."""
    return bytes([11, 0, which])


def user_force_on_missing_body():
    """A user effect (kind 0: tb_effect_add_force) on body id = body count (232 % 8 == 0)."""
    one = 40  # fuzz_double: a byte below 64 is (b & 63) / 8 - 4, so 40 is 1.0
    return bytes([OP_EFFECT, 6, 0, 232, one, one, one, one, one, one, 0])


def raw_double(value):
    """fuzz_double: a selector byte >= 192, then the double's 8 bytes, most significant first."""
    return bytes([0xC0]) + struct.pack(">d", value)


def far_spring_to_world(distance):
    """A spring (kind 4) from body 0's point (0, distance, 0) to the world origin, 2.1 N/m."""
    return bytes([OP_EFFECT, 4, 0, 1, 0, 32]) + raw_double(distance) + bytes([32, KEEP]) + \
        size(20) + bytes([KEEP, KEEP])


def read_outs():
    """operate() 11, an odd byte: fuzz_op_read (body 0, then tb_scene_max_stable_step)."""
    return bytes([11, 1])


def sphere_at_velocity(kilograms_tenths, velocity):
    """A sphere of radius 0.5 m given its mass, at the velocity (0, velocity, 0)."""
    return bytes([OP_BODY, 0, 0]) + size(kilograms_tenths) + size(5) * 3 + \
        bytes([0, KEEP, KEEP, 0, 32]) + raw_double(velocity) + bytes([32, KEEP])


REGRESSIONS = {
    # F9: a spring point 6e246 m from the centre of mass: the guard's |r|^2 / I overflowed and
    # tb_scene_max_stable_step answered OK with dt = 0 (the spring is now refused).
    "F9-far-spring-point-stable-step-zero": SCENE + sphere_body() +
    far_spring_to_world(6.3498042097568784e246) + read_outs(),
    # F15: 0.9 kg at -1.797e308 m/s: P = M v is finite, dx/dt = P / M is not (now refused).
    "F15-velocity-rate-overflows": SCENE + sphere_at_velocity(9, -1.7976931348623157e308),
    # F3: tb_scene_derivative / tb_scene_normalize_quaternions given a NULL state, with no body
    # (returned success) and with one (dereferenced NULL).
    "F3-null-state-no-body": SCENE + null_arguments(13),
    "F3-null-state-one-body": SCENE + sphere_body() + null_arguments(13),
    # F4: tb_effect_add_force with a NULL force (UB: NULL + 16), and with an id past the body
    # count from inside a user effect while RK4 steps.
    "F4-add-force-null": SCENE + sphere_body() + null_arguments(14),
    "F4-add-force-missing-body": SCENE + sphere_body() + user_force_on_missing_body() +
    integrator(2) + advance(),
}

folder = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "api")
os.makedirs(folder, exist_ok=True)
for name, data in SEEDS.items():
    with open(os.path.join(folder, name), "wb") as out:
        out.write(data)

folder = os.path.join(os.path.dirname(os.path.abspath(__file__)), "regressions", "api")
os.makedirs(folder, exist_ok=True)
for name, data in REGRESSIONS.items():
    with open(os.path.join(folder, name), "wb") as out:
        out.write(data)
