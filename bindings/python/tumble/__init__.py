"""tumble: rigid bodies that fly, spin, tumble and flip, integrated the way the physics says
(a C library; this package ships it and calls it with ctypes).

    import tumble
    scene = tumble.Scene.from_file("examples/scenes/sliding_block.json")
    frames = scene.run(method="rk4", dt=1/480)       # every frame, as NumPy arrays
    frames.position[:, 0, 0]                          # x of body 0 at every frame, m

    sim = tumble.Simulation(scene, method="cvode-adams", rtol=1e-8)
    sim.advance(0.5)                                  # interactive, as MuJoCo's MjData
    sim.positions[0], sim.angular_velocity[0]         # live, zero-copy views

    results = tumble.run_many([variant_1, variant_2], workers=2)   # threads, or client=Dask

Scenes come from files, from dictionaries in the scene-file format (docs/scene-format.md), or
from a SceneBuilder. Units are SI and the world frame is z up throughout.

Errors, by one rule: what the library refuses raises TumbleError with the library's status and
message, e.g. "scene.json: bodies[0].mass: must be > 0, got -1"; when what it refused is an
argument's value (INVALID_ARGUMENT, NOT_FINITE, OUT_OF_RANGE, UNSTABLE_STEP) the exception is
also a ValueError. An argument of the wrong type raises TypeError, and a value the bindings
refuse before calling the library (an option that does not apply to the method) ValueError.
A file that cannot be read raises OSError. Ctrl-C raises KeyboardInterrupt; a run keeps the
frames made so far on the exception (`frames`).
"""

from ._core import METHODS, TumbleError, TumbleValueError, lib
from ._ensemble import run_many
from ._events import EVENT_DTYPE
from ._builder import SceneBuilder
from ._scene import ACCURACY_SWEEP, Frames, Scene
from ._simulation import Simulation
from ._version import __version__  # equal to the library's: _native checks it at import

__all__ = ["Scene", "SceneBuilder", "Frames", "Simulation", "run_many", "TumbleError",
           "TumbleValueError", "METHODS", "ACCURACY_SWEEP", "EVENT_DTYPE", "__version__",
           "library_version"]

#: tb_version() of the libtumble loaded (the same as __version__, or the import fails)
library_version: str = lib.tb_version().decode()
