# The Plimsoll Python module in Blender: mass properties of the selected object, and the object
# floated on waves as keyframes. Debian's Blender 3.4 runs the system Python (3.11), which
# imports the module built against it (docs/python.md); the module's folder comes from the
# add-on's preference or $PLIMSOLL_PYTHON_PATH.
import importlib
import json
import math
import os
import sys
import tempfile

import bpy
from mathutils import Matrix, Quaternion, Vector

from .axes import plimsoll_to_blender
from .project_export import write_obj


class FloatError(Exception):
    pass


def import_plimsoll(configured=""):
    """The plimsoll module: from `configured` (the add-on's preference), else from
    $PLIMSOLL_PYTHON_PATH, else wherever Blender's Python finds it. FloatError says why not."""
    tried = []
    for folder in (configured, os.environ.get("PLIMSOLL_PYTHON_PATH", "")):
        folder = bpy.path.abspath(folder) if folder else ""
        if folder and folder not in sys.path:
            sys.path.insert(0, folder)
        if folder:
            tried.append(folder)
    try:
        return importlib.import_module("plimsoll")
    except ImportError as e:
        where = ", ".join(tried) if tried else "no folder given"
        raise FloatError(
            f"the plimsoll Python module cannot be imported ({e}; looked in: {where}). Build it for "
            f"Blender's Python {sys.version_info.major}.{sys.version_info.minor} and give its folder "
            "in the add-on's preferences or $PLIMSOLL_PYTHON_PATH") from e


def work_folder(obj, folder=""):
    """Where the object's mesh and project are written: `folder`, else a folder per object in
    Blender's temporary folder."""
    path = bpy.path.abspath(folder) if folder else os.path.join(
        bpy.app.tempdir or tempfile.gettempdir(), "plimsoll", bpy.path.clean_name(obj.name))
    os.makedirs(path, exist_ok=True)
    return path


def export_mesh(obj, folder):
    """The object's evaluated mesh as OBJ in Plimsoll's axes (rotation and scale applied, as
    File > Export > Plimsoll project writes it). Returns its path."""
    if obj is None or obj.type != "MESH":
        raise FloatError("select a mesh object")
    path = os.path.join(folder, bpy.path.clean_name(obj.name) + ".obj")
    write_obj(obj, path, bpy.context.evaluated_depsgraph_get())
    return path


def mass_properties(obj, texture_size=128, density=500.0, folder="", module_path=""):
    """Bakes the object at `texture_size` and computes its mass properties from the textures and
    exactly. Stores them on the object (Plimsoll's axes, +y up, about the object's origin with
    its rotation and scale applied): plimsoll_mass, plimsoll_volume, plimsoll_center_of_mass,
    plimsoll_inertia (9 numbers, row by row) and the same with plimsoll_exact_. Returns the
    texture method's result (massprops' facts)."""
    plimsoll = import_plimsoll(module_path)
    mesh = export_mesh(obj, work_folder(obj, folder))
    try:
        texture = plimsoll.massprops(mesh, size=int(texture_size), density=float(density))
        exact = plimsoll.massprops(mesh, exact=True, density=float(density))
    except plimsoll.Error as e:
        raise FloatError(f"{e.kind}: {e.message}") from e
    for prefix, result in (("plimsoll_", texture), ("plimsoll_exact_", exact)):
        obj[prefix + "mass"] = result["mass"]
        obj[prefix + "volume"] = result["volume"]
        obj[prefix + "center_of_mass"] = [float(v) for v in result["center_of_mass"]]
        obj[prefix + "inertia"] = [float(v) for v in result["inertia"].ravel()]
    obj["plimsoll_texture_size"] = int(texture_size)
    obj["plimsoll_density"] = float(density)
    obj["plimsoll_mesh_file"] = mesh
    return texture


def waves(amplitude, wavelength, direction_deg, steepness, count):
    """`count` Gerstner waves: the first as given, each further one half as high and 0.6 times
    as long, turned 35 degrees further, so that the sea is not one regular swell."""
    out = []
    for k in range(count):
        angle = math.radians(direction_deg + 35.0 * k)
        out.append({"amplitude": amplitude * 0.5 ** k, "wavelength": wavelength * 0.6 ** k,
                    "direction": [math.cos(angle), math.sin(angle)],
                    "steepness": steepness, "phase": 1.3 * k})
    return out


def float_project(obj, mesh_file, seconds, fps, density, texture_size, water):
    """A one-body project (docs/project-schema.md): the object at its location, a uniform solid,
    Gerstner waves (none: flat water), one frame per Blender frame."""
    x, y, z = obj.matrix_world.translation
    position = [float(x), float(z), float(-y)]  # Blender's +z up to Plimsoll's +y up
    model = {"model": "gerstner", "level": 0.0, "waves": water} if water else {"model": "flat", "level": 0.0}
    return {
        "schema_version": 1,
        "name": obj.name,
        "medium": {"name": "water", "density": 1025.0, "viscosity": 0.001},
        "water": model,
        "simulation": {"gravity": [0.0, -9.81, 0.0], "time_step": 1.0 / fps, "sub_steps": 4,
                       "integrator": "semi-implicit-euler", "duration": float(seconds)},
        "bodies": [{"name": obj.name, "mesh": os.path.basename(mesh_file),
                    "texture_size": int(texture_size), "material": {"density": float(density)},
                    "position": position}],
    }


# Plimsoll's axes to Blender's: (x, y, z) -> (x, -z, y).
TO_BLENDER = Matrix(((1, 0, 0), (0, 0, -1), (0, 1, 0)))


def object_matrix(row, columns, linear):
    """The object's world matrix at one row of the trajectory: the body's pose (its centre of
    mass and quaternion, with the centre of mass in object space) in Blender's axes, times the
    rotation and scale the exported mesh had applied."""
    value = dict(zip(columns, row))
    q = Quaternion((value["qw"], value["qx"], value["qy"], value["qz"]))
    rotation = q.to_matrix()
    com_world = Vector((value["x"], value["y"], value["z"]))
    com_local = Vector((value["com_x"], value["com_y"], value["com_z"]))
    origin = com_world - rotation @ com_local  # the object origin, Plimsoll's axes
    rotation_b = TO_BLENDER @ rotation @ TO_BLENDER.transposed()
    return Matrix.Translation(TO_BLENDER @ origin) @ (rotation_b @ linear).to_4x4()


def simulate_keyframes(obj, seconds=5.0, fps=None, density=500.0, texture_size=128, amplitude=0.2,
                       wavelength=8.0, direction_deg=0.0, steepness=0.5, wave_count=2, folder="",
                       module_path=""):
    """Floats the object on Gerstner waves for `seconds` and keyframes its location and
    rotation (quaternion) at every frame from the scene's current frame. The project written
    is kept in the work folder (its path in the object's plimsoll_float_project). Returns the
    trajectory (plimsoll.simulate's result)."""
    plimsoll = import_plimsoll(module_path)
    scene = bpy.context.scene
    fps = float(fps or scene.render.fps / scene.render.fps_base)
    folder = work_folder(obj, folder)
    linear = obj.matrix_world.to_3x3()
    mesh = export_mesh(obj, folder)
    water = waves(amplitude, wavelength, direction_deg, steepness, wave_count) if amplitude > 0 else []
    project = os.path.join(folder, bpy.path.clean_name(obj.name) + ".plim.json")
    with open(project, "w", encoding="utf-8") as f:
        json.dump(float_project(obj, mesh, seconds, fps, density, texture_size, water), f, indent=2)
        f.write("\n")
    try:
        run = plimsoll.simulate(project, seconds=float(seconds))
    except plimsoll.Error as e:
        raise FloatError(f"{e.kind}: {e.message}") from e

    obj.animation_data_clear()
    obj.rotation_mode = "QUATERNION"
    start = scene.frame_current
    obj.keyframe_insert("location", frame=start)
    obj.keyframe_insert("rotation_quaternion", frame=start)
    columns = run["columns"]
    previous = obj.rotation_quaternion.copy()
    for k, row in enumerate(run["table"]):
        obj.matrix_world = object_matrix(row, columns, linear)
        # q and -q are one rotation: keep the sign of the previous key, so that the keys
        # interpolate the short way.
        if previous.dot(obj.rotation_quaternion) < 0:
            obj.rotation_quaternion = -obj.rotation_quaternion
        previous = obj.rotation_quaternion.copy()
        obj.keyframe_insert("location", frame=start + k + 1)
        obj.keyframe_insert("rotation_quaternion", frame=start + k + 1)
    scene.frame_end = max(scene.frame_end, start + len(run["table"]))
    scene.frame_set(start)
    obj["plimsoll_float_project"] = project
    return run
