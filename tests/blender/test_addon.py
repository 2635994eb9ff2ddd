"""tumble for Blender, headless: the add-on's keys equal `tumble run` on the add-on's own scene
file, its export round-trips, and free_bake removes exactly its keys.

    blender -b --factory-startup --python tests/blender/test_addon.py -- \
        --cli build/cli/tumble --out DIRECTORY [--zip build/tumble_blender.zip]

The add-on is installed from the zip scripts/make_blender_addon.sh builds (made here when not
given). tumble's Python package comes from TUMBLE_PYTHON_PATH (and TUMBLE_LIBRARY, a shared
libtumble), as a user would point the add-on at it.

Two scenes built in bpy: (a) a row of 5 dominoes on a big passive box, the first tipped 20
degrees; (b) 3 dice (Euler ZXY, quaternion and axis-angle rotation modes) dropped on a passive
table. For each, the keys must equal the CLI's CSV at every frame within 1e-6 m and 1e-4 degrees:
both run the same file with the same method and frame times, so they differ only by Blender's
single-precision keys (6e-8 m at 1 m, 1e-7 rad: 60x and 10x below the tolerances) and the
rotation-mode conversions (float32 mathutils, about 1e-7 rad). Exit status 0 when every check
holds.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import zipfile

import bpy
import mathutils

try:
    import numpy as np
except ImportError:  # tumble's Python package needs it too: Debian's python3-numpy
    print("test_addon: skipped: Blender's Python has no NumPy (apt-get install python3-numpy)")
    sys.stdout.flush()
    os._exit(77)

FPS = 24
METRES = 1e-6
DEGREES = 1e-4
failures = []


def check(condition, message):
    print(f"test_addon: {'ok' if condition else 'FAIL'}: {message}")
    if not condition:
        failures.append(message)


def arguments():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cli", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--zip")
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return parser.parse_args(argv)


def install(zip_path, out):
    """The add-on as a user installs it: the zip's package, enabled by Blender's add-on
    utilities."""
    import addon_utils

    folder = os.path.join(out, "addons")
    with zipfile.ZipFile(zip_path) as archive:
        archive.extractall(folder)
    sys.path.insert(0, folder)
    module = addon_utils.enable("tumble_blender", default_set=True)
    check(module is not None and hasattr(bpy.ops.tumble, "bake"), "the add-on enables")


def clear(scene, frames):
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    for action in list(bpy.data.actions):
        bpy.data.actions.remove(action)
    if scene.rigidbody_world is None:
        bpy.ops.rigidbody.world_add()
    world = scene.rigidbody_world
    world.enabled = True
    scene.render.fps, scene.render.fps_base = FPS, 1.0
    scene.frame_start, scene.frame_end = 1, frames
    world.point_cache.frame_start, world.point_cache.frame_end = 1, frames
    scene.frame_set(1)


def box(name, size, location, kind="ACTIVE", mode="XYZ", rotation=None, friction=0.5,
        restitution=0.0, mass=1.0):
    bpy.ops.mesh.primitive_cube_add(size=1, location=location)
    obj = bpy.context.object
    obj.name = name
    obj.scale = size
    obj.rotation_mode = mode
    if rotation is not None:
        setattr(obj, {"QUATERNION": "rotation_quaternion",
                      "AXIS_ANGLE": "rotation_axis_angle"}.get(mode, "rotation_euler"), rotation)
    bpy.ops.rigidbody.object_add(type=kind)
    rb = obj.rigid_body
    rb.collision_shape = "BOX"
    rb.mass, rb.friction, rb.restitution = mass, friction, restitution
    return obj


def dominoes(scene):
    """5 dominoes 0.1 x 0.4 x 0.8 m, 0.3 m apart, on a 4 x 4 x 0.2 m passive box whose top is
    z = 0; the first tipped 20 degrees towards the next, its lowest edge 1 mm above the box."""
    clear(scene, 25)
    box("Floor", (4, 4, 0.2), (0.6, 0, -0.1), kind="PASSIVE")
    tilt, t, h = math.radians(20), 0.1, 0.8
    z = t / 2 * math.sin(tilt) + h / 2 * math.cos(tilt) + 1e-3
    box("Domino1", (t, 0.4, h), (0, 0, z), rotation=(0, tilt, 0))
    for i in range(1, 5):
        box(f"Domino{i + 1}", (t, 0.4, h), (0.3 * i, 0, h / 2 + 1e-3))


def dice(scene):
    """3 dice 5 cm, 0.1 kg, dropped from 0.2 to 0.3 m above a 1.2 x 0.8 x 0.75 m table."""
    clear(scene, 20)
    box("Table", (1.2, 0.8, 0.75), (0, 0, 0.375), kind="PASSIVE", restitution=0.5)
    s = (0.05, 0.05, 0.05)
    box("DieEuler", s, (-0.2, 0, 0.95), mode="ZXY", rotation=(0.3, 0.5, 0.7), restitution=0.5,
        mass=0.1)
    q = mathutils.Quaternion((1, 2, 3), 0.9)
    box("DieQuaternion", s, (0, 0.1, 1.0), mode="QUATERNION", rotation=tuple(q), restitution=0.5,
        mass=0.1)
    box("DieAxisAngle", s, (0.2, -0.1, 1.05), mode="AXIS_ANGLE", rotation=(1.2, 0, 1, 1),
        restitution=0.5, mass=0.1)


def solid(add, name, shape, **options):
    add(**options)
    obj = bpy.context.object
    obj.name = name
    bpy.ops.rigidbody.object_add(type="ACTIVE")
    obj.rigid_body.collision_shape = shape
    return obj


def shapes(scene):
    """One body of each other shape, dropped on the floor: sphere, capsule, cylinder, cone and
    convex hull (Suzanne, whose hull's centre of mass is not her origin). The floor is Blender's
    Plane with its default shape (a flat object: always a ground plane)."""
    clear(scene, 10)
    bpy.ops.mesh.primitive_plane_add(size=4, location=(0, 0, 0))
    bpy.context.object.name = "Floor"
    bpy.ops.rigidbody.object_add(type="PASSIVE")
    mesh = bpy.ops.mesh
    solid(mesh.primitive_uv_sphere_add, "Ball", "SPHERE", radius=0.1, location=(-0.6, 0, 0.3))
    solid(mesh.primitive_cylinder_add, "Pill", "CAPSULE", radius=0.05, depth=0.3,
          location=(-0.3, 0, 0.3), rotation=(0.4, 0, 0))
    solid(mesh.primitive_cylinder_add, "Can", "CYLINDER", radius=0.05, depth=0.2,
          location=(0, 0, 0.3))
    solid(mesh.primitive_cone_add, "Cone", "CONE", radius1=0.08, depth=0.2, location=(0.3, 0, 0.3))
    solid(mesh.primitive_monkey_add, "Suzanne", "CONVEX_HULL", size=0.3, location=(0.6, 0, 0.4),
          rotation=(0.2, 0.3, 0))


def shape_sizes(scene, path):
    """Blender sizes its shapes from the object's bounding box (rigidbody.c): a sphere's radius
    half the largest side, a capsule, cylinder or cone the largest of x and y for the diameter
    and z for the whole length; the file must say the same."""
    with open(path) as file:
        bodies = {b["name"]: b["shape"] for b in json.load(file)["bodies"]}
    size = {name: sorted(scene.objects[name].dimensions) for name in ("Ball", "Pill", "Can")}
    dx, dy, dz = scene.objects["Pill"].dimensions
    expected = [(bodies["Ball"]["radius"], size["Ball"][2] / 2),
                (bodies["Pill"]["radius"], max(dx, dy) / 2),
                (bodies["Pill"]["length"] + 2 * bodies["Pill"]["radius"], dz),
                (bodies["Can"]["radius"], 0.05), (bodies["Can"]["length"], 0.2)]
    check(all(abs(a - b) <= 1e-6 for a, b in expected), f"shapes: sizes as Blender's {expected}")
    check(bodies["Suzanne"]["type"] == "mesh" and bodies["Cone"]["type"] == "mesh",
          "shapes: the hull and the cone are meshes")


def read_csv(path):
    rows = {}
    with open(path, newline="") as file:
        for row in csv.DictReader(file):
            rows.setdefault(row["body"], []).append(row)
    return rows


def key_pose(obj, frame):
    """The baked keys at a frame: (location (3,), rotation as a quaternion (4,))."""
    curves = {(fc.data_path, fc.array_index): fc for fc in obj.animation_data.action.fcurves}

    def channel(path, n):
        return [curves[(path, i)].evaluate(frame) for i in range(n)]

    mode = obj.rotation_mode
    if mode == "QUATERNION":
        q = mathutils.Quaternion(channel("rotation_quaternion", 4))
    elif mode == "AXIS_ANGLE":
        angle, *axis = channel("rotation_axis_angle", 4)
        q = mathutils.Quaternion(axis, angle)
    else:
        q = mathutils.Euler(channel("rotation_euler", 3), mode).to_quaternion()
    return np.array(channel("location", 3)), np.array(q, dtype=np.float64)


def angle_between(a, b):
    """The rotation angle between two unit quaternions, degrees (atan2: exact near zero)."""
    a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
    w = abs(a @ b)
    return math.degrees(2 * math.atan2(math.sqrt(max(0.0, 1 - w * w)), w))


def compare_keys(scene, objects, rows, name):
    worst_m = worst_deg = 0.0
    worst = {}
    frames = scene.frame_end - scene.frame_start + 1
    for obj in objects:
        got = rows.get(obj.name, [])
        check(len(got) == frames, f"{name}: {obj.name}: {len(got)} CSV frames, {frames} expected")
        counts = {len(fc.keyframe_points) for fc in obj.animation_data.action.fcurves
                  if fc.data_path != "scale"}
        check(counts == {frames}, f"{name}: {obj.name}: a key at every frame ({counts})")
        for k, row in enumerate(got):
            location, q = key_pose(obj, scene.frame_start + k)
            x = np.array([float(row[c]) for c in ("x", "y", "z")])
            qr = np.array([float(row[c]) for c in ("qw", "qx", "qy", "qz")])
            worst_m = max(worst_m, float(np.max(np.abs(location - x))))
            worst_deg = max(worst_deg, angle_between(q, qr))
            worst[obj.name] = max(worst.get(obj.name, 0.0), angle_between(q, qr))
    print(f"test_addon: {name}: worst degrees per body " +
          ", ".join(f"{k} {v:.1e}" for k, v in worst.items()))
    check(worst_m <= METRES and worst_deg <= DEGREES,
          f"{name}: keys against tumble run: {worst_m:.2e} m, {worst_deg:.2e} degrees at worst")


def moved(obj, rows):
    first, last = rows[obj.name][0], rows[obj.name][-1]
    return math.dist([float(first[c]) for c in "xyz"], [float(last[c]) for c in "xyz"])


def initial_poses(matrices, rows, name):
    """The CSV's first frame (the shape frames tumble started from) is where Blender's own world
    matrices put the objects: their origins and rotations, also for a hull or cone, whose centre
    of mass is not the origin."""
    worst_m = worst_deg = 0.0
    for body, matrix in matrices.items():
        first = rows[body][0]
        worst_m = max(worst_m, math.dist([float(first[c]) for c in "xyz"], matrix.translation))
        q = np.array([float(first[c]) for c in ("qw", "qx", "qy", "qz")])
        worst_deg = max(worst_deg, angle_between(q, np.array(matrix.to_quaternion())))
    check(worst_m <= METRES and worst_deg <= DEGREES,
          f"{name}: tumble starts where Blender has the objects: {worst_m:.1e} m, "
          f"{worst_deg:.1e} degrees")


def bake_and_compare(scene, args, name):
    path = os.path.join(args.out, f"{name}.json")
    check(bpy.ops.tumble.export_scene(filepath=path) == {"FINISHED"}, f"{name}: export_scene")
    active = [o for o in scene.objects if o.rigid_body and o.rigid_body.type == "ACTIVE"]
    before = {o.name: (tuple(o.location), o.rotation_mode) for o in active}
    matrices = {o.name: o.matrix_world.copy() for o in active}
    keep = active[0]  # a key of the user's own, which the bake must leave alone
    keep.keyframe_insert("scale", frame=3)
    check(bpy.ops.tumble.bake() == {"FINISHED"}, f"{name}: bake")
    csv_path = os.path.join(args.out, f"{name}.csv")
    subprocess.run([args.cli, "run", path, "--out", csv_path], check=True,
                   stderr=subprocess.DEVNULL)
    rows = read_csv(csv_path)
    initial_poses(matrices, rows, name)
    compare_keys(scene, active, rows, name)
    print(f"test_addon: {name}: bodies moved " +
          ", ".join(f"{o.name} {moved(o, rows):.3f} m" for o in active))
    free_bake(scene, active, keep, before, name)
    return path


def free_bake(scene, active, keep, before, name):
    check(not scene.rigidbody_world.enabled, f"{name}: the bake turned Blender's simulation off")
    check(bpy.ops.tumble.free_bake() == {"FINISHED"}, f"{name}: free_bake")
    check(scene.rigidbody_world.enabled, f"{name}: free_bake turned Blender's simulation on")
    curves = keep.animation_data.action.fcurves
    left = sorted((fc.data_path, len(fc.keyframe_points)) for fc in curves)
    check(left == [("scale", 1)] * 3, f"{name}: {keep.name}'s own scale keys stay, alone: {left}")
    others = [o.name for o in active if o is not keep and o.animation_data is not None and
              o.animation_data.action is not None]
    check(not others, f"{name}: no action left on the other bodies ({others})")
    check([a.name for a in bpy.data.actions] == [keep.animation_data.action.name],
          f"{name}: the bake's actions are gone ({[a.name for a in bpy.data.actions]})")
    scene.frame_set(scene.frame_end)
    after = {o.name: (tuple(o.location), o.rotation_mode) for o in active}
    check(after == before, f"{name}: the bodies are back where they were")


def rebuild(scene, path):
    """Objects from a scene file the add-on wrote (boxes, a ground plane as a big box under the
    bodies): the friction and restitution are the square roots of the products it wrote, as
    every object of these scenes has the same; damping from the drag, d = 1 - exp(-c / M)."""
    with open(path) as file:
        data = json.load(file)
    fps, duration = data["output"]["fps"], data["output"]["duration"]
    clear(scene, 1 + round(duration * fps))
    material = next(e for e in data["effects"] if e["type"] in ("contact", "ground"))
    f, e = math.sqrt(material["static_friction"]), math.sqrt(material["restitution"])
    drag = {d["body"]: d for d in data["effects"] if d["type"] == "drag"}
    for body in data["bodies"]:
        kind = "ACTIVE" if body.get("motion", "dynamic") == "dynamic" else "PASSIVE"
        obj = box(body["name"], body["shape"]["size"], body["position"], kind=kind,
                  mode="QUATERNION", rotation=body["orientation"], friction=f, restitution=e,
                  mass=body.get("mass", 1.0))
        if body["name"] in drag:
            c = drag[body["name"]]
            obj.rigid_body.linear_damping = 1 - math.exp(-c["linear"] / body["mass"])
            obj.rigid_body.angular_damping = 0.1  # Blender's default: the test scenes keep it
    for ground in (g for g in data["effects"] if g["type"] == "ground"):
        box("Ground", (50, 50, 1), (0, 0, ground["offset"] - 0.5), kind="PASSIVE",
            friction=f, restitution=e)
    g = next((x["g"] for x in data["effects"] if x["type"] == "gravity"), None)
    if g is not None:
        scene.gravity = g


def same(a, b, path="", tolerance=1e-6):
    """Equal JSON up to float formatting (Blender keeps single precision: 1e-6 relative)."""
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k], f"{path}.{k}") for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y, f"{path}[{i}]") for i, (x, y) in
                                        enumerate(zip(a, b)))
    if isinstance(a, float) or isinstance(b, float):
        ok = abs(a - b) <= tolerance * max(1.0, abs(a), abs(b))
    else:
        ok = a == b
    if not ok:
        print(f"test_addon: differs at {path}: {a!r} and {b!r}")
    return ok


def round_trip(scene, path, name):
    rebuild(scene, path)
    again = os.path.join(os.path.dirname(path), f"{name}-again.json")
    check(bpy.ops.tumble.export_scene(filepath=again) == {"FINISHED"}, f"{name}: export again")
    with open(path) as a, open(again) as b:
        first, second = json.load(a), json.load(b)
    first.pop("description"), second.pop("description")  # names the Blender scene
    check(same(first, second), f"{name}: the scene file round-trips through Blender")


def refused(message, *names):
    try:
        bpy.ops.tumble.bake()
        check(False, f"{message}: refused")
    except RuntimeError as error:
        text = str(error).strip()
        check(all(name in text for name in names), f"{message}: refused naming {names}: {text}")


def refusals(scene):
    """A scene tumble refuses is reported naming the object and the value: by the add-on (a
    shape or a constraint type with no counterpart; more in test_addon_joints.py) and by the
    library (two bodies that start inside each other)."""
    clear(scene, 5)
    box("Floor", (4, 4, 0.2), (0, 0, -0.1), kind="PASSIVE")
    box("Crate", (0.2, 0.2, 0.2), (0, 0, 0.5))
    box("Crate.001", (0.2, 0.2, 0.2), (0.05, 0, 0.5))
    refused("bodies inside each other", '"Crate"', '"Crate.001"', "0.15 m inside")
    check(not any(o.animation_data for o in scene.objects), "a refused bake writes no key")
    clear(scene, 5)
    box("Floor", (4, 4, 0.2), (0, 0, -0.1), kind="PASSIVE")
    box("Crate", (0.2, 0.2, 0.2), (0, 0, 0.5))
    bpy.ops.mesh.primitive_cube_add(size=1, location=(1, 0, 0.5))
    bpy.context.object.name = "Lump"
    bpy.ops.rigidbody.object_add(type="ACTIVE")
    bpy.context.object.rigid_body.collision_shape = "COMPOUND"
    refused("a compound shape", "'Lump'", "COMPOUND")
    clear(scene, 5)
    box("Crate", (0.2, 0.2, 0.2), (0, 0, 0.5))
    bpy.ops.object.empty_add(location=(0, 0, 1))
    bpy.context.object.name = "Hinge"
    bpy.ops.rigidbody.constraint_add(type="GENERIC")
    refused("a rigid body constraint tumble has not", "'Hinge'", "GENERIC", "no counterpart")


def passive_bodies(scene, args):
    """Passive bodies: static bodies where the installed tumble has them (then the dominoes again
    with their floor a static box), else a level box under the bodies becomes a ground plane
    and any other passive body (a ramp) is refused, naming it."""
    import tumble
    from tumble_blender import locate

    if locate.supports(tumble, "static"):
        dominoes(scene)
        scene.tumble.passive = "STATIC"
        bake_and_compare(scene, args, "dominoes-static")
        scene.tumble.passive = "AUTO"
        return
    clear(scene, 5)
    box("Ramp", (2, 2, 0.2), (0, 0, -0.1), kind="PASSIVE", rotation=(0.3, 0, 0))
    box("Crate", (0.2, 0.2, 0.2), (0, 0, 0.5))
    refused("a ramp without static bodies", "'Ramp'", "no static bodies")
    scene.tumble.passive = "STATIC"
    refused("static bodies asked of a tumble without them", "no static")
    scene.tumble.passive = "AUTO"


def animated_keys(scene):
    """An Animated passive box becomes a keyframed body whose keys are its animation sampled at
    every frame (read through the add-on's reader: the scene format's keyframed bodies, whatever
    the installed tumble takes). The paddle moves linearly from x = -1 at frame 1 to x = 1 at
    frame 5 and turns 90 degrees about z: key k at t = k / 24 s, x = -1 + k / 2."""
    from tumble_blender.scene_export import read_scene

    clear(scene, 5)
    box("Crate", (0.2, 0.2, 0.2), (0, 0, 0.5))
    paddle = box("Paddle", (0.4, 0.05, 0.3), (-1, 0, 0.15), kind="PASSIVE")
    paddle.rigid_body.kinematic = True
    for frame, x, turn in ((1, -1.0, 0.0), (5, 1.0, math.pi / 2)):
        paddle.location.x, paddle.rotation_euler.z = x, turn
        paddle.keyframe_insert("location", frame=frame)
        paddle.keyframe_insert("rotation_euler", frame=frame)
    for curve in paddle.animation_data.action.fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR"
    plan = read_scene(scene, bpy.context.evaluated_depsgraph_get(), static_supported=True)
    body = next(b for b in plan.scene["bodies"] if b["name"] == "Paddle")
    keys = body["keys"]
    ok = body["motion"] == "keyframed" and len(keys) == 5 and "mass" not in body
    for k, key in enumerate(keys):
        angle = math.pi / 8 * k
        expected = [math.cos(angle / 2), 0, 0, math.sin(angle / 2)]
        ok = ok and abs(key["t"] - k / FPS) < 1e-12
        ok = ok and abs(key["position"][0] - (-1 + k / 2)) < 1e-6
        ok = ok and angle_between(np.array(key["orientation"]), np.array(expected)) < DEGREES
    check(ok, f"an animated passive body is keyframed at every frame: {json.dumps(keys)[:200]}")
    paddle.animation_data_clear()


def missing_package(scene):
    """Without the tumble package the bake says how to install it (nothing else in Blender's
    Python has it here: the test gives it through TUMBLE_PYTHON_PATH)."""
    saved = os.environ.pop("TUMBLE_PYTHON_PATH", None)
    try:
        dice(scene)
        refused("without the tumble package", "not found", "tumble Python path", "pip install")
    finally:
        if saved is not None:
            os.environ["TUMBLE_PYTHON_PATH"] = saved


def default_shape_floor(scene):
    """Without static bodies, a passive box mesh with Blender's default shape (Convex Hull) is a
    box too, and becomes the ground plane at its top face."""
    from tumble_blender.scene_export import read_scene

    clear(scene, 5)
    floor = box("Floor", (3, 3, 0.5), (0, 0, -0.25), kind="PASSIVE")
    floor.rigid_body.collision_shape = "CONVEX_HULL"
    box("Crate", (0.2, 0.2, 0.2), (0, 0, 0.5))
    plan = read_scene(scene, bpy.context.evaluated_depsgraph_get(), static_supported=False)
    grounds = [e for e in plan.scene["effects"] if e["type"] == "ground"]
    check(len(grounds) == 1 and abs(grounds[0]["offset"]) < 1e-6 and
          [b["name"] for b in plan.scene["bodies"]] == ["Crate"],
          f"a hull-shaped passive box is the ground plane at its top: {grounds}")


def addon_zip(args):
    """The zip given, else one scripts/make_blender_addon.sh makes now."""
    if args.zip is not None:
        return args.zip
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    return subprocess.run([os.path.join(root, "scripts", "make_blender_addon.sh"),
                           tempfile.mkdtemp()], check=True, capture_output=True,
                          text=True).stdout.strip()


def main():
    args = arguments()
    os.makedirs(args.out, exist_ok=True)
    install(addon_zip(args), args.out)
    scene = bpy.context.scene
    missing_package(scene)
    for name, build in (("dominoes", dominoes), ("dice", dice)):
        build(scene)
        path = bake_and_compare(scene, args, name)
        round_trip(scene, path, name)
    shapes(scene)
    shape_sizes(scene, bake_and_compare(scene, args, "shapes"))
    refusals(scene)
    passive_bodies(scene, args)
    animated_keys(scene)
    default_shape_floor(scene)
    print(f"test_addon: {len(failures)} failures")
    sys.stdout.flush()
    os._exit(1 if failures else 0)


def run(entry):
    try:
        entry()
    except Exception:  # Blender keeps running after a script's exception: fail the test instead
        import traceback

        traceback.print_exc()
        sys.stdout.flush()
        os._exit(1)


if __name__ == "__main__":  # imported by test_addon_joints.py for its helpers
    run(main)
