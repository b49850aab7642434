# Run by Blender: PLIMSOLL=/path/to/plimsoll blender -b --factory-startup --python
#   test_export_project.py -- WORK_FOLDER BUNDLE...
# The add-on's export, validated by plimsoll, and round trips through plimsoll's bake:
# - a Blender cube (2 m, at z = 1, density 500): the project places it at y = 1, plimsoll
#   validate finds it usable, the result is in the operator's report and the text block, and
#   its bundle, imported back, encloses 8 m^3 with the exact mass 4000 kg;
# - each BUNDLE imported, exported as a project, exported by plimsoll and imported again:
#   the volume stays within 1e-6 relative of the first import's.
# Exits 1 on the first failure.
import json
import os
import subprocess
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # Blender does not add it
from blender_test_support import check, mesh_volume, run, script_arguments  # noqa: E402
import plimsoll_blender  # noqa: E402
from plimsoll_blender import bundle_import, project_export  # noqa: E402


def plimsoll_export(project, out):
    result = subprocess.run([os.environ["PLIMSOLL"], "export", project, "--out", out, "--quiet"],
                            capture_output=True, text=True, timeout=600)
    check(result.returncode == 0, f"plimsoll export {project}: {result.stderr}")
    bodies = json.loads(result.stdout)["bodies"]
    check(len(bodies) == 1, f"{project}: {len(bodies)} bodies")
    return bodies[0]["folder"]


def select_only(obj):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj


def cube_round_trip(work):
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=(0.0, 0.0, 1.0))
    cube = bpy.context.active_object
    cube.name = "crate"
    project = os.path.join(work, "crate.plim.json")
    select_only(cube)
    result = bpy.ops.export_scene.plimsoll_project(filepath=project, density=500.0, texture_size=64)
    check("FINISHED" in result, f"export operator: {result}")
    check(os.path.isfile(os.path.join(work, "crate.obj")), "crate.obj not written")
    body = json.load(open(project))["bodies"][0]
    check(body["mesh"] == "crate.obj" and body["material"] == {"density": 500.0}, f"project body {body}")
    check(body["position"] == [0.0, 1.0, 0.0], f"position {body['position']} (Blender z = 1 is y = 1)")
    text = bpy.data.texts.get("plimsoll validate")
    check(text is not None, "no text block 'plimsoll validate'")
    check(": usable" in text.as_string(), f"validate says: {text.as_string()}")

    folder = plimsoll_export(project, os.path.join(work, "out"))
    exact = json.load(open(os.path.join(folder, "manifest.json")))["mass_properties"]["exact"]
    check(abs(exact["volume"] - 8.0) < 1e-9 and abs(exact["mass"] - 4000.0) < 1e-6, f"crate mass {exact}")
    back = bundle_import.import_bundle(folder)
    volume = mesh_volume(back)
    check(abs(volume - 8.0) <= 1e-6 * 8.0, f"crate volume back {volume}")
    print(f"ok: crate: validate usable, exported, imported back with volume {volume:.9g}", flush=True)


def bundle_round_trip(work, bundle):
    first = bundle_import.import_bundle(bundle)
    name = first["plimsoll_body"]
    before = mesh_volume(first)
    folder = os.path.join(work, "round_trip_" + name)
    project = os.path.join(folder, name + ".plim.json")
    usable, report = project_export.export_project(first, project, density=500.0, texture_size=128,
                                                   plimsoll=os.environ["PLIMSOLL"])
    check(usable, f"{name}: plimsoll validate: {report}")
    again = bundle_import.import_bundle(plimsoll_export(project, os.path.join(folder, "out")))
    after = mesh_volume(again)
    check(abs(after - before) <= 1e-6 * abs(before), f"{name}: volume {before} -> {after}")
    print(f"ok: {name}: Blender -> project -> plimsoll export -> Blender, volume {before:.9g} -> {after:.9g}",
          flush=True)


def main():
    args = script_arguments()
    check(len(args) >= 2, "usage: -- WORK_FOLDER BUNDLE...")
    check(os.environ.get("PLIMSOLL"), "set PLIMSOLL to the plimsoll executable")
    work, bundles = args[0], args[1:]
    os.makedirs(work, exist_ok=True)
    plimsoll_blender.register()
    cube_round_trip(work)
    for bundle in bundles:
        bundle_round_trip(work, bundle)
    plimsoll_blender.unregister()
    print("test_export_project: all passed", flush=True)


run(main)
