"""tumble.run_many: ensembles on threads and on a Dask cluster give exactly the serial runs."""

import os

import numpy as np
import pytest

import tumble

FIELDS = ("t", "position", "orientation", "velocity", "angular_velocity", "kinetic_energy",
          "potential_energy", "linear_momentum", "angular_momentum", "center_of_mass")


def handle(spin):
    """A box spun mostly about its intermediate axis, with a small spin `spin` about another."""
    return {"bodies": [{"name": "handle", "shape": {"type": "box", "size": [0.1, 0.2, 0.4]},
                        "density": 700, "angular_velocity": [spin, 8.0, 0.01]}],
            "effects": [{"type": "gravity"}],
            "output": {"fps": 30, "duration": 3.0}}


def assert_same_bits(a, b):
    for name in FIELDS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.stats == b.stats


SPINS = [0.001 * 2**k for k in range(6)]


def test_threads_give_the_serial_runs_bit_for_bit_in_any_order():
    serial = [tumble.Scene.from_dict(handle(s)).run(method="rk4", dt=1 / 480) for s in SPINS]
    threaded = tumble.run_many([handle(s) for s in SPINS], method="rk4", dt=1 / 480, workers=2)
    backwards = tumble.run_many([handle(s) for s in reversed(SPINS)], method="rk4",
                                dt=1 / 480, workers=3)
    for k in range(len(SPINS)):
        assert_same_bits(threaded[k], serial[k])
        assert_same_bits(backwards[-1 - k], serial[k])
    # the runs differ from each other: the comparison above can tell them apart
    assert not np.array_equal(serial[0].orientation, serial[-1].orientation)


def test_each_item_can_bring_its_own_settings():
    scene = tumble.Scene.from_dict(handle(0.01))
    results = tumble.run_many([scene, (scene, {"method": "cvode-adams", "rtol": 1e-8})],
                              method="rk4", dt=1 / 240)
    assert_same_bits(results[0], scene.run(method="rk4", dt=1 / 240))
    assert_same_bits(results[1], scene.run(method="cvode-adams", rtol=1e-8))


def test_failures_raise_or_take_their_place():
    spring = {"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1,
                          "position": [1.1, 0, 0]}],
              "effects": [{"type": "spring", "body_a": "a", "point_b": [0, 0, 0],
                           "stiffness": 1e7}]}
    items = [handle(0.01), (spring, {"dt": 0.01})]
    with pytest.raises(tumble.TumbleError, match="stability limit"):
        tumble.run_many(items, workers=2)
    results = tumble.run_many(items, workers=2, errors="return")
    assert isinstance(results[0], tumble.Frames)
    assert isinstance(results[1], tumble.TumbleError)
    assert results[1].status == "UNSTABLE_STEP"


def test_bad_arguments_are_refused_before_anything_runs():
    with pytest.raises(ValueError, match="workers"):
        tumble.run_many([handle(0.0)], workers=0)
    with pytest.raises(TypeError, match="workers"):
        tumble.run_many([handle(0.0)], workers=1.5)
    with pytest.raises(ValueError, match="errors"):
        tumble.run_many([handle(0.0)], errors="ignore")
    with pytest.raises(TypeError, match="dict of settings"):
        tumble.run_many([(handle(0.0), 5)])
    with pytest.raises(ValueError, match="unknown settings"):
        tumble.run_many([(handle(0.0), {"steps": 3})])
    with pytest.raises(TypeError, match="a scene is"):
        tumble.run_many([3.5])


def final_orientation(frames):
    """A summary computed where the run ran: only it travels back."""
    return frames.orientation[-1].copy()


def test_reduce_returns_a_summary_of_each_run():
    serial = [tumble.Scene.from_dict(handle(s)).run() for s in SPINS[:3]]
    reduced = tumble.run_many([handle(s) for s in SPINS[:3]], reduce=final_orientation)
    for k in range(3):
        assert np.array_equal(reduced[k], final_orientation(serial[k]))
    with pytest.raises(TypeError, match="reduce"):
        tumble.run_many([handle(0.0)], reduce=3)


def _distributed():
    if os.environ.get("TUMBLE_TEST_INSTALLED"):  # the test command installs Dask: never skip
        import distributed
        return distributed
    return pytest.importorskip("distributed")


def test_a_dask_cluster_of_processes_gives_the_serial_runs_bit_for_bit():
    distributed = _distributed()
    serial = [tumble.Scene.from_dict(handle(s)).run(method="rk4", dt=1 / 480) for s in SPINS]
    with distributed.LocalCluster(n_workers=3, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = tumble.run_many([handle(s) for s in SPINS], method="rk4", dt=1 / 480,
                                 client=client)
        last = tumble.run_many([handle(s) for s in SPINS], method="rk4", dt=1 / 480,
                               client=client, reduce=final_orientation)
        pids = set(client.run(os.getpid).values())
    assert len(pids) == 3 and os.getpid() not in pids  # other processes did the work
    for k in range(len(SPINS)):
        assert_same_bits(remote[k], serial[k])
        assert np.array_equal(last[k], final_orientation(serial[k]))
    assert remote[0].names == ["handle"] and remote[0].source.body_names == ["handle"]
