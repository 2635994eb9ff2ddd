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


@pytest.fixture
def sliding_boxes():
    """A maker of a SceneBuilder: a 1 kg, 10 cm box on the ground, a 0.5 kg, 8 cm box on it
    sliding at 0.15 m/s and turning at 2 rad/s, and (side=True) another beside them sliding
    the other way: friction between bodies and on the ground, sliding and coming to rest, which
    holds slots of the friction pools (tests/test_run_again.c builds the same in C)."""
    import tumble  # here: the conftest loads before a test picks the library (test_install)

    def make(side=True):
        b = tumble.SceneBuilder()
        b.add_body("base", shape={"type": "box", "size": [0.1, 0.1, 0.1]}, mass=1,
                   position=[0, 0, 0.05])
        b.add_body("top", shape={"type": "box", "size": [0.08, 0.08, 0.08]}, mass=0.5,
                   position=[0, 0, 0.14], velocity=[0.15, 0, 0], angular_velocity=[0, 0, 2])
        if side:
            b.add_body("side", shape={"type": "box", "size": [0.08, 0.08, 0.08]}, mass=0.5,
                       position=[0.2, 0, 0.04], velocity=[-0.1, 0.05, 0])
        for effect in ("gravity", "ground", "contact"):
            b.add_effect(effect)
        return b
    return make
