"""SceneBuilder: a scene written in code, in the scene-file format's words, and handed to the
library as a Scene (the format's dictionary, docs/scene-format.md)."""

import copy
from typing import Optional

import numpy as np

from ._scene import Scene


class SceneBuilder:
    """Builds a scene in code, in the scene-file format's words:

        b = tumble.SceneBuilder()
        b.add_body("ball", shape={"type": "sphere", "radius": 0.1}, mass=1, position=[0, 0, 2])
        b.add_effect("gravity")
        b.add_joint("ball", "ball", anchor=[0, 0, 3])   # hung from the world by a rigid rod
        scene = b.build(method="rk4", dt=1/240, fps=60, duration=2)
    """

    def __init__(self):
        self._description = {"bodies": [], "effects": []}

    def add_body(self, name: str, **fields) -> "SceneBuilder":
        """A body with the scene format's fields: shape, mass or density (kg, kg/m^3),
        inertia, position (m, world, centre of mass), orientation (w, x, y, z),
        velocity (m/s), angular_velocity (rad/s, world) or angular_velocity_body, ..."""
        self._description["bodies"].append({"name": name, **fields})
        return self

    def add_keyframed_body(self, name: str, t, position, orientation=None, velocity=None,
                           angular_velocity=None, interpolation: str = "cubic",
                           **fields) -> "SceneBuilder":
        """A keyframed body (the scene format's "motion": "keyframed", docs/scene-format.md,
        "Keys"): its pose follows keys at times t (K,) s, strictly increasing, with position
        (K, 3) m (world; the shape frame's origin) and orientation (K, 4) quaternions
        (w, x, y, z; default the identity); velocity (K, 3) m/s and angular_velocity (K, 3)
        rad/s (world) are the cubic curve's tangents at the keys (rows of NaN: Catmull-Rom's);
        interpolation "linear", "cubic" or "step". fields as add_body's (a shape, a contact);
        it needs no mass. The library checks the keys when the scene is built."""
        t = np.atleast_1d(_numbers(name, "t", t))
        if t.ndim != 1:
            raise ValueError(f"add_keyframed_body({name!r}): t must be one time per key (K,), "
                             f"got shape {t.shape}")
        count = len(t)
        if count == 0:
            raise ValueError(f"add_keyframed_body({name!r}): t must hold at least one key")
        position = _rows(name, "position", position, count, 3)
        orientation = _rows(name, "orientation",
                            [1.0, 0, 0, 0] if orientation is None else orientation, count, 4)
        tangents = {}
        for key, value in (("velocity", velocity), ("angular_velocity", angular_velocity)):
            if value is not None:
                tangents[key] = _rows(name, key, value, count, 3)
        keys = []
        for k in range(count):
            entry = {"t": float(t[k]), "position": position[k].tolist(),
                     "orientation": orientation[k].tolist()}
            for key, rows in tangents.items():
                if not np.all(np.isnan(rows[k])):
                    entry[key] = rows[k].tolist()
            keys.append(entry)
        return self.add_body(name, motion="keyframed", interpolation=interpolation, keys=keys,
                             **fields)

    def set_body_pieces(self, name: str, pieces) -> "SceneBuilder":
        """Gives the body added as name a shape of convex pieces, replacing its shape (C's
        tb_scene_set_body_pieces; the scene format's list as a shape, docs/scene-format.md,
        "Bodies of several pieces"): pieces is a non-empty sequence of shapes in the format's
        words, each with an optional "position" (m) and "orientation" (w, x, y, z) placing it
        in the body's shape frame. The body's density or mass applies to them all, and its mass
        properties are the pieces' combined by the parallel-axis theorem (tb_mass_combine).
        ValueError for a name not added or no pieces; the library checks each piece when the
        scene is built, naming it."""
        if isinstance(pieces, (dict, str, bytes)) or not hasattr(pieces, "__iter__"):
            raise TypeError(f"set_body_pieces({name!r}): pieces must be a sequence of shapes "
                            f"(dicts), got {type(pieces).__name__}")
        pieces = list(pieces)
        for k, piece in enumerate(pieces):
            if not isinstance(piece, dict):
                raise TypeError(f"set_body_pieces({name!r}): pieces[{k}] must be a shape (a dict), "
                                f"got {type(piece).__name__}")
        pieces = [dict(piece) for piece in pieces]
        if not pieces:
            raise ValueError(f"set_body_pieces({name!r}): pieces must not be empty")
        for body in self._description["bodies"]:
            if body["name"] == name:
                body["shape"] = pieces
                return self
        raise ValueError(f"set_body_pieces: no body named {name!r} was added")

    def add_effect(self, type: str, **fields) -> "SceneBuilder":
        """An effect with the scene format's fields: "gravity", "drag", "spring", "force",
        "torque", "ground", ... (docs/scene-format.md, "Effects")."""
        self._description["effects"].append({"type": type, **fields})
        return self

    def add_joint(self, type: str, bodies, anchor, axis=None, **fields) -> "SceneBuilder":
        """A joint with the scene format's fields (docs/joints.md, "Joints in a scene file"):
        type "ball", "hinge", "slider" or "fixed"; bodies one body's name (joined to the
        world) or a list of one or two; anchor (3,) m and axis (3,) (hinge and slider: the axis
        or the direction of travel), both in the world frame at the start; fields limits
        ([lower, upper], rad or m from the start pose), restitution (at the limits),
        motor ({"speed" or "target", "max_torque" for a hinge or "max_force" for a slider}),
        break_force (N), break_torque (N m), soft ({"frequency": Hz, "damping_ratio"}). The
        library checks it when the scene is built (TumbleError naming joints[k].field)."""
        joint = {"type": type, "bodies": [bodies] if isinstance(bodies, str) else list(bodies),
                 "anchor": np.asarray(anchor, dtype=float).tolist()}
        if axis is not None:
            joint["axis"] = np.asarray(axis, dtype=float).tolist()
        joint.update(fields)
        self._description.setdefault("joints", []).append(joint)
        return self

    def build(self, fps: Optional[float] = None, duration: Optional[float] = None,
              sleeping: Optional[bool] = None, **integrator) -> "Scene":
        """The Scene, checked by the library; fps (frames/s) and duration (s) are its output
        settings, sleeping the file's "sleeping" (whether islands of resting bodies sleep;
        default true), integrator its method and dt/rtol/atol (scene format's "integrator")."""
        description = copy.deepcopy(self._description)
        if sleeping is not None:
            description["sleeping"] = bool(sleeping)
        if integrator:
            description["integrator"] = integrator
        output = {k: v for k, v in (("fps", fps), ("duration", duration)) if v is not None}
        if output:
            description["output"] = output
        return Scene.from_dict(description, name="<builder>")


def _numbers(body, argument, value):
    """value as an array of floats, or TypeError naming the argument (strings, booleans and
    complex numbers are not numbers here, as in the scene format)."""
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):
        array = None
    if array is None or array.dtype.kind not in "iuf":
        kind = f"an array of {array.dtype}" if array is not None else type(value).__name__
        raise TypeError(f"add_keyframed_body({body!r}): {argument} must be real numbers, got "
                        f"{kind}")
    return array.astype(float)


def _rows(body, argument, value, count, width):
    """value as (count, width) floats, one row given for every key, or an error naming it."""
    array = _numbers(body, argument, value)
    if array.shape not in ((width,), (count, width)):
        raise ValueError(f"add_keyframed_body({body!r}): {argument} must have shape "
                         f"({count}, {width}) for {count} keys (or ({width},) for all), got "
                         f"{array.shape}")
    return np.broadcast_to(array, (count, width))
