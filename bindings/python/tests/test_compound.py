"""Bodies of several convex pieces from Python (SceneBuilder.set_body_pieces, the scene format's
shape list; docs/python.md): their mass properties against the parallel-axis theorem, computed
here, and a dumbbell of two spheres resting on both."""

import numpy as np
import pytest

import tumble

DENSITY = 800.0  # kg/m^3


def rotation(q):
    """The rotation matrix of the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def box_inertia(mass, size):
    """A solid box's inertia tensor about its centre, in its own frame (kg m^2)."""
    a, b, c = np.square(size)
    return mass / 12.0 * np.diag([b + c, a + c, a + b])


def test_a_body_of_two_pieces_has_their_mass_properties_combined():
    # A plank (0.3 x 0.1 x 0.05 m) and a post (0.05 x 0.1 x 0.2 m) turned 90 degrees about z and
    # set on the plank's end: each piece's mass is density times volume, its inertia about its
    # own centre the box's, turned into the body's shape frame (R I R^T); combined about their
    # centre of mass c = sum m p / M by the parallel-axis theorem, sum R I R^T + m (|d|^2 E -
    # d d^T) with d = p - c. The library's (tb_mass_combine, then the principal axes and back
    # through tb_mass_tensor) agree to rounding: 1e-12 of the largest moment.
    s = np.sqrt(0.5)
    pieces = [{"type": "box", "size": [0.3, 0.1, 0.05]},
              {"type": "box", "size": [0.05, 0.1, 0.2], "position": [0.1, 0.0, 0.125],
               "orientation": [s, 0.0, 0.0, s]}]
    scene = (tumble.SceneBuilder()
             .add_body("tee", shape={"type": "sphere", "radius": 1.0}, density=DENSITY)
             .set_body_pieces("tee", pieces)
             .add_effect("gravity")
             .build(method="rk4", fps=60, duration=0.1))
    masses, centres, tensors = [], [], []
    for piece in pieces:
        m = DENSITY * np.prod(piece["size"])
        R = rotation(piece.get("orientation", [1.0, 0.0, 0.0, 0.0]))
        masses.append(m)
        centres.append(np.array(piece.get("position", [0.0, 0.0, 0.0])))
        tensors.append(R @ box_inertia(m, piece["size"]) @ R.T)
    total = sum(masses)
    c = sum(m * p for m, p in zip(masses, centres)) / total
    inertia = sum(I + m * (np.dot(p - c, p - c) * np.eye(3) - np.outer(p - c, p - c))
                  for m, p, I in zip(masses, centres, tensors))
    assert scene.piece_counts == [2]
    assert scene.masses[0] == pytest.approx(total, rel=1e-14)
    assert np.allclose(scene.center_of_mass[0], c, rtol=0, atol=1e-15)
    assert np.allclose(scene.inertia[0], inertia, rtol=0, atol=1e-12 * np.abs(inertia).max())


def test_set_body_pieces_refuses_an_unknown_body_and_no_pieces():
    b = tumble.SceneBuilder().add_body("ball", shape={"type": "sphere", "radius": 0.1}, mass=1)
    with pytest.raises(ValueError, match="no body named 'wheel'"):
        b.set_body_pieces("wheel", [{"type": "sphere", "radius": 0.1}])
    with pytest.raises(ValueError, match="must not be empty"):
        b.set_body_pieces("ball", [])
    # a bad piece is the library's to refuse, naming it
    b.set_body_pieces("ball", [{"type": "sphere", "radius": 0.1},
                               {"type": "box", "size": [0.1, -1, 0.1]}])
    with pytest.raises(tumble.TumbleError, match=r"bodies\[0\]\.shape\[1\]"):
        b.build()


def test_a_dumbbell_of_two_spheres_lands_on_both():
    # Two 5 cm spheres 0.4 m apart on one body, dropped 0.2 m tilted 10 degrees about y, so one
    # sphere lands first. Each sphere is a piece with its own contact point (the sphere's: its
    # centre, radius r, support 1), so the ground's stiffness puts M g on one point at its
    # penetration, and with both spheres down each carries M g / 2 and sinks by penetration / 2.
    # After 1.5 s it rests on both: each sphere's centre at r - penetration / 2, within 10 % of
    # that sinking, and still (1 mm/s).
    r, half, pen = 0.05, 0.2, 1e-4
    tilt = np.radians(10.0)
    q = [np.cos(tilt / 2), 0.0, np.sin(tilt / 2), 0.0]
    b = tumble.SceneBuilder()
    b.add_body("dumbbell", shape={"type": "sphere", "radius": r}, density=DENSITY,
               position=[0, 0, 0.3], orientation=q)
    b.set_body_pieces("dumbbell", [{"type": "sphere", "radius": r, "position": [-half, 0, 0]},
                                   {"type": "sphere", "radius": r, "position": [half, 0, 0]}])
    b.add_effect("gravity")
    b.add_effect("ground", penetration=pen)
    scene = b.build(method="cvode-bdf", rtol=1e-7, fps=100, duration=1.5)
    assert scene.piece_counts == [2]
    frames = scene.run()
    x, R = frames.position[-1, 0], rotation(frames.orientation[-1, 0])
    for end in (-half, half):
        z = (x + R @ np.array([end, 0.0, 0.0]))[2]
        assert abs((r - z) / (pen / 2) - 1) < 0.1, (end, r - z)
    assert np.linalg.norm(frames.velocity[-1, 0]) < 1e-3
