"""The package under test is the installed wheel (scripts/test.sh sets TUMBLE_TEST_INSTALLED):
its own libtumble.so and layout.json, found with no environment variable."""

import os
import pathlib
import sysconfig

import pytest

import tumble
from tumble import _native

ROOT = pathlib.Path(__file__).resolve().parents[3]

installed = pytest.mark.skipif(not os.environ.get("TUMBLE_TEST_INSTALLED"),
                               reason="runs against the installed wheel (scripts/test.sh)")


@installed
def test_the_installed_package_runs_with_its_own_library():
    package = pathlib.Path(tumble.__file__).resolve().parent
    source = ROOT / "bindings" / "python" / "tumble"
    assert package != source, f"the tests import the source tree's {source}"
    assert package == pathlib.Path(sysconfig.get_paths()["purelib"]).resolve() / "tumble"
    assert "TUMBLE_LIBRARY" not in os.environ
    assert pathlib.Path(_native._path) == package / "libtumble.so"
    assert (package / "layout.json").exists()
