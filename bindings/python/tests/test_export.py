"""Frames to files through the C library's writer: the .npz holds the frames in memory bit
for bit, the CSV reads back exactly, glTF is a GLB with a node per body; bad arguments are
refused with the library's or Python's errors."""

import csv
import json
import struct

import numpy as np
import pytest

import tumble


@pytest.fixture
def frames(scenes):
    return tumble.Scene.from_file(scenes / "spring_chain.json").run(duration=1.0)


def test_npz_holds_the_frames_bit_for_bit(frames, tmp_path):
    frames.to_npz(tmp_path / "chain.npz")
    with np.load(tmp_path / "chain.npz") as npz:
        for key in ("t", "position", "orientation", "velocity", "angular_velocity"):
            # the 64-bit patterns, so not even -0.0 against 0.0 passes
            assert np.array_equal(npz[key].view(np.uint64),
                                  getattr(frames, key).view(np.uint64)), key
        assert list(npz["names"]) == frames.names
        assert str(npz["up_axis"]) == "z"


def test_csv_reads_back_exactly(frames, tmp_path):
    frames.to_csv(tmp_path / "chain.csv")
    rows = list(csv.DictReader(open(tmp_path / "chain.csv", newline="")))
    assert len(rows) == len(frames.t) * len(frames.names)
    last = rows[-1]
    assert last["body"] == frames.names[-1]
    assert float(last["t"]) == frames.t[-1]
    assert [float(last[k]) for k in ("x", "y", "z")] == list(frames.position[-1, -1])


def test_gltf_is_a_glb_with_a_node_per_body(frames, tmp_path):
    frames.to_gltf(tmp_path / "chain.glb")
    data = (tmp_path / "chain.glb").read_bytes()
    magic, version, length, json_length, kind = struct.unpack_from("<4sIII4s", data)
    assert (magic, version, length, kind) == (b"glTF", 2, len(data), b"JSON")
    document = json.loads(data[20:20 + json_length])
    names = [node["name"] for node in document["nodes"]]
    assert set(frames.names) <= set(names)
    assert document["animations"][0]["samplers"][1]["interpolation"] == "CUBICSPLINE"
    frames.to_gltf(tmp_path / "chain.gltf", rotation="linear")
    text = json.loads((tmp_path / "chain.gltf").read_text())
    assert text["animations"][0]["samplers"][1]["interpolation"] == "LINEAR"


# An L-shaped prism, 0.1 m thick (the L (0, 0) (0.2, 0) (0.2, 0.1) (0.1, 0.1) (0.1, 0.3) (0, 0.3)
# at z = 0 and z = 0.1): not convex, so its hull (16 triangles) is not it (20 triangles).
L_VERTICES = [[x, y, z] for z in (0.0, 0.1)
              for x, y in ((0, 0), (0.2, 0), (0.2, 0.1), (0.1, 0.1), (0.1, 0.3), (0, 0.3))]
L_TRIANGLES = ([[6, 7 + k, 8 + k] for k in range(4)] + [[0, 2 + k, 1 + k] for k in range(4)] +
               [t for i in range(6) for t in ([i, (i + 1) % 6, 6 + (i + 1) % 6],
                                               [i, 6 + (i + 1) % 6, 6 + i])])


def test_a_mesh_body_built_in_python_exports_its_triangles(tmp_path):
    """A mesh body given through SceneBuilder reaches the scene's visual mesh: the .glb's mesh
    for it has exactly the given triangles, each corner the float nearest the given vertex."""
    builder = tumble.SceneBuilder()
    builder.add_body("letter", density=500, shape={"type": "mesh", "vertices": L_VERTICES,
                                                   "triangles": L_TRIANGLES})
    frames = builder.build(fps=10, duration=0.1).run()
    frames.to_gltf(tmp_path / "letter.glb")
    data = (tmp_path / "letter.glb").read_bytes()
    json_length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20:20 + json_length])
    blob = data[20 + json_length + 8:]
    mesh = next(m for m in document["meshes"] if m["name"] == "letter")
    primitive = mesh["primitives"][0]

    def accessor(index, dtype, width):
        a = document["accessors"][index]
        view = document["bufferViews"][a["bufferView"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        return np.frombuffer(blob, dtype=dtype, count=a["count"] * width,
                             offset=start).reshape(a["count"], width)

    positions = accessor(primitive["attributes"]["POSITION"], "<f4", 3)
    indices = accessor(primitive["indices"], "<u4", 1).reshape(-1, 3)
    expected = np.asarray(L_VERTICES, dtype=np.float64)[np.asarray(L_TRIANGLES)]
    assert indices.shape == (len(L_TRIANGLES), 3)
    assert np.array_equal(positions[indices], expected.astype(np.float32))


def test_usd_is_a_layer_with_a_body_xform_per_body_at_the_frames_rate(frames, tmp_path):
    # usd-core reads it in tests/export/check_usd.py; here the text says what the run was
    frames.to_usd(tmp_path / "chain.usda")
    text = (tmp_path / "chain.usda").read_text()
    assert text.startswith("#usda 1.0\n")
    fps = round(1.0 / (frames.t[1] - frames.t[0]))
    assert f"    timeCodesPerSecond = {fps}\n" in text and '    upAxis = "Z"\n' in text
    for name in frames.names:
        assert f"string tumbleBody = \"{name}\"" in text
    assert f"    endTimeCode = {len(frames.t) - 1}\n" in text


def test_bad_arguments_are_refused_and_leave_no_file(frames, tmp_path):
    with pytest.raises(ValueError, match="format must be one of"):
        frames.to_file(tmp_path / "x.glb", format="gif")
    with pytest.raises(ValueError, match="cannot tell the format"):
        frames.to_file(tmp_path / "x.txt")
    with pytest.raises(ValueError, match="rotation must be one of"):
        frames.to_gltf(tmp_path / "x.glb", rotation="smooth")
    with pytest.raises(tumble.TumbleError, match="cannot open for writing"):
        frames.to_npz(tmp_path / "no_such_directory" / "x.npz")
    assert list(tmp_path.iterdir()) == []
