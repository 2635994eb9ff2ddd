"""The add-on's operators (bpy.ops.tumble.bake, export_scene, free_bake), its settings on the
scene and its panel in Scene properties."""
import json

import bpy

from . import bake, locate
from .scene_export import METHODS, read_scene
from .shapes import ShapeError

PASSIVE_MODES = (
    ("AUTO", "Auto", "Static bodies when the installed tumble has them, else a ground plane"),
    ("STATIC", "Static bodies", "Every passive body a static body of its shape"),
    ("GROUND", "Ground plane", "A level passive box under the active bodies as a ground plane"),
)


class TumbleSettings(bpy.types.PropertyGroup):
    method: bpy.props.EnumProperty(
        name="Method", default="rk4", description="tumble's integrator (docs/integrators.md)",
        items=[(m, m, f"tumble's {m}") for m in METHODS])
    passive: bpy.props.EnumProperty(name="Passive bodies", default="AUTO", items=PASSIVE_MODES)


class TumblePreferences(bpy.types.AddonPreferences):
    bl_idname = __package__
    python_path: bpy.props.StringProperty(
        name="tumble Python path", subtype="DIR_PATH",
        description="A folder holding the tumble package (a site-packages folder); "
                    "TUMBLE_PYTHON_PATH does the same")

    def draw(self, context):
        self.layout.prop(self, "python_path")


def preference(context):
    addon = context.preferences.addons.get(__package__)
    return addon.preferences.python_path if addon is not None else ""


def plan_scene(context, tumble):
    """The Plan for the scene, passive bodies mapped as the settings and the installed tumble
    allow (tumble None: as the scene format has them, static and keyframed bodies)."""
    settings = context.scene.tumble
    static = tumble is None or (locate.supports(tumble, "static") and
                                locate.supports(tumble, "keyframed"))
    if settings.passive == "STATIC" and not static:
        raise ShapeError("the installed tumble has no static or keyframed bodies: choose "
                         "Passive bodies > Ground plane, or update tumble")
    return read_scene(context.scene, context.evaluated_depsgraph_get(), settings.method,
                      settings.passive, static)


class TUMBLE_OT_bake(bpy.types.Operator):
    """Simulate the rigid bodies with tumble over the frame range and key every active body"""
    bl_idname = "tumble.bake"
    bl_label = "Bake with tumble"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        scene = context.scene
        world = scene.rigidbody_world
        if world is not None and not world.enabled and not scene.get(bake.WORLD_MARK):
            self.report({"ERROR"}, "the rigid body world is disabled (Scene > Rigid Body World)")
            return {"CANCELLED"}
        try:
            tumble = locate.import_tumble(preference(context))
        except locate.TumbleMissing as missing:
            self.report({"ERROR"}, str(missing))
            return {"CANCELLED"}
        bake.free(scene)
        try:
            plan = plan_scene(context, tumble)
            for obj in plan.active:
                bake.check_free_channels(obj)
            motions = self.simulate(context, tumble, plan)
        except (ShapeError, bake.BakeError) as refused:
            self.report({"ERROR"}, str(refused))
            return {"CANCELLED"}
        for obj in plan.active:
            bake.write_keys(obj, plan.frame_start, *motions[obj.name])
        if world is not None and world.enabled:
            world.enabled = False  # else Blender's own simulation overrides the keys
            scene[bake.WORLD_MARK] = True
        scene.frame_set(scene.frame_current)
        for note in plan.notes:  # what has no counterpart is a warning, a mapping a note
            self.report({"WARNING"} if "ignore" in note else {"INFO"}, note)
        self.report({"INFO"}, f"tumble baked {len(plan.active)} bodies, frames "
                              f"{plan.frame_start} to {plan.frame_end}")
        return {"FINISHED"}

    @staticmethod
    def simulate(context, tumble, plan):
        wm = context.window_manager
        wm.progress_begin(0, plan.frame_end - plan.frame_start)
        try:
            return bake.simulate(tumble, plan, wm.progress_update)
        finally:
            wm.progress_end()


class TUMBLE_OT_free_bake(bpy.types.Operator):
    """Remove the keys tumble baked (only those) and put the bodies back where they were"""
    bl_idname = "tumble.free_bake"
    bl_label = "Free tumble bake"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        freed = bake.free(context.scene)
        self.report({"INFO"}, f"tumble keys removed from {len(freed)} objects")
        return {"FINISHED"}


class TUMBLE_OT_export_scene(bpy.types.Operator):
    """Write the rigid bodies as a tumble scene file (tumble run FILE simulates it)"""
    bl_idname = "tumble.export_scene"
    bl_label = "Export tumble scene"
    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    filter_glob: bpy.props.StringProperty(default="*.json", options={"HIDDEN"})

    def invoke(self, context, event):
        if not self.filepath:
            self.filepath = bpy.path.ensure_ext(bpy.path.abspath("//") + "scene", ".json")
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        try:
            tumble = locate.import_tumble(preference(context))
        except locate.TumbleMissing:
            tumble = None  # a file can be written without tumble: in the full scene format
        try:
            plan = plan_scene(context, tumble)
            if tumble is not None:
                bake.load(tumble, plan)  # refused here, named, rather than by tumble run
        except (ShapeError, bake.BakeError) as refused:
            self.report({"ERROR"}, str(refused))
            return {"CANCELLED"}
        path = bpy.path.abspath(self.filepath)
        with open(path, "w", encoding="utf-8") as file:
            json.dump(plan.scene, file, indent=1)
            file.write("\n")
        self.report({"INFO"}, f"tumble scene written to {path}")
        return {"FINISHED"}


class TUMBLE_PT_panel(bpy.types.Panel):
    bl_label = "tumble"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "scene"

    def draw(self, context):
        layout = self.layout
        layout.prop(context.scene.tumble, "method")
        layout.prop(context.scene.tumble, "passive")
        row = layout.row()
        row.operator(TUMBLE_OT_bake.bl_idname, icon="PHYSICS")
        row.operator(TUMBLE_OT_free_bake.bl_idname, icon="X")
        layout.operator(TUMBLE_OT_export_scene.bl_idname, icon="EXPORT")


CLASSES = (TumbleSettings, TumblePreferences, TUMBLE_OT_bake, TUMBLE_OT_free_bake,
           TUMBLE_OT_export_scene, TUMBLE_PT_panel)
