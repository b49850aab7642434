# Plimsoll add-on for Blender (3.4, as Debian 12 ships it, and later): File > Import > Plimsoll
# bundle, File > Export > Plimsoll project, and through the Plimsoll Python module the View3D
# sidebar's Plimsoll tab: mass properties of the selected object, and the object floated on
# waves as keyframes. Install: copy or link this folder into Blender's scripts/addons/ and
# enable "Plimsoll" (blender/README.md).
bl_info = {
    "name": "Plimsoll",
    "author": "Plimsoll",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > Plimsoll bundle, File > Export > Plimsoll project, "
                "View3D > Sidebar > Plimsoll",
    "description": "Import Plimsoll runtime bundles (mesh, painted maps, water graph, mass "
                   "properties); export a mesh as a Plimsoll project and validate it; bake the "
                   "selected object's mass properties and float it on waves as keyframes",
    "category": "Import-Export",
}

import bpy
from bpy.props import FloatProperty, IntProperty, PointerProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from . import bundle_import, float_object, project_export


class PlimsollPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__

    plimsoll_path: StringProperty(
        name="plimsoll executable",
        description="Path of the plimsoll program (empty: $PLIMSOLL, else plimsoll on PATH)",
        subtype="FILE_PATH",
        default="")

    module_path: StringProperty(
        name="Python module folder",
        description="Folder holding the plimsoll Python module (plimsoll.cpython-*.so; empty: "
                    "$PLIMSOLL_PYTHON_PATH, else Blender's own Python path)",
        subtype="DIR_PATH",
        default="")

    def draw(self, context):
        self.layout.prop(self, "plimsoll_path")
        self.layout.prop(self, "module_path")


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


class PlimsollSettings(bpy.types.PropertyGroup):
    """The sidebar's settings (per scene)."""
    texture_size: IntProperty(name="Texture size", description="Physics texture, texels per side",
                              default=128, min=8, max=8192)
    density: FloatProperty(name="Density", description="Uniform solid density, kg/m^3",
                           default=500.0, min=1e-6)
    seconds: FloatProperty(name="Seconds", description="Simulated time, s", default=5.0, min=0.0)
    fps: FloatProperty(name="Frames per second",
                       description="Frames per simulated second: the time step (0: the scene's)",
                       default=0.0, min=0.0)
    amplitude: FloatProperty(name="Wave amplitude", description="m (0: flat water)",
                             default=0.2, min=0.0)
    wavelength: FloatProperty(name="Wavelength", description="m", default=8.0, min=0.01)
    direction: FloatProperty(name="Wave direction", description="Degrees from +x", default=0.0)
    steepness: FloatProperty(name="Steepness", description="Gerstner steepness, 0..1",
                             default=0.5, min=0.0, max=1.0)
    wave_count: IntProperty(name="Waves", description="Gerstner waves (each further one half "
                            "as high, 0.6 times as long, turned 35 degrees)",
                            default=2, min=1, max=16)
    folder: StringProperty(name="Work folder", description="Where the mesh and project are "
                           "written (empty: Blender's temporary folder)", subtype="DIR_PATH",
                           default="")


def module_path(context):
    prefs = preferences(context)
    return prefs.module_path if prefs else ""


class PLIMSOLL_OT_mass_properties(bpy.types.Operator):
    """Bake the selected mesh object with Plimsoll and show its mass properties"""
    bl_idname = "object.plimsoll_mass_properties"
    bl_label = "Bake and mass properties"
    bl_options = {"REGISTER", "UNDO"}

    texture_size: IntProperty(name="Texture size", default=128, min=8, max=8192)
    density: FloatProperty(name="Density", description="kg/m^3", default=500.0, min=1e-6)

    def invoke(self, context, event):
        settings = context.scene.plimsoll
        self.texture_size, self.density = settings.texture_size, settings.density
        return self.execute(context)

    def execute(self, context):
        try:
            result = float_object.mass_properties(
                context.active_object, self.texture_size, self.density,
                context.scene.plimsoll.folder, module_path(context))
        except float_object.FloatError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Plimsoll: mass {result['mass']:.6g} kg, volume "
                              f"{result['volume']:.6g} m^3 ({self.texture_size}^2 texels)")
        return {"FINISHED"}


class PLIMSOLL_OT_float(bpy.types.Operator):
    """Float the selected mesh object on waves with Plimsoll and keyframe its motion"""
    bl_idname = "object.plimsoll_float"
    bl_label = "Float on waves"
    bl_options = {"REGISTER", "UNDO"}

    seconds: FloatProperty(name="Seconds", default=5.0, min=0.0)
    fps: FloatProperty(name="Frames per second", description="0: the scene's", default=0.0, min=0.0)
    texture_size: IntProperty(name="Texture size", default=128, min=8, max=8192)
    density: FloatProperty(name="Density", description="kg/m^3", default=500.0, min=1e-6)
    amplitude: FloatProperty(name="Wave amplitude", description="m (0: flat water)", default=0.2, min=0.0)
    wavelength: FloatProperty(name="Wavelength", description="m", default=8.0, min=0.01)
    direction: FloatProperty(name="Wave direction", description="Degrees from +x", default=0.0)
    steepness: FloatProperty(name="Steepness", default=0.5, min=0.0, max=1.0)
    wave_count: IntProperty(name="Waves", default=2, min=1, max=16)

    def invoke(self, context, event):
        s = context.scene.plimsoll
        for name in ("seconds", "fps", "texture_size", "density", "amplitude", "wavelength",
                     "direction", "steepness", "wave_count"):
            setattr(self, name, getattr(s, name))
        return self.execute(context)

    def execute(self, context):
        try:
            run = float_object.simulate_keyframes(
                context.active_object, self.seconds, self.fps or None, self.density,
                self.texture_size, self.amplitude, self.wavelength, self.direction,
                self.steepness, self.wave_count, context.scene.plimsoll.folder,
                module_path(context))
        except float_object.FloatError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Plimsoll: {len(run['time'])} frames keyframed ({run['device']})")
        return {"FINISHED"}


class PLIMSOLL_PT_sidebar(bpy.types.Panel):
    bl_label = "Plimsoll"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Plimsoll"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.plimsoll
        obj = context.active_object
        layout.prop(settings, "texture_size")
        layout.prop(settings, "density")
        layout.operator(PLIMSOLL_OT_mass_properties.bl_idname)
        if obj is not None and "plimsoll_mass" in obj:
            box = layout.box()
            box.label(text=f"{obj.name}, {obj.get('plimsoll_texture_size', '?')}^2 texels "
                           "(Plimsoll axes, y up)")
            for label, prefix in (("texture", "plimsoll_"), ("exact", "plimsoll_exact_")):
                if prefix + "mass" not in obj:
                    continue
                c = obj[prefix + "center_of_mass"]
                box.label(text=f"{label}: mass {obj[prefix + 'mass']:.6g} kg, "
                               f"volume {obj[prefix + 'volume']:.6g} m^3")
                box.label(text=f"  centre of mass {c[0]:.4g} {c[1]:.4g} {c[2]:.4g} m")
                inertia = obj[prefix + "inertia"]
                box.label(text=f"  inertia diag {inertia[0]:.4g} {inertia[4]:.4g} {inertia[8]:.4g} kg m^2")
        layout.separator()
        for name in ("seconds", "fps", "amplitude", "wavelength", "direction", "steepness",
                     "wave_count", "folder"):
            layout.prop(settings, name)
        layout.operator(PLIMSOLL_OT_float.bl_idname)


def menu_import(self, context):
    self.layout.operator(PLIMSOLL_OT_import_bundle.bl_idname, text="Plimsoll bundle (manifest.json)")


def menu_export(self, context):
    self.layout.operator(PLIMSOLL_OT_export_project.bl_idname, text="Plimsoll project (.plim.json)")


classes = (PlimsollPreferences, PLIMSOLL_OT_import_bundle, PLIMSOLL_OT_export_project,
           PlimsollSettings, PLIMSOLL_OT_mass_properties, PLIMSOLL_OT_float, PLIMSOLL_PT_sidebar)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.plimsoll = PointerProperty(type=PlimsollSettings)
    bpy.types.TOPBAR_MT_file_import.append(menu_import)
    bpy.types.TOPBAR_MT_file_export.append(menu_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(menu_export)
    bpy.types.TOPBAR_MT_file_import.remove(menu_import)
    del bpy.types.Scene.plimsoll
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
