"""Finding the tumble Python package from Blender's own Python, which is not the one pip
installed tumble into: the add-on preference "tumble Python path", then the environment
variable TUMBLE_PYTHON_PATH (each a folder holding the package `tumble`, several separated by
os.pathsep), then whatever Blender's Python can import already."""
import importlib
import os
import sys

HOW_TO_INSTALL = (
    "the tumble Python package was not found by Blender's Python {version}. Install it into a "
    "venv of that Python version (`python{version} -m venv DIR && DIR/bin/pip install "
    "./bindings/python` from tumble's sources) and set Edit > Preferences > Add-ons > tumble for "
    "Blender > tumble Python path to DIR/lib/python{version}/site-packages (or the environment "
    "variable TUMBLE_PYTHON_PATH), or install it into Blender's own Python; docs/blender.md")


class TumbleMissing(ImportError):
    pass


def folders(preference=""):
    found = [p for p in (preference or "").split(os.pathsep) if p]
    found += [p for p in os.environ.get("TUMBLE_PYTHON_PATH", "").split(os.pathsep) if p]
    return [os.path.abspath(os.path.expanduser(p)) for p in found]


def import_tumble(preference=""):
    """The tumble module, or TumbleMissing saying how to install it (and why the import
    failed when the package is there but does not load, e.g. NumPy or libtumble missing)."""
    for folder in reversed(folders(preference)):
        if folder not in sys.path:
            sys.path.insert(0, folder)
    try:
        return importlib.import_module("tumble")
    except ModuleNotFoundError as missing:
        if missing.name not in ("tumble", None):
            raise TumbleMissing(f"tumble needs the Python package {missing.name} in Blender's "
                                f"Python {sys.version.split()[0]}: {missing}") from missing
        version = "%d.%d" % sys.version_info[:2]
        raise TumbleMissing(HOW_TO_INSTALL.format(version=version)) from missing
    except ImportError as broken:
        raise TumbleMissing(f"the tumble package was found but does not load: {broken}") from broken


_static_support = {}


def supports(tumble, motion):
    """Whether the installed tumble takes bodies of this motion ("static", "keyframed"): asked
    by loading a two-body scene, so the answer is the library's own."""
    if motion not in _static_support:
        probe = {"type": "box", "size": [1, 1, 1]}
        other = {"name": "b", "motion": motion, "shape": probe}
        if motion == "keyframed":
            other["keys"] = [{"t": t, "position": [0, 0, -2], "orientation": [1, 0, 0, 0]}
                             for t in (0, 1)]
        else:
            other.update(position=[0, 0, -2])
        try:
            tumble.Scene.from_dict({"bodies": [{"name": "a", "shape": probe, "mass": 1}, other]})
            _static_support[motion] = True
        except tumble.TumbleError:
            _static_support[motion] = False
    return _static_support[motion]
