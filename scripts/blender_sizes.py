# Blender's reading of mesh files: for each file named after "--", its axis-aligned bounds in
# metres, in Plimsoll's y-up axes, as one JSON object per line:
#   {"file": ..., "min": [x,y,z], "max": [x,y,z]}  or  {"file": ..., "error": ...}
# Run headless, one Blender process for many files (Blender is slow to start):
#   blender -b --factory-startup --python scripts/blender_sizes.py -- FILE...
# Blender's importers convert glTF, FBX and OBJ (y-up) to its z-up axes and apply the file's
# unit (FBX UnitScaleFactor; glTF is metres); STL and OBJ are read with y up and no unit. Its
# z-up (x, y, z) is Plimsoll's y-up (x, z, -y).
import json
import sys

import bpy
import numpy
from mathutils import Vector

# Debian's Blender 3.4 glTF importer still says numpy.bool, which numpy 1.24 removed.
if not hasattr(numpy, "bool") or numpy.bool is not bool:
    try:
        numpy.bool = bool
    except Exception:  # noqa: BLE001
        pass


def clear():
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)


def load(path):
    lower = path.lower()
    if lower.endswith(".fbx"):
        bpy.ops.import_scene.fbx(filepath=path)
    elif lower.endswith(".glb") or lower.endswith(".gltf"):
        bpy.ops.import_scene.gltf(filepath=path)
    elif lower.endswith(".obj"):
        bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
    elif lower.endswith(".stl"):
        bpy.ops.import_mesh.stl(filepath=path, axis_forward="-Z", axis_up="Y")
    else:
        raise RuntimeError("no importer for " + path)


def bounds():
    lo = Vector((1e300, 1e300, 1e300))
    hi = -lo
    count = 0
    for obj in bpy.context.scene.objects:
        if obj.type != "MESH":
            continue
        # The mesh as stored (the bind pose of a skinned one), as assimp reads it.
        for v in obj.data.vertices:
            p = obj.matrix_world @ v.co
            for a in range(3):
                lo[a] = min(lo[a], p[a])
                hi[a] = max(hi[a], p[a])
            count += 1
    if count == 0:
        raise RuntimeError("no mesh vertices")
    # z-up to y-up: (x, y, z) -> (x, z, -y)
    return [lo[0], lo[2], -hi[1]], [hi[0], hi[2], -lo[1]]


files = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
for path in files:
    try:
        clear()
        load(path)
        lo, hi = bounds()
        print(json.dumps({"file": path, "min": lo, "max": hi}), flush=True)
    except Exception as error:  # noqa: BLE001 - one file's failure must not stop the rest
        print(json.dumps({"file": path, "error": str(error)}), flush=True)
