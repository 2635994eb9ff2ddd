"""A Blender rigid body's collision shape as a tumble shape, with what the scene needs of its
mass properties (centre of mass, mean moment of inertia).

Frames: the tumble shape frame is the object's own frame without its scale (origin at the
object's origin, axes its rotated axes); the object's scale is applied to the sizes and the
vertices. Blender (rigidbody.c, rigidbody_validate_sim_shape) centres every primitive shape on
the object's origin, sizes it from the object's bounding box (obj.dimensions: the box times
the scale) and stands capsules, cylinders and cones on the local z axis; tumble's primitives
are centred on the shape frame's origin along z as well, so these map one to one.
"""
import math

import numpy as np

CONE_SEGMENTS = 32  # tumble has no cone: a 32-sided pyramid (its volume 0.6% under the cone's)


class ShapeError(ValueError):
    """A shape tumble cannot take; the message names the object and the value."""


def f32(value):
    """A float32 value Blender stores (0.1 is kept as 0.10000000149011612) as the shortest
    decimal that reads back as the same float32, so that a scene file says 0.1."""
    return float(str(np.float32(value)))


def vec(values):
    return [f32(v) for v in values]


def dimensions(obj):
    """The shape's box, m: the object's local bounding box times its world scale (what Blender
    sizes the shape by, rigidbody.c), in double precision from Blender's single-precision
    values (obj.dimensions goes through the world matrix and may be off by an ulp)."""
    corners = np.array([tuple(c) for c in obj.bound_box], dtype=np.float64)
    box = corners.max(axis=0) - corners.min(axis=0)
    if obj.parent is None:
        scale = np.abs(np.array(vec(obj.scale)))
    else:
        scale = np.array(obj.matrix_world.to_scale(), dtype=np.float64)
    return [f32(x) for x in box * np.abs(scale)]


def shape_of(obj, depsgraph):
    """(shape dict, centre of mass in the shape frame (3,), mean principal moment per kg).

    The mean moment per kg, trace(I) / (3 M), is what the angular damping is scaled by."""
    kind = obj.rigid_body.collision_shape
    dx, dy, dz = dimensions(obj)
    origin = np.zeros(3)
    if kind == "BOX":
        return ({"type": "box", "size": [dx, dy, dz]}, origin, (dx * dx + dy * dy + dz * dz) / 18)
    if kind == "SPHERE":
        r = max(dx, dy, dz) / 2  # Blender encloses the whole box
        return {"type": "sphere", "radius": r}, origin, 0.4 * r * r
    if kind in ("CAPSULE", "CYLINDER"):
        r = max(dx, dy) / 2
        if kind == "CYLINDER":
            moments = (0.5 * r * r + 2 * (3 * r * r + dz * dz) / 12) / 3
            return {"type": "cylinder", "radius": r, "length": dz}, origin, moments
        length = max(dz - 2 * r, 0.0)  # Blender: the total length is dz, tumble's the middle
        moments = (0.5 * r * r + 2 * (3 * r * r + dz * dz) / 12) / 3  # as a cylinder of dz
        return {"type": "capsule", "radius": r, "length": length}, origin, moments
    if kind == "CONE":
        vertices, triangles = cone(max(dx, dy) / 2, dz)
    elif kind in ("CONVEX_HULL", "MESH"):
        vertices, triangles = hull(obj, depsgraph)
    else:
        raise ShapeError(f"'{obj.name}': collision shape {kind} has no counterpart in tumble "
                         f"(use Box, Sphere, Capsule, Cylinder, Cone, Convex Hull or Mesh)")
    return mesh_shape(obj, vertices, triangles)


def cone(radius, height):
    """A cone along z centred on its box's centre, apex up (Bullet's btConeShapeZ)."""
    angles = 2 * math.pi * np.arange(CONE_SEGMENTS) / CONE_SEGMENTS
    rim = [[radius * math.cos(a), radius * math.sin(a), -height / 2] for a in angles]
    vertices = np.array(rim + [[0.0, 0.0, height / 2], [0.0, 0.0, -height / 2]])
    apex, base, n = CONE_SEGMENTS, CONE_SEGMENTS + 1, CONE_SEGMENTS
    triangles = [[i, (i + 1) % n, apex] for i in range(n)]
    triangles += [[i, base, (i + 1) % n] for i in range(n)]
    return vertices, triangles


def hull(obj, depsgraph):
    """The convex hull of the object's mesh (its evaluated mesh unless the rigid body's Source
    is Base), scaled into the shape frame, as (vertices (n, 3), outward triangles). tumble
    collides a mesh as its convex hull, so Blender's concave Mesh shape becomes its hull too."""
    import bmesh

    source = obj if obj.rigid_body.mesh_source == "BASE" else obj.evaluated_get(depsgraph)
    mesh = source.to_mesh()
    try:
        local = [tuple(v.co) for v in mesh.vertices]
    finally:
        source.to_mesh_clear()
    if len(local) < 4:
        raise ShapeError(f"'{obj.name}': a convex hull needs 4 vertices, the mesh has "
                         f"{len(local)}")
    bm = bmesh.new()
    try:
        for co in local:
            bm.verts.new(co)
        made = bmesh.ops.convex_hull(bm, input=list(bm.verts), use_existing_faces=False)
        unused = list({v for v in made["geom_interior"] + made["geom_unused"]
                       if isinstance(v, bmesh.types.BMVert)})
        bmesh.ops.delete(bm, geom=unused, context="VERTS")
        bmesh.ops.triangulate(bm, faces=list(bm.faces))
        bm.verts.index_update()
        # the float32 mesh coordinates, exactly, then the scale in double precision
        vertices = np.array([tuple(v.co) for v in bm.verts], dtype=np.float64)
        triangles = [[v.index for v in f.verts] for f in bm.faces]
    finally:
        bm.free()
    vertices *= np.array(vec(obj.scale))
    if volume_moments(vertices, triangles)[0] < 0:  # wound inward (a negative scale)
        triangles = [[a, c, b] for a, b, c in triangles]
    return vertices, triangles


def volume_moments(vertices, triangles):
    """(volume, first moment (3,), second moment matrix (3, 3)) of a closed triangle mesh, by
    the divergence theorem over the tetrahedra from the origin to each triangle: a tetrahedron
    (0, a, b, c) of signed volume V has first moment V (a + b + c) / 4 and second moment
    V / 20 (a a^T + b b^T + c c^T + s s^T) with s = a + b + c."""
    t = np.asarray(triangles)
    a, b, c = vertices[t[:, 0]], vertices[t[:, 1]], vertices[t[:, 2]]
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6
    s = a + b + c
    first = (volume[:, None] * s).sum(axis=0) / 4
    outer = np.einsum("ni,nj->nij", a, a) + np.einsum("ni,nj->nij", b, b)
    outer += np.einsum("ni,nj->nij", c, c) + np.einsum("ni,nj->nij", s, s)
    second = (volume[:, None, None] * outer).sum(axis=0) / 20
    return volume.sum(), first, second


def mesh_shape(obj, vertices, triangles):
    volume, first, second = volume_moments(vertices, triangles)
    if not volume > 0:
        raise ShapeError(f"'{obj.name}': its collision hull has no volume ({volume:g} m^3)")
    centre = first / volume
    # trace(I) about the centre of mass per kg: 2 (E|r|^2 - |c|^2) (uniform density)
    per_kg = 2 * (np.trace(second) / volume - centre @ centre) / 3
    shape = {"type": "mesh", "vertices": [[float(x) for x in v] for v in vertices],
             "triangles": [[int(i) for i in t] for t in triangles]}
    return shape, centre, per_kg
