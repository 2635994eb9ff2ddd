"""help() on the package reads like the C headers: every public class, method and property
has a docstring, the state's documentation gives units and frames, and public methods carry
type hints."""

import inspect

import tumble

PUBLIC = (tumble.Scene, tumble.SceneBuilder, tumble.Frames, tumble.Simulation)


def public_members(cls):
    for name, member in vars(cls).items():
        if name.startswith("_") and name != "__init__":
            continue
        if callable(member) or isinstance(member, (property, classmethod, staticmethod)):
            yield name, member


def test_every_public_member_has_a_docstring():
    missing = [f"{cls.__name__}.{name}" for cls in PUBLIC for name, member in public_members(cls)
               if not inspect.getdoc(getattr(member, "__func__", member))]
    missing += [f.__name__ for f in (tumble.run_many,) if not inspect.getdoc(f)]
    assert missing == []


def test_the_state_is_documented_with_units_and_frames():
    doc = inspect.getdoc(tumble.Simulation)
    for words in ("m, centre of mass", "body (principal) frame -> world", "kg m/s",
                  "kg m^2/s", "rad/s", "world frame", "read-only", "Lifetimes"):
        assert words in doc, words
    for name in ("position", "quaternion", "momentum", "angular_momentum", "velocity",
                 "angular_velocity"):
        assert "frame" in inspect.getdoc(getattr(tumble.Simulation, name)), name


def test_public_methods_have_type_hints():
    unhinted = []
    for cls in PUBLIC:
        for name, member in public_members(cls):
            function = getattr(member, "__func__", member)
            if isinstance(member, property) or not inspect.isfunction(function):
                continue
            if name != "__init__" and "return" not in function.__annotations__:
                unhinted.append(f"{cls.__name__}.{name}")
    assert unhinted == []
