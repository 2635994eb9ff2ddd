"""The ctypes declarations against the C headers: sizes and every field's offset, as the
compiler sees them (layout_probe.c). A drift between the bindings and the library fails here."""

import ctypes
import json
import subprocess

import tumble
from tumble import _native


def test_struct_layouts_match_the_headers(layout_probe):
    layout = json.loads(subprocess.run([layout_probe], check=True, capture_output=True,
                                       text=True).stdout)
    for name, struct in _native.STRUCTS.items():
        c = layout[name]
        assert ctypes.sizeof(struct) == c["size"], name
        for field, _ in struct._fields_:
            assert getattr(struct, field).offset == c[field], f"{name}.{field}"
        assert {f for f, _ in struct._fields_} == set(c) - {"size", "_"}, name


def test_package_and_library_versions_agree():
    assert tumble.__version__ == tumble.library_version
