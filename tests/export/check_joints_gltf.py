"""The joints drawn in a glTF export (tumble run --out FILE.glb), read back from the file alone
(its JSON and binary chunks, with the standard library: no glTF package needed).

    check_joints_gltf.py TUMBLE WORKDIR SCENE.json

SCENE is examples/scenes/double_pendulum.json: rod1 (1 m, centre at x = 0.5 m) hinged to the
world at the origin, rod2 hinged to rod1's far end. Each joint is a node named "joint J (type)",
a child of its first body's node (so it moves with it), with extras.tumble_joint naming its
index, type and bodies. Evaluated with its parent's keys (linear rotation keys: each key is the
frame's pose), at every frame:
  * joint 0's marker (on rod1) stays at the origin, where the hinge holds rod1;
  * joint 1's marker (on rod2) stays on rod1's far end, the point (0.5, 0, 0) of rod1's frame.
Both to 1e-6 m: the file stores 32-bit floats (positions of about 1 m to 6e-8, quaternions to
6e-8 a component, so about 3e-7 m at 2 m), and the joints themselves hold to 1e-15 m."""

import json
import math
import os
import struct
import subprocess
import sys

tumble, work, scene = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
path = os.path.join(work, "double_pendulum.glb")
subprocess.run([tumble, "run", scene, "--out", path, "--rotation", "linear", "--duration", "3"],
               check=True, stderr=subprocess.DEVNULL)
with open(path, "rb") as f:
    data = f.read()
magic, version, _ = struct.unpack_from("<4sII", data, 0)
assert magic == b"glTF" and version == 2
json_length, _ = struct.unpack_from("<II", data, 12)
gltf = json.loads(data[20:20 + json_length])
blob_start = 20 + json_length + 8
COMPONENTS = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}


def accessor(index):
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    n = COMPONENTS[a["type"]]
    start = blob_start + view.get("byteOffset", 0) + a.get("byteOffset", 0)
    values = struct.unpack_from(f"<{a['count'] * n}f", data, start)
    return [values[k * n:(k + 1) * n] for k in range(a["count"])]


nodes = gltf["nodes"]
by_name = {node["name"]: k for k, node in enumerate(nodes)}
joints = [k for k, node in enumerate(nodes) if "tumble_joint" in node.get("extras", {})]
assert [nodes[k]["name"] for k in joints] == ["joint 0 (hinge)", "joint 1 (hinge)"], joints
assert nodes[joints[0]]["extras"]["tumble_joint"] == {"index": 0, "type": "hinge",
                                                      "bodies": ["rod1", "world"]}
assert nodes[joints[1]]["extras"]["tumble_joint"]["bodies"] == ["rod2", "rod1"]
assert joints[0] in nodes[by_name["rod1"]]["children"]
assert joints[1] in nodes[by_name["rod2"]]["children"]
assert "mesh" in nodes[joints[0]]  # drawn: a small sphere

keys = {}  # node -> {"translation": [...], "rotation": [...]}
animation = gltf["animations"][0]
for channel in animation["channels"]:
    sampler = animation["samplers"][channel["sampler"]]
    assert sampler["interpolation"] == "LINEAR"
    keys.setdefault(channel["target"]["node"], {})[channel["target"]["path"]] = \
        accessor(sampler["output"])


def rotate(q, v):  # q = (x, y, z, w), glTF's order
    x, y, z, w = q
    u = (x, y, z)
    t = [2 * (u[1] * v[2] - u[2] * v[1]), 2 * (u[2] * v[0] - u[0] * v[2]),
         2 * (u[0] * v[1] - u[1] * v[0])]
    return [v[i] + w * t[i] + (u[(i + 1) % 3] * t[(i + 2) % 3] - u[(i + 2) % 3] * t[(i + 1) % 3])
            for i in range(3)]


def world(node, frame, local):
    """A point of node's frame in tumble's world (z up: the root's turn left out)."""
    pose = keys[node]
    turned = rotate(pose["rotation"][frame], local)
    return [pose["translation"][frame][i] + turned[i] for i in range(3)]


rod1, rod2 = by_name["rod1"], by_name["rod2"]
frames = len(keys[rod1]["translation"])
assert frames == 181, frames  # 3 s at 60 fps
worst = 0.0
for k in range(frames):
    on_world = world(rod1, k, nodes[joints[0]]["translation"])
    on_rod2 = world(rod2, k, nodes[joints[1]]["translation"])
    rod1_end = world(rod1, k, [0.5, 0.0, 0.0])
    worst = max(worst, math.dist(on_world, [0, 0, 0]), math.dist(on_rod2, rod1_end))
assert worst < 1e-6, worst
print(f"check_joints_gltf: the markers stay on their joints to {worst:.2g} m over {frames} frames")
