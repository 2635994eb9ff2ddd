"""Contact events (include/tumble/contact_events.h, docs/events.md) collected from a run: the
library calls back at step boundaries; each event is kept as a row of EVENT_DTYPE."""

import ctypes
from typing import Callable, Optional

import numpy as np

from . import _native
from ._core import failure, lib, number

#: One event: its time (s), kind ("begin", "hit", "end"), the two bodies' names ("ground" for a
#: ground plane), the deepest point and the normal from body_a to body_b (world, z up), the
#: approach (begin, hit) or separation (end) speed (m/s) and the normal impulse over the
#: contact (N s, at end).
EVENT_DTYPE = np.dtype([("t", "f8"), ("kind", "U5"), ("body_a", "O"), ("body_b", "O"),
                        ("point", "f8", (3,)), ("normal", "f8", (3,)), ("speed", "f8"),
                        ("impulse", "f8")])

_WORLD = ctypes.c_size_t(-1).value


class Listener:
    """Sets the scene's event callback (refusals raise TumbleError) and keeps the events."""

    def __init__(self, handle, names, hit_speed: float,
                 on_event: Optional[Callable[[dict], None]] = None):
        self.names = list(names)
        if "ground" in self.names and lib.tb_scene_ground_count(handle) > 0:
            # the rows name a ground plane "ground": a body so named would read as the plane
            raise ValueError(f"body {self.names.index('ground')} is named \"ground\", the name "
                             f"the events give a ground plane, and the scene has a ground plane: "
                             f"rename the body")
        self.rows = []
        self.on_event = on_event
        self.failure = None
        self.callback = _native.CONTACT_EVENT_FN(self._called)  # alive while the run lasts
        definition = lib.tb_contact_events_def_default()
        definition.fn = self.callback
        definition.hit_threshold = number("hit_speed", hit_speed)
        status = lib.tb_scene_set_contact_events(handle, ctypes.byref(definition))
        if status != 0:  # the C field's name is the argument's here
            detail = lib.tb_scene_detail(handle).decode()
            raise failure(status, detail.replace("def->hit_threshold", "hit_speed"))

    def _name(self, body):
        return "ground" if body == _WORLD else self.names[body]

    def _called(self, event, ctx):
        e = event.contents
        row = (e.t, lib.tb_contact_event_kind_name(e.kind).decode(), self._name(e.body_a),
               self._name(e.body_b), tuple(e.point), tuple(e.normal), e.speed, e.impulse)
        self.rows.append(row)
        if self.on_event is not None and self.failure is None:
            try:
                self.on_event(dict(zip(EVENT_DTYPE.names, row)))
            except BaseException as raised:  # noqa: B036 - kept and raised after the run
                self.failure = raised

    def array(self) -> np.ndarray:
        return np.array(self.rows, dtype=EVENT_DTYPE)
