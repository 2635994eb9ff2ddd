"""docs/scene-format.schema.json against the loader (the scene_schema ctest; scripts/test.sh runs
it with the jsonschema package from PyPI).

    python3 tests/scene_schema.py --tumble path/to/tumble [--source repository]

1. The schema is a valid JSON Schema (draft 2020-12, checked against the meta-schema).
2. Every key the loader accepts is in the schema, and the schema has no key the loader does not
   accept (but for PENDING, keys other branches add). The loader's keys are read from its C
   sources, src/io/scene_file*.c: every list of allowed keys is a `static const char *const
   NAME[] = {"a", "b", ..., NULL}` passed to tb__json_object(), the one function that refuses
   unknown keys; the shape types' own keys are the `shape_types` table in scene_file_shapes.c.
   KEY_LISTS says which schema object each list is; a list it does not name fails the test.
   Likewise the value lists: the methods (src/ode/methods.c's table), the effect types
   (`strcmp(type, "...")` in scene_file_effects.c) and the shape types.
3. Which integrator settings each method takes: for every setting and every method, the
   loader's verdict (`tumble check` on a one-body scene) equals the schema's.
4. Every scene file the loader accepts (examples/scenes, tests/scenes, the scene loader's fuzz
   seeds) validates; every example scene is accepted by both.
5. INVALID: scenes the loader refuses (each checked with `tumble check`) that the schema
   refuses too. What a schema cannot say (a unit quaternion, a body name that exists, the
   triangle inequality of moments, the frame count, a closed mesh, a duplicate JSON key) is
   listed in docs/scene-format.md, "JSON Schema"."""

import argparse
import copy
import json
import pathlib
import re
import subprocess
import sys
import tempfile

try:
    import jsonschema
except ImportError:
    print("scene_schema: needs the jsonschema package (pip install jsonschema)", file=sys.stderr)
    sys.exit(77)  # ctest's SKIP_RETURN_CODE

SHAPES = ["box", "sphere", "cylinder", "capsule", "ellipsoid", "mesh", "points"]
EFFECTS = ["gravity", "drag", "spring", "force", "torque", "ground", "contact"]
# (file, function, array) -> the schema objects ($defs names; "" the top level) whose keys,
# together, are that list.
KEY_LISTS = {
    ("scene_file.c", "load_document", "keys"): [""],
    ("scene_file_bodies.c", "load_body", "keys"): ["body"],
    ("scene_file_bodies.c", "load_contact", "keys"): ["contact_points"],
    ("scene_file_bodies.c", "load_contact_point", "point_keys"): ["contact_point"],
    ("scene_file_shapes.c", "tb__load_shape_object", "keys"): [f"shape_{s}" for s in SHAPES],
    ("scene_file_shapes.c", "tb__load_shape_object", "piece_keys"): [f"piece_{s}"
                                                                       for s in SHAPES[:-1]],
    ("scene_file_shapes.c", "load_points", "keys"): ["point_mass"],
    ("scene_file_effects.c", "load_gravity", "keys"): ["effect_gravity"],
    ("scene_file_effects.c", "load_drag", "keys"): ["effect_drag"],
    ("scene_file_effects.c", "load_spring", "keys"): ["effect_spring"],
    ("scene_file_effects.c", "load_force_or_torque", "force_keys"): ["effect_force"],
    ("scene_file_effects.c", "load_force_or_torque", "torque_keys"): ["effect_torque"],
    ("scene_file_effects.c", "load_ground", "keys"): ["effect_ground"],
    ("scene_file_effects.c", "load_contact", "keys"): ["effect_contact"],
    ("scene_file_run.c", "tb__load_integrator", "keys"): ["integrator"],
    ("scene_file_run.c", "tb__load_output", "keys"): ["output"],
    ("scene_file_keys.c", "load_key", "allowed"): ["body_key"],
    ("scene_file_joints.c", "load_joint", "axis_keys"): ["joint_hinge", "joint_slider"],
    ("scene_file_joints.c", "load_joint", "no_axis_keys"): ["joint_ball", "joint_fixed"],
    ("scene_file_joints.c", "load_joint_motor", "hinge_keys"): ["joint_motor_hinge"],
    ("scene_file_joints.c", "load_joint_motor", "slider_keys"): ["joint_motor_slider"],
    ("scene_file_joints.c", "load_joint_soft", "keys"): ["joint_soft"],
}
# Keys the schema has before this branch's loader reads them (added on other branches): none now.
PENDING: set = set()

BALL = {"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1,
        "position": [0, 0, 1]}
KEY = {"t": 0, "position": [0, 0, 1], "orientation": [1, 0, 0, 0]}
SETTINGS = {"dt": 0.01, "allow_unstable": True, "rtol": 1e-6, "atol": 0, "max_steps": 1000,
            "max_order": 2, "linear_solver": "auto"}


def scene(**top):
    return {"bodies": [copy.deepcopy(BALL)], **top}


def body(**changes):
    b = {**copy.deepcopy(BALL), **changes}
    return {"bodies": [{k: v for k, v in b.items() if v is not None}]}


# Each is refused by the loader (checked) and must be refused by the schema.
INVALID = {
    "unknown top-level key": scene(gravity=[0, 0, -9.81]),
    "no bodies": {"effects": []},
    "empty bodies": {"bodies": []},
    "body without a name": body(name=None),
    "body name not a string": body(name=3),
    "negative mass": body(mass=-1),
    "mass above TB_MASS_MAX": body(mass=1e101),
    "mass and density": body(density=1000),
    "shape without mass or density": body(mass=None),
    "shape with inertia": body(inertia=[1, 1, 1]),
    "no shape and no inertia": body(shape=None),
    "density without a shape": body(shape=None, inertia=[1, 1, 1], density=1000),
    "radius on a box": body(shape={"type": "box", "size": [1, 1, 1], "radius": 1}),
    "unknown shape type": body(shape={"type": "cone", "radius": 1}),
    "box size of two numbers": body(shape={"type": "box", "size": [1, 1]}),
    "sphere of zero radius": body(shape={"type": "sphere", "radius": 0}),
    "points shape with a mass": body(shape={"type": "points",
                                           "points": [{"position": [0, 0, 0], "mass": 1}]}),
    "empty list of pieces": body(shape=[]),
    "points as a piece": body(shape=[{"type": "points",
                                      "points": [{"position": [0, 0, 0], "mass": 1}]}]),
    "piece with an unknown key": body(shape=[{"type": "sphere", "radius": 1, "offset": [0, 0, 1]}]),
    "piece orientation of three numbers": body(shape=[{"type": "sphere", "radius": 1,
                                                       "orientation": [1, 0, 0]}]),
    "mesh with file and vertices": body(shape={"type": "mesh", "file": "a.obj",
                                              "vertices": [[0, 0, 0]],
                                              "triangles": [[0, 0, 0]]}),
    "both angular velocities": body(angular_velocity=[1, 0, 0],
                                    angular_velocity_body=[1, 0, 0]),
    "orientation of three numbers": body(orientation=[1, 0, 0]),
    "contact true": body(contact=True),
    "contact point of negative radius": body(
        contact={"points": [{"position": [0, 0, 0], "radius": -1}]}),
    "contact support 0": body(contact={"points": [{"position": [0, 0, 0]}], "support": 0}),
    "unknown effect type": scene(effects=[{"type": "wind"}]),
    "effect without a type": scene(effects=[{"g": [0, 0, -9.81]}]),
    "key of another effect": scene(effects=[{"type": "gravity", "body": "ball"}]),
    "spring without stiffness": scene(effects=[{"type": "spring", "body_a": "ball",
                                                "point_b": [0, 0, 2]}]),
    "spring to the world without point_b": scene(effects=[{"type": "spring", "body_a": "ball",
                                                           "stiffness": 10}]),
    "force in a local frame": scene(effects=[{"type": "force", "body": "ball",
                                              "force": [1, 0, 0], "frame": "local"}]),
    "ground restitution 1.5": scene(effects=[{"type": "ground", "restitution": 1.5}]),
    "negative friction": scene(effects=[{"type": "ground", "static_friction": -0.1}]),
    "contact listing a body twice": scene(effects=[{"type": "contact",
                                                    "bodies": ["ball", "ball"]}]),
    "unknown method": scene(integrator={"method": "rk5"}),
    "dt for cvode-bdf": scene(integrator={"method": "cvode-bdf", "dt": 0.01}),
    "rtol for the default rk4": scene(integrator={"rtol": 1e-6}),
    "rtol of 1": scene(integrator={"method": "cvode-adams", "rtol": 1}),
    "max_order 6 for BDF": scene(integrator={"method": "cvode-bdf", "max_order": 6}),
    "max_steps 1.5": scene(integrator={"method": "cvode-bdf", "max_steps": 1.5}),
    "allow_unstable as a string": scene(integrator={"allow_unstable": "yes"}),
    "unknown linear solver": scene(integrator={"method": "cvode-bdf", "linear_solver": "lu"}),
    "fps 0": scene(output={"fps": 0}),
    "negative duration": scene(output={"duration": -1}),
    "unknown output key": scene(output={"format": "csv"}),
    "keys on a dynamic body": body(keys=[KEY]),
    "interpolation on a static body": body(motion="static", mass=None, interpolation="linear"),
    "contact points on a static body": body(motion="static", mass=None,
                                            contact={"points": [{"position": [0, 0, 0]}]}),
    "contact points on a keyframed body": body(motion="keyframed", mass=None, position=None,
                                               keys=[KEY],
                                               contact={"points": [{"position": [0, 0, 0]}]}),
    "keyframed without keys": body(motion="keyframed", mass=None, position=None),
    "keyframed with a position": body(motion="keyframed", mass=None, keys=[KEY]),
    "keyframed with an orientation": body(motion="keyframed", mass=None, position=None,
                                          orientation=[1, 0, 0, 0], keys=[KEY]),
    "keyframed with a velocity": body(motion="keyframed", mass=None, position=None,
                                      velocity=[1, 0, 0], keys=[KEY]),
    "keyframed with an angular velocity": body(motion="keyframed", mass=None, position=None,
                                               angular_velocity_body=[0, 0, 1], keys=[KEY]),
    "keyframed, unknown interpolation": body(motion="keyframed", mass=None, position=None,
                                             keys=[KEY], interpolation="spline"),
    "unknown joint type": scene(joints=[{"type": "rope", "bodies": ["ball"],
                                         "anchor": [0, 0, 2]}]),
    "joint of three bodies": scene(joints=[{"type": "ball", "bodies": ["ball"] * 3,
                                            "anchor": [0, 0, 2]}]),
    "joint without an anchor": scene(joints=[{"type": "ball", "bodies": ["ball"]}]),
    "hinge without an axis": scene(joints=[{"type": "hinge", "bodies": ["ball"],
                                            "anchor": [0, 0, 2]}]),
    "hinge of zero axis": scene(joints=[{"type": "hinge", "bodies": ["ball"],
                                         "anchor": [0, 0, 2], "axis": [0, 0, 0]}]),
    "axis on a ball joint": scene(joints=[{"type": "ball", "bodies": ["ball"],
                                           "anchor": [0, 0, 2], "axis": [0, 0, 1]}]),
    "hinge motor with a force": scene(joints=[{"type": "hinge", "bodies": ["ball"],
                                               "anchor": [0, 0, 2], "axis": [0, 0, 1],
                                               "motor": {"speed": 1, "max_force": 1}}]),
    "motor with speed and target": scene(joints=[{"type": "slider", "bodies": ["ball"],
                                                  "anchor": [0, 0, 2], "axis": [0, 0, 1],
                                                  "motor": {"speed": 1, "target": 1,
                                                            "max_force": 1}}]),
    "restitution without limits": scene(joints=[{"type": "hinge", "bodies": ["ball"],
                                                 "anchor": [0, 0, 2], "axis": [0, 0, 1],
                                                 "restitution": 0.5}]),
    "soft of zero frequency": scene(joints=[{"type": "ball", "bodies": ["ball"],
                                             "anchor": [0, 0, 2], "soft": {"frequency": 0}}]),
    "break force 0": scene(joints=[{"type": "fixed", "bodies": ["ball"], "anchor": [0, 0, 2],
                                    "break_force": 0}]),
}


def c_functions(text):
    """(offset, name) of each function definition (its name at column 0's line)."""
    pattern = re.compile(r"^(?:static\s+)?(?:const\s+)?[A-Za-z_][\w \*]*?\b(\w+)\(", re.M)
    return [(m.start(), m.group(1)) for m in pattern.finditer(text)
            if not text[m.end():text.find(")", m.end()) + 2].rstrip().endswith(";")]


def function_at(functions, offset):
    name = None
    for start, candidate in functions:
        if start <= offset:
            name = candidate
    return name


def loader_key_lists(source):
    """{(file, function, array): [keys]} for every key list passed to tb__json_object, and the
    shape types' own keys {type: [keys]}."""
    lists, shape_keys = {}, {}
    array = re.compile(r"static const char \*const (\w+)\[\] = \{(.*?)\};", re.S)
    call = re.compile(r"tb__json_object\(([^;]*?)\);", re.S)
    for path in sorted((source / "src" / "io").glob("scene_file*.c")):
        text = path.read_text()
        functions = c_functions(text)
        arrays = {(function_at(functions, m.start()), m.group(1)): re.findall(r'"([^"]*)"',
                                                                               m.group(2))
                  for m in array.finditer(text)}
        for m in call.finditer(text):
            function = function_at(functions, m.start())
            last_argument = m.group(1).rsplit(",", 1)[-1]
            for name in re.findall(r"\b\w+\b", last_argument):
                if (function, name) in arrays:
                    lists[(path.name, function, name)] = arrays[(function, name)]
        table = re.search(r"shape_types\[\] = \{(.*?)\n\};", text, re.S)
        if table:
            for m in re.finditer(r'\{"(\w+)", \{([^}]*)\}\}', table.group(1)):
                shape_keys[m.group(1)] = ["type"] + re.findall(r'"(\w+)"', m.group(2))
    return lists, shape_keys


def schema_keys(schema, name):
    target = schema if name == "" else schema["$defs"][name]
    assert target.get("additionalProperties") is False, f"{name or 'top level'}: open to any key"
    return set(target["properties"])


def check_keys(schema, source, failures):
    lists, shape_keys = loader_key_lists(source)
    assert len(lists) >= len(KEY_LISTS) // 2, f"found only {len(lists)} key lists: parser broken?"
    for where, keys in sorted(lists.items()):
        if where not in KEY_LISTS:
            failures.append(f"{where}: a key list this test does not know ({keys}): put its keys "
                            f"in the schema and name the schema object in KEY_LISTS")
            continue
        names = KEY_LISTS[where]
        in_schema = set().union(*(schema_keys(schema, n) for n in names))
        pending = {k for n, k in PENDING if n in names}
        missing = set(keys) - in_schema
        extra = in_schema - set(keys) - pending
        if missing or extra:
            failures.append(f"{where} -> {names}: not in the schema {sorted(missing)}, "
                            f"not in the loader {sorted(extra)}")
    for where in KEY_LISTS.keys() - lists.keys():
        failures.append(f"{where}: no such key list in the loader any more")
    closed = {n for n, d in schema["$defs"].items() if d.get("additionalProperties") is False}
    unmapped = closed - {n for names in KEY_LISTS.values() for n in names}
    if unmapped:
        failures.append(f"schema objects no loader key list backs: {sorted(unmapped)}")
    for shape, keys in shape_keys.items():
        if f"shape_{shape}" not in schema["$defs"]:
            failures.append(f"shape type {shape}: not in the schema")
        elif schema_keys(schema, f"shape_{shape}") != set(keys):
            failures.append(f"shape {shape}: loader {sorted(keys)}, schema "
                            f"{sorted(schema_keys(schema, f'shape_{shape}'))}")
    return shape_keys


def check_value_lists(schema, source, shape_keys, failures):
    methods = re.findall(r'\[TB_METHOD_\w+\]\s*=\s*\{(?:\{|\.info\s*=\s*\{\s*\.name\s*=\s*)"([\w-]+)"',
                         (source / "src" / "ode" / "methods.c").read_text())
    effects = set(re.findall(r'strcmp\(type, "(\w+)"\)',
                             (source / "src" / "io" / "scene_file_effects.c").read_text()))
    defs = schema["$defs"]
    for what, loader, in_schema in (
            ("methods", set(methods), set(defs["integrator"]["properties"]["method"]["enum"])),
            ("effect types", effects, set(defs["effect"]["properties"]["type"]["enum"])),
            ("shape types", set(shape_keys), set(defs["shape"]["properties"]["type"]["enum"]))):
        if not loader or loader != in_schema:
            failures.append(f"{what}: loader {sorted(loader)}, schema {sorted(in_schema)}")
    return methods


class Loader:
    """`tumble check` on a scene written to a file: True if accepted."""

    def __init__(self, tumble, directory):
        self.tumble, self.directory, self.count = tumble, pathlib.Path(directory), 0

    def accepts_file(self, path):
        run = subprocess.run([self.tumble, "check", str(path)], capture_output=True, text=True,
                             timeout=60)
        if run.returncode not in (0, 2):
            raise RuntimeError(f"tumble check {path}: exit {run.returncode}\n{run.stderr}")
        return run.returncode == 0, run.stderr.strip()

    def accepts(self, document):
        self.count += 1
        path = self.directory / f"scene_{self.count}.json"
        path.write_text(json.dumps(document))
        return self.accepts_file(path)


def check_settings(validator, loader, methods, failures):
    for method in methods:
        for key, value in SETTINGS.items():
            document = scene(integrator={"method": method, key: value})
            by_loader, message = loader.accepts(document)
            by_schema = validator.is_valid(document)
            if by_loader != by_schema:
                failures.append(f"integrator {{method: {method}, {key}: {value}}}: loader "
                                f"{'accepts' if by_loader else 'refuses'} ({message}), schema "
                                f"{'accepts' if by_schema else 'refuses'}")


def check_files(validator, loader, source, failures):
    examples = sorted((source / "examples" / "scenes").glob("*.json"))
    others = sorted([*(source / "tests" / "scenes").rglob("*.json"),
                     *(source / "fuzz" / "corpus" / "scene_loader").iterdir(),
                     *(source / "fuzz" / "regressions" / "scene_loader").iterdir()])
    accepted = refused_both = refused_loader_only = 0
    for path in examples + others:
        by_loader, message = loader.accepts_file(path)
        try:
            document = json.loads(path.read_text())
            errors = [e.message for e in validator.iter_errors(document)]
        except (ValueError, UnicodeDecodeError):
            errors = ["not JSON"]
        if path in examples and not by_loader:
            failures.append(f"{path}: an example the loader refuses: {message}")
        if by_loader and errors:
            failures.append(f"{path}: the loader accepts it, the schema refuses: {errors[0]}")
        accepted += by_loader
        refused_both += not by_loader and bool(errors)
        if not by_loader and not errors:
            refused_loader_only += 1
            print(f"scene_schema: {path.name}: refused by the loader only ({message})")
    print(f"scene_schema: {len(examples) + len(others)} scene files: {accepted} accepted by "
          f"both, {refused_both} refused by both, {refused_loader_only} by the loader only")


def check_invalid(validator, loader, failures):
    for what, document in INVALID.items():
        by_loader, message = loader.accepts(document)
        if by_loader:
            failures.append(f"invalid case '{what}': the loader accepts it")
        if validator.is_valid(document):
            failures.append(f"invalid case '{what}': the schema accepts it (loader: {message})")
    print(f"scene_schema: {len(INVALID)} invalid scenes refused by the loader and the schema")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--tumble", required=True)
    parser.add_argument("--source", default=pathlib.Path(__file__).resolve().parents[1],
                        type=pathlib.Path)
    args = parser.parse_args()
    schema = json.loads((args.source / "docs" / "scene-format.schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    failures = []
    shape_keys = check_keys(schema, args.source, failures)
    methods = check_value_lists(schema, args.source, shape_keys, failures)
    with tempfile.TemporaryDirectory() as directory:
        loader = Loader(args.tumble, directory)
        check_settings(validator, loader, methods, failures)
        check_files(validator, loader, args.source, failures)
        check_invalid(validator, loader, failures)
    for failure in failures:
        print(f"scene_schema: FAIL: {failure}", file=sys.stderr)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
