# Plimsoll add-on for Blender (3.4, as Debian 12 ships it, and later): File > Import > Plimsoll
# bundle, File > Export > Plimsoll project. Install: copy or link this folder into Blender's
# scripts/addons/ and enable "Plimsoll" (blender/README.md).
bl_info = {
    "name": "Plimsoll",
    "author": "Plimsoll",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > Plimsoll bundle, File > Export > Plimsoll project",
    "description": "Import Plimsoll runtime bundles (mesh, painted maps, water graph, mass "
                   "properties); export a mesh as a Plimsoll project and validate it",
    "category": "Import-Export",
}

import bpy
from bpy.props import FloatProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from . import bundle_import, project_export


class PlimsollPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__

    plimsoll_path: StringProperty(
        name="plimsoll executable",
        description="Path of the plimsoll program (empty: $PLIMSOLL, else plimsoll on PATH)",
        subtype="FILE_PATH",
        default="")

    def draw(self, context):
        self.layout.prop(self, "plimsoll_path")


def preferences(context):
    addon = context.preferences.addons.get(__name__)
    return addon.preferences if addon else None


class PLIMSOLL_OT_import_bundle(bpy.types.Operator, ImportHelper):
    """Import a Plimsoll runtime bundle: pick its manifest.json"""
    bl_idname = "import_scene.plimsoll_bundle"
    bl_label = "Import Plimsoll bundle"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".json"
    filter_glob: StringProperty(default="manifest.json;*.gltf", options={"HIDDEN"})

    def execute(self, context):
        try:
            obj = bundle_import.import_bundle(self.filepath)
        except bundle_import.BundleError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Plimsoll bundle: {obj.name}, {len(obj.data.vertices)} vertices, "
                              f"{len(obj.children)} water-graph nodes, mass {obj['plimsoll_mass']:.6g} kg")
        return {"FINISHED"}


class PLIMSOLL_OT_export_project(bpy.types.Operator, ExportHelper):
    """Export the active mesh as a Plimsoll project (mesh + project JSON) and validate it"""
    bl_idname = "export_scene.plimsoll_project"
    bl_label = "Export Plimsoll project"

    filename_ext = ".plim.json"
    filter_glob: StringProperty(default="*.plim.json", options={"HIDDEN"})
    density: FloatProperty(name="Density", description="Uniform solid density, kg/m^3",
                           default=500.0, min=1e-6)
    texture_size: IntProperty(name="Texture size", description="Physics texture, texels per side",
                              default=256, min=8, max=8192)

    def execute(self, context):
        prefs = preferences(context)
        try:
            usable, text = project_export.export_project(
                context.active_object, self.filepath, self.density, self.texture_size,
                prefs.plimsoll_path if prefs else "")
        except project_export.ExportError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        first = text.splitlines()[0] if text else ""
        if usable is None:
            self.report({"WARNING"}, text)
        elif usable:
            self.report({"INFO"}, f"plimsoll validate: {first} (text block 'plimsoll validate')")
        else:
            self.report({"WARNING"}, f"plimsoll validate: {first} (text block 'plimsoll validate')")
        return {"FINISHED"}


def menu_import(self, context):
    self.layout.operator(PLIMSOLL_OT_import_bundle.bl_idname, text="Plimsoll bundle (manifest.json)")


def menu_export(self, context):
    self.layout.operator(PLIMSOLL_OT_export_project.bl_idname, text="Plimsoll project (.plim.json)")


classes = (PlimsollPreferences, PLIMSOLL_OT_import_bundle, PLIMSOLL_OT_export_project)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_import.append(menu_import)
    bpy.types.TOPBAR_MT_file_export.append(menu_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(menu_export)
    bpy.types.TOPBAR_MT_file_import.remove(menu_import)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
