import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture
def scenes():
    return ROOT / "examples" / "scenes"


@pytest.fixture
def layout_probe():
    path = os.environ.get("TUMBLE_LAYOUT_PROBE")
    if not path:
        pytest.fail("TUMBLE_LAYOUT_PROBE must name the built layout probe (scripts/test.sh sets it)")
    return path
