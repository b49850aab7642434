# Floats the sample buoy in Blender through the add-on and the plimsoll Python module:
# bakes it and shows its mass properties (object.plimsoll_mass_properties), then floats it on
# waves for 5 s as keyframes (object.plimsoll_float), and checks every keyframe against the
# module's own simulate of the project the add-on wrote: the keyed object carries the body's
# centre of mass to where the trajectory says, turned by its quaternion (keys are float32).
#   blender -b --factory-startup --python test_float.py -- BUOY_OBJ WORK_FOLDER
# The module's folder comes from $PLIMSOLL_PYTHON_PATH.
import os
import sys

import bpy
from mathutils import Matrix, Quaternion, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # Blender does not add it
from blender_test_support import check, run, script_arguments  # noqa: E402

SECONDS, FPS, SIZE, DENSITY = 5.0, 30, 64, 500.0


def main():
    mesh_path, folder = script_arguments()
    import plimsoll_blender
    from plimsoll_blender import float_object
    plimsoll_blender.register()
    plimsoll = float_object.import_plimsoll()

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.wm.obj_import(filepath=mesh_path)
    obj = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = obj
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = FPS, 1.0
    scene.frame_set(1)
    scene.plimsoll.folder = folder

    check(bpy.ops.object.plimsoll_mass_properties(texture_size=SIZE, density=DENSITY) == {"FINISHED"},
          "the mass properties operator failed")
    mesh = obj["plimsoll_mesh_file"]
    direct = plimsoll.massprops(mesh, size=SIZE, density=DENSITY)
    check(obj["plimsoll_mass"] == direct["mass"] and obj["plimsoll_volume"] == direct["volume"],
          f"plimsoll_mass {obj['plimsoll_mass']} is not the module's {direct['mass']}")
    # Through Blender (float32 vertices) the buoy keeps its volume.
    original = plimsoll.massprops(mesh_path, exact=True, density=DENSITY)
    check(abs(obj["plimsoll_exact_volume"] / original["volume"] - 1) < 1e-5,
          f"exact volume {obj['plimsoll_exact_volume']} against the OBJ's {original['volume']}")

    # The importer turns the object, not its vertices: the exported mesh has that turn applied.
    linear = obj.matrix_world.to_3x3()
    check(bpy.ops.object.plimsoll_float(seconds=SECONDS, fps=FPS, texture_size=SIZE, density=DENSITY,
                                        amplitude=0.2, wavelength=6.0, direction=20.0,
                                        steepness=0.5, wave_count=2) == {"FINISHED"},
          "the float operator failed")
    project = obj["plimsoll_float_project"]
    trajectory = plimsoll.simulate(project, seconds=SECONDS)
    frames = len(trajectory["time"])
    check(frames == int(SECONDS * FPS), f"{frames} frames, expected {int(SECONDS * FPS)}")
    check(abs(trajectory["time"][-1] - SECONDS) < 1e-9, "the run does not end at 5 s")
    action = obj.animation_data.action
    keyed = {(c.data_path, c.array_index) for c in action.fcurves}
    check({("location", i) for i in range(3)} | {("rotation_quaternion", i) for i in range(4)} <= keyed,
          f"keyed channels: {sorted(keyed)}")
    check(all(len(c.keyframe_points) == frames + 1 for c in action.fcurves), "one key per frame")

    to_blender = Matrix(((1, 0, 0), (0, 0, -1), (0, 1, 0)))
    moved = 0.0
    for k in range(frames):
        scene.frame_set(1 + k + 1)
        t = {name: trajectory[name][k] for name in trajectory["columns"]}
        rotation = Quaternion((t["qw"], t["qx"], t["qy"], t["qz"])).to_matrix()
        com_local = linear.inverted() @ to_blender @ Vector((t["com_x"], t["com_y"], t["com_z"]))
        com_world = to_blender @ Vector((t["x"], t["y"], t["z"]))
        placed = obj.matrix_world @ com_local
        check((placed - com_world).length < 2e-5,
              f"frame {k + 1}: centre of mass at {tuple(placed)}, the module says {tuple(com_world)}")
        turned = obj.matrix_world.to_3x3() - to_blender @ rotation @ to_blender.transposed() @ linear
        check(max(abs(v) for row in turned for v in row) < 2e-6,
              f"frame {k + 1}: rotation differs from the module's by {turned}")
        moved = max(moved, abs(com_world.z - trajectory["y"][0]))
    check(moved > 0.01, "the buoy did not move on the waves")
    print(f"test_float: {frames} keyframes match plimsoll.simulate of {os.path.basename(project)}; "
          f"mass {obj['plimsoll_mass']:.6g} kg", flush=True)


run(main)
