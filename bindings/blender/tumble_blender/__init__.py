"""tumble for Blender: simulates the scene's rigid bodies (as Blender's rigid-body panels set
them up) with tumble and bakes the result as keys; writes the equivalent tumble scene file.

    bpy.ops.tumble.bake()                          # the frame range, keys on every active body
    bpy.ops.tumble.free_bake()                     # removes those keys (only those)
    bpy.ops.tumble.export_scene(filepath="x.json") # the scene file `tumble run` takes

docs/blender.md says how to install it and what maps from Blender's settings to tumble's."""

bl_info = {
    "name": "tumble for Blender",
    "author": "tumble's authors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Scene > tumble",
    "description": "Simulate rigid bodies with tumble and bake the keys",
    "category": "Physics",
}

import bpy  # noqa: E402

from .operators import CLASSES, TumbleSettings  # noqa: E402


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.tumble = bpy.props.PointerProperty(type=TumbleSettings)


def unregister():
    del bpy.types.Scene.tumble
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
