"""Renders a tumble glTF export in Blender (headless, Cycles on the CPU, denoising off): a
still PNG at a chosen time, or (--frames) the frames of an animation, or an MP4 of the motion. The camera looks at the
bodies' whole path from above and to the side, a sun lights them, the world is light grey.

    blender -b --factory-startup --python scripts/render_scene.py -- \
        FILE.glb OUT_STEM [--still-time T | --strobe N] [--frames N] [--movie] [--width 480]
        [--samples 16]

writes OUT_STEM.png (and OUT_STEM.mp4 with --movie, every frame up to 240, H.264). --frames N
instead writes OUT_STEM-NNNN.png, the motion at 12 pictures a simulated second (real time at
12 fps) or, for a run longer than N / 12 s, N pictures evenly over it: scripts/render_examples.sh
makes them an animated GIF with ffmpeg. --every T takes the pictures every T simulated seconds
instead (a stroboscope: at a spin's period the spin stands still and what else turns shows). --strobe N
draws each body at N evenly spaced times in one still (a multiple exposure of the motion);
--spread D moves the k-th copy by k D metres along x, a film strip of a body that stays put.
"""
import math
import sys

import numpy

numpy.bool = bool  # Blender 3.4's glTF importer still uses numpy.bool (NumPy 1.24 removed it)

import bpy  # noqa: E402
import mathutils  # noqa: E402


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:]
    options = {"--still-time": None, "--strobe": 0, "--spread": 0.0, "--width": 480, "--samples": 16,
               "--movie": False, "--frames": 0, "--every": 0.0}
    positional = []
    while argv:
        item = argv.pop(0)
        if item == "--movie":
            options[item] = True
        elif item in options:
            options[item] = float(argv.pop(0))
        else:
            positional.append(item)
    return positional[0], positional[1], options


def body_objects():
    return [o for o in bpy.data.objects
            if o.type == "MESH" and o.animation_data and o.animation_data.action]


def motion_bounds(scene, objects, animated=True):
    """Corners of the box holding every body at every frame (sampled)."""
    low = mathutils.Vector((math.inf,) * 3)
    high = mathutils.Vector((-math.inf,) * 3)
    step = max(1, (scene.frame_end - scene.frame_start) // 60)
    last = scene.frame_end if animated else scene.frame_start
    for frame in range(scene.frame_start, last + 1, step):
        scene.frame_set(frame)
        for o in objects:
            for corner in o.bound_box:
                p = o.matrix_world @ mathutils.Vector(corner)
                low = mathutils.Vector(map(min, low, p))
                high = mathutils.Vector(map(max, high, p))
    return low, high


def strobe(scene, objects, count, spread):
    """Copies of each body, fixed at count evenly spaced frames (the k-th moved k spread
    metres along x); the animated ones hidden. Returns the copies."""
    start, end = scene.frame_start, scene.frame_end
    copies = []
    for o in objects:
        for k in range(count):
            scene.frame_set(round(start + (end - start) * k / max(count - 1, 1)))
            placed = mathutils.Matrix.Translation((k * spread, 0, 0)) @ o.matrix_world
            last = copies[-1][0].matrix_world.translation if copies and copies[-1][1] is o else None
            if last is not None and (last - placed.translation).length < 0.5 * o.dimensions.length:
                continue  # overlapping the last copy (at rest): its faces would fight
            copy = o.copy()
            copy.animation_data_clear()
            copy.parent = None
            copy.matrix_world = placed
            scene.collection.objects.link(copy)
            copies.append((copy, o))
        o.hide_render = True
    return [copy for copy, _ in copies]


def add_camera_and_light(scene, low, high):
    """A camera looking at the box (low, high) from above and to the side, as close as lets
    every corner of the box into the 16:9 picture; a sun; a grey world."""
    centre = (low + high) / 2
    direction = mathutils.Vector((1.0, -1.6, 0.9)).normalized()  # from the centre to the camera
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.data.lens = 50
    turn = (-direction).to_track_quat("-Z", "Y")
    right, up = turn @ mathutils.Vector((1, 0, 0)), turn @ mathutils.Vector((0, 1, 0))
    half_width = math.atan(camera.data.sensor_width / 2 / camera.data.lens)
    half_height = math.atan(math.tan(half_width) * 9 / 16)
    distance = 0.0  # as close as the bounds allow (a small body fills the picture)
    for corner in [mathutils.Vector((x, y, z)) for x in (low.x, high.x)
                   for y in (low.y, high.y) for z in (low.z, high.z)]:
        d = corner - centre
        depth = d.dot(direction)  # towards the camera
        distance = max(distance, depth + abs(d.dot(right)) / math.tan(half_width),
                       depth + abs(d.dot(up)) / math.tan(half_height))
    camera.location = centre + direction * distance * 1.15
    camera.rotation_euler = turn.to_euler()
    camera.data.clip_end = distance * 100
    scene.collection.objects.link(camera)
    scene.camera = camera
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 4.0
    sun.rotation_euler = (math.radians(40), math.radians(15), math.radians(30))
    scene.collection.objects.link(sun)
    scene.world = bpy.data.worlds.new("world")
    scene.world.color = (0.35, 0.37, 0.40)


def set_up_render(scene, options):
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = int(options["--samples"])
    scene.cycles.use_denoising = False
    scene.render.resolution_x = int(options["--width"])
    scene.render.resolution_y = int(options["--width"] * 9 / 16)
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False


def render_every(scene, stem, seconds):
    """A picture every `seconds` of simulated time (between Blender's frames if need be)."""
    k = 0
    while k * seconds * scene.render.fps <= scene.frame_end - scene.frame_start:
        frame = scene.frame_start + k * seconds * scene.render.fps
        scene.frame_set(int(frame), subframe=frame - int(frame))
        scene.render.filepath = f"{stem}-{k:04d}.png"
        bpy.ops.render.render(write_still=True)
        k += 1


def render_frames(scene, stem, count):
    """The motion as PNG pictures, 12 a simulated second (Blender's 24 frames a second: every
    second frame) or count of them evenly over a longer run."""
    length = scene.frame_end - scene.frame_start
    scene.frame_step = max(2, math.ceil(length / max(count - 1, 1)))
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = stem + "-"
    bpy.ops.render.render(animation=True)


def main():
    path, stem, options = arguments()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.import_scene.gltf(filepath=path)
    objects = body_objects()
    start, end = (int(v) for v in bpy.data.actions[0].frame_range)
    scene.frame_start, scene.frame_end = start, end
    if options["--strobe"] > 0 and options["--frames"] == 0 and options["--every"] == 0:
        copies = strobe(scene, objects, int(options["--strobe"]), options["--spread"])
        scene.frame_set(start)
        add_camera_and_light(scene, *motion_bounds(scene, copies, animated=False))
    else:
        add_camera_and_light(scene, *motion_bounds(scene, objects))
    set_up_render(scene, options)
    if options["--every"] > 0:
        scene.render.image_settings.file_format = "PNG"
        scene.render.image_settings.color_mode = "RGB"
        render_every(scene, stem, options["--every"])
        return
    if options["--frames"] > 0:
        render_frames(scene, stem, int(options["--frames"]))
        return
    time = options["--still-time"]
    scene.frame_set(int(time * scene.render.fps) if time is not None else (start + end) // 2)
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = stem + ".png"
    bpy.ops.render.render(write_still=True)
    if options["--movie"]:
        scene.frame_end = min(end, start + 240)
        scene.render.image_settings.file_format = "FFMPEG"
        scene.render.ffmpeg.format = "MPEG4"
        scene.render.ffmpeg.codec = "H264"
        scene.render.ffmpeg.constant_rate_factor = "MEDIUM"
        scene.render.filepath = stem + ".mp4"
        bpy.ops.render.render(animation=True)


if __name__ == "__main__":
    main()
