"""Checks an installed tumble wheel runs on its own bundled libraries (scripts/test_wheel.sh runs
it in a fresh venv, outside the source tree, with the system's copies of those libraries made
unreachable where it can).

    python check_wheel.py NAME=PACKAGE...   (e.g. libgsl=libgsl27: the libraries the repaired
                                             wheel must bring itself, from `ldd` on the raw one,
                                             and the packages whose licences come with them)

Fails unless: the package imported is the installed one, with py.typed; two small runs give
the exact motion (a ball thrown under uniform gravity, whose path is the quadratic
z0 + vz t - g t^2 / 2); every named library is mapped into this process from the wheel's own
tumble.libs folder (/proc/self/maps), none from anywhere else; and `ldd` on the installed
libtumble.so resolves each of them inside tumble.libs, whose licences/ has each package's copyright file."""

import os
import pathlib
import subprocess
import sys
import sysconfig

import tumble


def stem(name):
    """libgsl-5d02bd0b.so.27.0.0 -> libgsl (auditwheel adds a hash); libgsl.so.27 -> libgsl."""
    base = name.split(".so")[0]
    head, _, tail = base.rpartition("-")
    return head if head and len(tail) == 8 and all(c in "0123456789abcdef" for c in tail) else base


def check_package():
    package = pathlib.Path(tumble.__file__).resolve().parent
    site = pathlib.Path(sysconfig.get_paths()["purelib"]).resolve()
    assert package == site / "tumble", f"imported {package}, not the installed package"
    assert (package / "py.typed").is_file(), "the wheel has no tumble/py.typed"
    bundled = site / "tumble.libs"
    assert bundled.is_dir(), f"the wheel has no {bundled} (not repaired by auditwheel?)"
    return package, bundled


def check_motion():
    """A ball thrown up: z(t) = z0 + vz t - g t^2/2, x(t) = vx t. RK4 integrates a quadratic
    exactly, so 1e-12 m is rounding over 100 steps of a few metres; CVODE (BDF, the SUNDIALS
    library the wheel bundles) holds its rtol 1e-10 to within 1e-7 m over 1 s."""
    g, z0, vx, vz = 9.81, 2.0, 1.5, 3.0
    scene = tumble.Scene.from_dict({
        "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1,
                    "position": [0, 0, z0], "velocity": [vx, 0, vz]}],
        "effects": [{"type": "gravity", "g": [0, 0, -g]}],
        "output": {"fps": 10, "duration": 1},
    })
    for method, options, tolerance in (("rk4", {"dt": 0.01}, 1e-12),
                                       ("cvode-bdf", {"rtol": 1e-10}, 1e-7)):
        frames = scene.run(method=method, **options)
        t = frames.t
        exact_z = z0 + vz * t - 0.5 * g * t * t
        error = max(abs(frames.position[:, 0, 2] - exact_z).max(),
                    abs(frames.position[:, 0, 0] - vx * t).max())
        assert error <= tolerance, f"{method}: {error:g} m from the exact path"
        print(f"check_wheel: {method}: {len(t)} frames, {error:.1e} m from the exact path")


def mapped_files():
    with open("/proc/self/maps") as maps:
        return {line.split(None, 5)[5].strip() for line in maps if len(line.split(None, 5)) == 6}


def check_libraries(package, bundled, pairs):
    wanted = {pair.split("=")[0] for pair in pairs}
    for pair in pairs:
        licence = bundled / "licenses" / f"{pair.split('=')[1]}.copyright"
        assert licence.is_file() and licence.stat().st_size > 0, f"no licence {licence}"
    paths = [pathlib.Path(p) for p in mapped_files() if p.startswith("/")]
    found = {}
    for path in paths:
        if stem(path.name) in wanted:
            assert path.parent == bundled, f"{path} is loaded from outside the wheel ({bundled})"
            found[stem(path.name)] = path
    missing = wanted - found.keys()
    assert not missing, f"not loaded at all: {sorted(missing)}"
    ldd = subprocess.run(["ldd", str(package / "libtumble.so")], capture_output=True, text=True,
                         check=True, env={k: v for k, v in os.environ.items()
                                          if k != "LD_LIBRARY_PATH"}).stdout
    for line in ldd.splitlines():
        name = line.split()[0]
        if stem(name) in wanted:
            where = line.split("=>")[1].split("(")[0].strip() if "=>" in line else ""
            assert where and pathlib.Path(where).resolve().parent == bundled, \
                f"ldd: {line.strip()}"
        assert "not found" not in line, f"ldd: {line.strip()}"
    for name in sorted(found):
        print(f"check_wheel: {name}: {found[name]}")


def main():
    assert "TUMBLE_LIBRARY" not in os.environ and not os.environ.get("LD_LIBRARY_PATH")
    package, bundled = check_package()
    check_motion()
    check_libraries(package, bundled, sys.argv[1:])
    print(f"check_wheel: tumble {tumble.__version__} runs on its bundled {len(sys.argv) - 1} "
          f"libraries")


if __name__ == "__main__":
    main()
