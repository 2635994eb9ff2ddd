"""The ctypes declarations against the C headers: sizes and every field's offset, as the
compiler sees them (layout_probe.c). A drift between the bindings and the library fails here;
the installed package makes the same check at import against the layout recorded when its
libtumble was built (tumble/layout.json)."""

import ctypes
import json
import subprocess

import tumble
from tumble import _native


def test_struct_layouts_match_the_headers(layout_probe):
    layout = json.loads(subprocess.run([layout_probe], check=True, capture_output=True,
                                       text=True).stdout)
    assert _native.check_layout(layout, _native.STRUCTS) == []
    assert layout["version"] == tumble.__version__


def test_a_layout_that_differs_is_named_field_by_field():
    class Shifted(ctypes.Structure):
        _fields_ = [("fps", ctypes.c_double), ("duration", ctypes.c_float)]

    layout = {"tb_run_def": {"size": 24, "fps": 0, "duration": 8, "extra": 16, "_": 0}}
    found = _native.check_layout(layout, {"tb_run_def": Shifted})
    assert found == ["tb_run_def: size 16 here, 24 in C",
                     "tb_run_def.extra: in C, not declared here"]


def test_package_and_library_versions_agree():
    assert tumble.__version__ == tumble.library_version
