"""Reads a tumble .npz with NumPy and compares it bit for bit with the same run's exact CSV
(17 significant digits read back with float(), which gives back the very double that was
printed; test_writers checks the CSV against the frames in memory the same way).

    check_npz.py FRAMES.npz FRAMES.csv
"""
import csv
import sys

import numpy as np


def main():
    npz_path, csv_path = sys.argv[1], sys.argv[2]
    with np.load(npz_path, allow_pickle=False) as npz:
        arrays = {name: npz[name] for name in npz.files}
    names = [str(n) for n in arrays["names"]]
    rows = list(csv.DictReader(open(csv_path, newline="")))
    frames, bodies = len(rows) // len(names), len(names)
    expected = {
        "t": np.array([float(r["t"]) for r in rows[::bodies]]),
        "position": [("x", "y", "z")],
        "orientation": [("qw", "qx", "qy", "qz")],
        "velocity": [("vx", "vy", "vz")],
        "angular_velocity": [("wx", "wy", "wz")],
    }
    for key in ("position", "orientation", "velocity", "angular_velocity"):
        columns = expected[key][0]
        expected[key] = np.array([[float(r[c]) for c in columns] for r in rows]).reshape(
            frames, bodies, len(columns))
    assert [r["body"] for r in rows[:bodies]] == names, f"names {names}"
    for key, value in expected.items():
        got = arrays[key]
        assert got.dtype == np.float64, f"{key}: dtype {got.dtype}"
        assert got.shape == value.shape, f"{key}: shape {got.shape}, expected {value.shape}"
        # bit for bit: compare the 64-bit patterns, so even -0.0 and 0.0 differ
        assert np.array_equal(got.view(np.uint64), value.view(np.uint64)), f"{key} differs"
    assert str(arrays["up_axis"]) == "z" and str(arrays["quaternion_order"]) == "w,x,y,z"
    assert str(arrays["units"]).startswith("SI")
    print(f"{npz_path}: {frames} frames x {bodies} bodies equal the CSV bit for bit; "
          f"members {sorted(arrays)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
