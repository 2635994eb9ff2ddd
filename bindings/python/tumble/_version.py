"""The package's version, set once in the repository's CMakeLists.txt: an installed package
reads it from layout.json (written at build time from the headers it was built with, beside
the libtumble.so it ships); a source checkout (PYTHONPATH=bindings/python with
TUMBLE_LIBRARY) reads CMakeLists.txt. _native refuses a libtumble of another version."""

import json
import pathlib
import re

_HERE = pathlib.Path(__file__).resolve().parent
LAYOUT_FILE = _HERE / "layout.json"


def _read_version():
    if LAYOUT_FILE.exists():
        return json.loads(LAYOUT_FILE.read_text())["version"]
    cmake = _HERE.parents[2] / "CMakeLists.txt"
    found = re.search(r"project\(tumble VERSION ([0-9.]+)", cmake.read_text()) \
        if cmake.exists() else None
    if found is None:
        raise ImportError(f"tumble: neither {LAYOUT_FILE} (an installed package) nor {cmake} "
                          f"(a source checkout) says the version: reinstall the package")
    return found.group(1)


__version__ = _read_version()
