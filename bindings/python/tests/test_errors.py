"""Errors arrive as TumbleError carrying the library's status and message."""

import pytest

import tumble


def test_a_bad_dictionary_names_the_field():
    with pytest.raises(tumble.TumbleError) as caught:
        tumble.Scene.from_dict({"bodies": [{"name": "b", "shape": {"type": "box", "size": [1, 1, 1]},
                                            "mass": -1}]}, name="mine")
    assert caught.value.status == "BAD_SCENE"
    assert "mine: bodies[0].mass: must be > 0, got -1" in caught.value.message


def test_a_malformed_file_names_line_and_column(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text('{\n  "bodies": [\n    {"name": "a",,}\n  ]\n}\n')
    with pytest.raises(tumble.TumbleError) as caught:
        tumble.Scene.from_file(path)
    assert caught.value.status == "PARSE_ERROR"
    assert "broken.json:3:" in caught.value.message


def test_a_missing_file_is_an_os_error(tmp_path):
    with pytest.raises(OSError):
        tumble.Scene.from_file(tmp_path / "nowhere.json")


def test_an_unknown_method_is_a_value_error():
    scene = tumble.Scene.from_dict({"bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1]}]})
    with pytest.raises(ValueError, match="rk45"):
        scene.run(method="rk45")


def test_a_step_beyond_the_stability_limit_is_refused():
    scene = tumble.Scene.from_dict({
        "bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1,
                    "position": [1.1, 0, 0]}],
        "effects": [{"type": "spring", "body_a": "a", "point_b": [0, 0, 0], "stiffness": 1e7}]})
    with pytest.raises(tumble.TumbleError, match="stability limit"):
        scene.run(method="rk4", dt=0.01)
