"""The Blender scene's rigid bodies as a tumble scene (the scene-file JSON of
docs/scene-format.md), read as Blender's own rigid-body panels set them up.

    plan = read_scene(context.scene, context.evaluated_depsgraph_get(), method="rk4",
                      passive="AUTO", static_supported=True)
    plan.scene          # the dict a scene file holds
    plan.objects        # body name -> Blender object (the names are the objects' names)
    plan.active         # the objects whose motion tumble computes (their keys are baked)

Frames: a body's shape frame is its object's frame without the scale (docs/blender.md), so the
CSV's and the library's shape-frame pose is the object's location and rotation. `position` is
the centre of mass: the object's origin for the primitive shapes, which Blender and tumble
both centre there, and the origin plus the rotated centre of a hull or cone.
"""
import math

import numpy as np

from .shapes import ShapeError, dimensions, f32, hull, shape_of, vec, volume_moments

METHODS = ("rk4", "midpoint", "euler", "cvode-adams", "cvode-bdf", "rosenbrock", "ark-imex")
FLAT = 1e-6  # a ground plane's normal must be within this of the world's z (radians)


class Plan:
    def __init__(self):
        self.scene = {}
        self.objects = {}
        self.active = []
        self.notes = []  # what was mapped approximately, for the operator's report
        self.frame_start = 1
        self.frame_end = 1
        self.fps = 24.0


def frame_range(scene):
    """Blender simulates rigid bodies over the world's point cache range (the Scene panel's
    Rigid Body World > Cache), else the scene's frame range."""
    world = scene.rigidbody_world
    if world is not None and world.point_cache is not None:
        return world.point_cache.frame_start, world.point_cache.frame_end
    return scene.frame_start, scene.frame_end


def rigid_objects(scene):
    world = scene.rigidbody_world
    if world is None:
        raise ShapeError("the scene has no rigid body world (Scene properties > Rigid Body "
                         "World, or Physics > Rigid Body on an object)")
    found = world.collection.objects if world.collection is not None else scene.objects
    return sorted((o for o in found if o.rigid_body is not None), key=lambda o: o.name)


def quaternion_of(obj):
    """The object's rotation as a unit quaternion (w, x, y, z) in double precision, from its
    own rotation values in its rotation mode (Euler 'XYZ' turns about x first: R = Rz Ry Rx)."""
    mode = obj.rotation_mode
    if mode == "QUATERNION":
        q = np.array(vec(obj.rotation_quaternion))
    elif mode == "AXIS_ANGLE":
        angle, *axis = vec(obj.rotation_axis_angle)
        axis = np.array(axis) / max(np.linalg.norm(axis), 1e-300)
        q = np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * axis])
    else:
        q = euler_quaternion(vec(obj.rotation_euler), mode)
    return q / np.linalg.norm(q)


def euler_quaternion(angles, order):
    """Blender's Euler angles (x, y, z) in an order such as 'ZXY' (the first axis turned first:
    R = R_Y R_X R_Z) as a quaternion, in double precision."""
    q = np.array([1.0, 0, 0, 0])
    for axis in order:
        i = "XYZ".index(axis)
        turn = np.zeros(4)
        turn[0], turn[1 + i] = math.cos(angles[i] / 2), math.sin(angles[i] / 2)
        q = quaternion_multiply(turn, q)
    return q


def quaternion_multiply(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def rotate(q, v):
    w, u = q[0], np.asarray(q[1:])
    return v + 2 * np.cross(u, np.cross(u, v) + w * v)


def world_pose(obj):
    """(origin (3,), quaternion (4,)) of the object in the world: from its own values when it
    has no parent (exact), else from its world matrix (Blender's single precision)."""
    if obj.parent is None and not has_delta(obj):
        return np.array(vec(obj.location)), quaternion_of(obj)
    location, rotation, _ = obj.matrix_world.decompose()
    q = np.array(rotation, dtype=np.float64)
    return np.array(location, dtype=np.float64), q / np.linalg.norm(q)


def has_delta(obj):
    return (any(obj.delta_location) or any(obj.delta_rotation_euler) or
            tuple(obj.delta_rotation_quaternion) != (1.0, 0.0, 0.0, 0.0))


def motion_of(obj):
    """'dynamic', 'static' or 'keyframed', as Blender treats the body: an Active body with
    Dynamic off, or any body with Animated on, follows its animation."""
    rb = obj.rigid_body
    if rb.kinematic or (rb.type == "ACTIVE" and not rb.enabled):
        return "keyframed"
    return "dynamic" if rb.type == "ACTIVE" else "static"


def check_active(obj):
    if obj.parent is not None:
        raise ShapeError(f"'{obj.name}': an active rigid body with a parent ('{obj.parent.name}'"
                         f"): tumble bakes world keys; clear the parent (Alt-P, Keep Transform)")
    if has_delta(obj):
        raise ShapeError(f"'{obj.name}': an active rigid body with delta transforms: apply "
                         f"them (Object > Apply > All Transforms to Deltas, reversed) or clear "
                         f"them; tumble bakes the location and rotation")
    if not obj.rigid_body.mass > 0:
        raise ShapeError(f"'{obj.name}': mass must be > 0, got {obj.rigid_body.mass:g}")


def body_of(obj, depsgraph, motion, keys):
    """The body's dict, its mean moment per kg and its centre of mass in the shape frame."""
    shape, centre, per_kg = shape_of(obj, depsgraph)
    origin, q = world_pose(obj)
    body = {"name": obj.name}
    if motion != "dynamic":
        body["motion"] = motion
    body["shape"] = shape
    if motion == "dynamic":
        body["mass"] = f32(obj.rigid_body.mass)
    if motion == "keyframed":
        body["interpolation"] = "linear"
        body["keys"] = [{"t": t, "position": [float(x) for x in p + rotate(k, centre)],
                         "orientation": [float(x) for x in k]} for t, p, k in keys]
    else:
        body["position"] = [float(x) for x in origin + rotate(q, centre)]
        body["orientation"] = [float(x) for x in q]
    return body, per_kg


def sample_keys(scene, objects, start, end, fps):
    """Each keyframed object's world pose at every frame of the range, at t = (f - start) / fps."""
    keys = {o.name: [] for o in objects}
    if not objects:
        return keys
    current = scene.frame_current
    try:
        for frame in range(start, end + 1):
            scene.frame_set(frame)
            for obj in objects:
                origin, q = world_pose(obj)
                previous = keys[obj.name][-1][2] if keys[obj.name] else q
                q = -q if q @ previous < 0 else q  # the nearer sign: linear keys turn the short way
                keys[obj.name].append(((frame - start) / fps, origin, q))
    finally:
        scene.frame_set(current)
    return keys


def gravity_of(scene):
    """Scene > Gravity times the world's Field Weights > Gravity (Blender multiplies only that
    weight into the rigid bodies' gravity), zero when Scene > Gravity is off."""
    if not scene.use_gravity:
        return [0.0, 0.0, 0.0]
    weight = f32(scene.rigidbody_world.effector_weights.gravity)
    return [f32(g) * weight for g in scene.gravity]


def damping(obj, mass, per_kg):
    """Bullet multiplies the velocities by (1 - d)^dt each step, an exponential decay at the rate
    -ln(1 - d) per second: a drag of M times that rate (linear) gives the same decay exactly,
    and the mean moment times it (angular) gives it exactly for spheres and cubes."""
    rb = obj.rigid_body
    drag = {}
    for key, d, scale in (("linear", f32(rb.linear_damping), mass),
                          ("angular", f32(rb.angular_damping), mass * per_kg)):
        if d >= 1:
            raise ShapeError(f"'{obj.name}': {key}_damping 1 stops the body dead; tumble's drag "
                             f"needs a damping below 1")
        if d > 0:
            drag[key] = -math.log1p(-d) * scale
    if not drag:
        return None
    return dict({"type": "drag", "body": obj.name}, **drag)


def material(a, b):
    """Bullet's combined coefficients: products of the two bodies' (btManifoldResult)."""
    fa, fb = f32(a.rigid_body.friction), f32(b.rigid_body.friction)
    ea, eb = f32(a.rigid_body.restitution), f32(b.rigid_body.restitution)
    return (fa * fb, min(ea * eb, 1.0))


def contact(bodies, pair_material, g):
    friction, restitution = pair_material
    effect = {"type": "contact", "bodies": bodies, "restitution": restitution,
              "static_friction": friction, "kinetic_friction": friction}
    if g > 0:
        effect["gravity"] = g
    return effect


def contacts(colliders, g, apart=()):
    """One contact effect when every pair has the same material and none is kept apart (a
    constraint's Disable Collisions), else one per pair (tumble takes one material per effect,
    and a pair in no more than one effect)."""
    pairs = [(a, b) for i, a in enumerate(colliders) for b in colliders[i + 1:]
             if "dynamic" in (motion_of(a), motion_of(b)) and
             frozenset((a.name, b.name)) not in apart]
    materials = {material(a, b) for a, b in pairs}
    if len(materials) <= 1 and not apart:
        return [contact([o.name for o in colliders], materials.pop(), g)] if pairs else []
    return [contact([a.name, b.name], material(a, b), g) for a, b in pairs]


def is_flat(obj):
    """An object with no thickness (Blender's Plane): it cannot be a solid body."""
    return min(dimensions(obj)) == 0


def fills_its_box(obj, depsgraph):
    """Whether a Convex Hull or Mesh shape is its bounding box (a box mesh with Blender's default
    shape): the hull's volume is the box's, to 1e-6."""
    if obj.rigid_body.collision_shape not in ("CONVEX_HULL", "MESH"):
        return False
    dx, dy, dz = dimensions(obj)
    try:
        volume = volume_moments(*hull(obj, depsgraph))[0]
    except ShapeError:
        return False
    return abs(volume - dx * dy * dz) <= 1e-6 * dx * dy * dz


def plane_like(obj, active, depsgraph):
    """The height of a ground plane for a passive body that does not move, stands level (its z
    axis up), lies under every active body's origin and is a box (its top face: Blender centres
    the Box shape on the origin; a hull that fills its bounding box), or is flat (a Plane, or a
    slab a tenth as thick as it is wide, of any shape: the top of its mesh's bounding box); None
    for any other."""
    dx, dy, dz = dimensions(obj)
    box = obj.rigid_body.collision_shape == "BOX"
    if motion_of(obj) != "static" or not (box or dz <= 0.1 * min(dx, dy) or
                                          fills_its_box(obj, depsgraph)):
        return None
    origin, q = world_pose(obj)
    up = rotate(q, np.array([0.0, 0.0, 1.0]))
    if not up[2] > math.cos(FLAT):
        return None
    top = dz / 2
    if not box:
        corners = [c[2] for c in obj.bound_box]
        top = max(corners) * abs(f32(obj.scale[2])) if obj.parent is None else top
    for body in active:
        local = rotate(q * [1, -1, -1, -1], world_pose(body)[0] - origin)
        if not (local[2] > top and abs(local[0]) <= dx / 2 and abs(local[1]) <= dy / 2):
            return None
    return origin[2] + top


def ground_for(obj, active, g):
    """The passive box's top face as a ground plane; its material with the active bodies' by
    Bullet's products (the mean when they differ: one plane has one material)."""
    pairs = [material(obj, body) for body in active] or [material(obj, obj)]
    friction = sum(p[0] for p in pairs) / len(pairs)
    restitution = sum(p[1] for p in pairs) / len(pairs)
    effect = {"type": "ground", "normal": [0.0, 0.0, 1.0], "offset": None,
              "restitution": restitution, "static_friction": friction,
              "kinetic_friction": friction}
    if g > 0:
        effect["gravity"] = g
    return effect, len(set(pairs)) > 1


def read_scene(scene, depsgraph, method="rk4", passive="AUTO", static_supported=True):
    """The Plan of the scene at the start of its frame range. passive: 'STATIC' (passive
    bodies as static bodies), 'GROUND' (a level passive box under the active bodies as a ground
    plane, any other passive body refused), 'AUTO' (static bodies when the installed tumble has
    them, else as 'GROUND'). Raises ShapeError naming the object and the value."""
    if method not in METHODS:
        raise ShapeError(f"method: must be one of {', '.join(METHODS)}, got {method!r}")
    plan = Plan()
    plan.frame_start, plan.frame_end = frame_range(scene)
    plan.fps = scene.render.fps / f32(scene.render.fps_base)
    if plan.frame_end <= plan.frame_start:
        raise ShapeError(f"frame range {plan.frame_start}..{plan.frame_end}: the end must be "
                         f"after the start")
    world = scene.rigidbody_world
    objects = rigid_objects(scene)
    if not objects:
        raise ShapeError("the rigid body world holds no rigid bodies")
    use_ground = passive == "GROUND" or (passive == "AUTO" and not static_supported)
    current, enabled = scene.frame_current, world.enabled
    world.enabled = False  # Blender's own simulation would run at every frame we visit
    try:
        scene.frame_set(plan.frame_start)
        return fill(plan, scene, depsgraph, objects, method, use_ground, world)
    finally:
        world.enabled = enabled
        scene.frame_set(current)


def fill(plan, scene, depsgraph, objects, method, use_ground, world):
    from .joints import read_joints  # joints.py reads poses with this module's helpers

    g_vector = gravity_of(scene)
    g = math.sqrt(sum(x * x for x in g_vector))
    plan.active = [o for o in objects if motion_of(o) == "dynamic"]
    for obj in plan.active:
        check_active(obj)
        if any(obj.lock_location) or any(obj.lock_rotation):
            plan.notes.append(f"'{obj.name}': its transform locks hold Bullet's body to axes; "
                              f"tumble has no counterpart and ignores them")
    keyframed = [o for o in objects if motion_of(o) == "keyframed"]
    keys = sample_keys(scene, keyframed, plan.frame_start, plan.frame_end, plan.fps)
    bodies, effects, colliders, grounds = [], [], [], []
    for obj in objects:
        motion = motion_of(obj)
        if motion != "dynamic" and (use_ground or is_flat(obj)):
            top = plane_like(obj, plan.active, depsgraph)
            if top is None and is_flat(obj):
                raise ShapeError(f"'{obj.name}': a flat passive object (no thickness) becomes a "
                                 f"ground plane only when level, still and under every active "
                                 f"body; give it a thickness to make it a static body")
            if top is None:
                raise ShapeError(
                    f"'{obj.name}': a {'passive' if motion == 'static' else 'animated'} body, "
                    f"and the installed tumble has no {motion} bodies: only a level passive "
                    f"box, or a flat passive object, under every active body can become a "
                    f"ground plane (update tumble)")
            ground, mixed = ground_for(obj, plan.active, g)
            ground["offset"] = top
            grounds.append(ground)
            plan.notes.append(f"'{obj.name}': the ground plane z = {top:g}" +
                              (" (its friction the mean over the bodies)" if mixed else ""))
            continue
        body, per_kg = body_of(obj, depsgraph, motion, keys.get(obj.name))
        bodies.append(body)
        plan.objects[obj.name] = obj
        colliders.append(obj)
        if motion == "dynamic":
            drag = damping(obj, body["mass"], per_kg)
            if drag is not None:
                effects.append(drag)
    if not plan.active:
        raise ShapeError("no active rigid body: nothing for tumble to simulate")
    if g > 0:
        effects.insert(0, {"type": "gravity", "g": g_vector})
    joints, apart = read_joints(world, plan.objects, plan.fps, plan.notes)
    effects += contacts(colliders, g, apart) + grounds
    duration = (plan.frame_end - plan.frame_start) / plan.fps
    plan.scene = {"description": f"Blender scene '{scene.name}', frames {plan.frame_start} to "
                                 f"{plan.frame_end} at {plan.fps:g} fps (tumble for Blender)",
                  "bodies": bodies, "effects": effects}
    if joints:
        plan.scene["joints"] = joints
    plan.scene.update({"integrator": {"method": method},
                       "output": {"fps": plan.fps, "duration": duration}})
    if world.time_scale != 1:
        plan.notes.append(f"the world's speed {world.time_scale:g} has no counterpart: ignored")
    return plan
