"""Errors arrive as TumbleError carrying the library's status and message."""

import os
import subprocess
import sys

import numpy as np
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


# One rule for exceptions: what the library refuses is a TumbleError (a refused value also a
# ValueError); a wrong type is a TypeError; an option the method does not read a ValueError.

def _ball():
    return tumble.Scene.from_dict({"bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1]}]})


def test_an_unknown_method_is_the_librarys_refusal():
    with pytest.raises(tumble.TumbleError) as caught:
        _ball().run(method="rk45")
    assert caught.value.status == "INVALID_ARGUMENT"
    assert 'unknown method "rk45"; methods: euler, midpoint, rk4' in caught.value.message


def test_a_method_name_in_any_case_is_accepted():
    assert _ball().run(method="RK4", duration=0.1).stats["steps"] > 0


@pytest.mark.parametrize("options", [{"dt": "fast"}, {"fps": "60"}, {"method": 4},
                                     {"duration": [1]}, {"method": "cvode-bdf", "rtol": True}])
def test_an_argument_of_the_wrong_type_is_a_type_error(options):
    with pytest.raises(TypeError):
        _ball().run(**options)


@pytest.mark.parametrize("options, field", [({"fps": float("nan")}, "fps"),
                                            ({"fps": -1.0}, "fps"),
                                            ({"duration": 1e300}, "duration")])
def test_a_refused_value_is_a_tumble_error_and_a_value_error(options, field):
    # NaN fps and a duration of 1e300 s used to fail inside NumPy (converting NaN to an integer,
    # an array too large) before the library saw them.
    with pytest.raises(tumble.TumbleError) as caught:
        _ball().run(**options)
    assert isinstance(caught.value, ValueError)
    assert caught.value.message.startswith(field)


@pytest.mark.parametrize("options, named", [({"method": "cvode-adams", "rtol": 2.0},
                                             "rtol: must be in [1e-15, 1), got 2"),
                                            ({"method": "cvode-bdf", "atol": -1.0},
                                             "atol: must be >= 0, got -1"),
                                            ({"method": "rk4", "dt": float("nan")},
                                             "dt: must be finite, got nan")])
def test_a_refused_setting_names_the_argument_not_the_c_field(options, named):
    # Simulation(rtol=2) was refused as "integrator: def.rtol: ...", the C struct's field that
    # a Python caller never sees; the message names the argument as it was passed.
    for make in (lambda: tumble.Simulation(_ball(), **options), lambda: _ball().run(**options)):
        with pytest.raises(ValueError) as caught:
            make()
        assert caught.value.message.startswith(named), caught.value.message
        assert "def." not in caught.value.message


@pytest.mark.parametrize("method, options, named", [("rk4", {"rtol": 1e-8}, "rtol"),
                                                    ("euler", {"atol": 1e-9}, "atol"),
                                                    ("cvode-bdf", {"dt": 0.01}, "dt")])
def test_an_option_the_method_does_not_read_is_refused(method, options, named):
    # rtol given to rk4 used to be ignored silently; the CLI refuses it.
    with pytest.raises(ValueError, match=f"^{named} applies to .* methods \\(.*\\), not to "
                                         f"{method}$"):
        _ball().run(method=method, **options)


def test_a_scene_file_with_a_nul_byte_is_refused(tmp_path):
    # ctypes passes a bytes object up to its first NUL: the part before it, a valid scene, was
    # loaded and the rest ignored. The CLI refuses such a file; so do the bindings.
    path = tmp_path / "nul.json"
    valid = b'{"bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1]}]}'
    path.write_bytes(valid + b'\0{"more": 1}')
    with pytest.raises(tumble.TumbleError) as caught:
        tumble.Scene.from_file(path)
    assert caught.value.status == "PARSE_ERROR"
    assert f"a NUL byte at offset {len(valid)}" in caught.value.message


def test_a_libtumble_of_another_version_is_refused(tmp_path):
    # A stand-in libtumble that says it is 9.9.9: importing tumble against it must fail with a
    # message naming both versions, before any struct is read with the wrong layout.
    source = tmp_path / "fake.c"
    source.write_text('const char *tb_version(void) { return "9.9.9"; }\n')
    library = tmp_path / "libtumble_fake.so"
    subprocess.run(["cc", "-shared", "-fPIC", str(source), "-o", str(library)], check=True)
    env = dict(os.environ, TUMBLE_LIBRARY=str(library), PYTHONPATH=os.pathsep.join(sys.path))
    result = subprocess.run([sys.executable, "-c", "import tumble"], env=env,
                            capture_output=True, text=True)
    assert result.returncode != 0
    assert (f"is libtumble 9.9.9, but this tumble Python package is {tumble.__version__}"
            in result.stderr)


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf")])
def test_a_number_json_cannot_hold_is_refused_naming_the_field(value):
    # NaN and infinities were written into the JSON as NaN and Infinity, which the parser then
    # refused as "PARSE_ERROR: <builder>:1:160: invalid token near 'NaN'", a column of text the
    # caller never wrote, naming no field
    b = tumble.SceneBuilder()
    b.add_body("ball", shape={"type": "sphere", "radius": 0.1}, mass=1, position=[0, 0, 0.1])
    b.add_effect("ground", restitution=value)
    with pytest.raises(ValueError) as caught:
        b.build()
    assert isinstance(caught.value, tumble.TumbleError)
    assert caught.value.status == "BAD_SCENE"
    assert caught.value.message == (f"<builder>: effects[0].restitution: must be a finite "
                                    f"number, got {value}")
    with pytest.raises(tumble.TumbleError, match=r"mine: bodies\[0\]\.position\[2\]: must be a "):
        tumble.Scene.from_dict({"bodies": [{"name": "b", "mass": 1, "inertia": [1, 1, 1],
                                            "position": [0, 0, value]}]}, name="mine")


def test_numpy_arrays_and_scalars_are_the_numbers_they_hold():
    # a position as a NumPy array, a density as numpy.int32: "Object of type ndarray is not JSON
    # serializable" before; now the scene the same lists and numbers make
    def scene(position, density, normal):
        b = tumble.SceneBuilder()
        b.add_body("ball", shape={"type": "sphere", "radius": 0.1}, density=density,
                   position=position)
        b.add_effect("gravity").add_effect("ground", normal=normal)
        return b.build(fps=10, duration=0.2).run()
    plain = scene([0, 0, 0.5], 1000, [0, 0, 1])
    numpy = scene(np.array([0, 0, 0.5]), np.int32(1000), (np.float32(0), 0, np.float64(1)))
    assert np.array_equal(plain.position, numpy.position)
