# Run by Blender: blender -b --factory-startup --python test_import_bundle.py -- BUNDLE...
# Imports each exported bundle through the add-on and checks the result against the bundle's
# own files: vertex, face and UV counts and every UV against the glTF's accessors, the volume Blender
# computes against the manifest's exact one, the custom properties against the manifest, and
# one empty per water-graph node with its capacity. Exits 1 on the first failure.
import json
import os
import struct
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # Blender does not add it
from blender_test_support import check, mesh_volume, run, script_arguments  # noqa: E402
import plimsoll_blender  # noqa: E402
from plimsoll_blender import bundle_import  # noqa: E402


def close(a, b, relative):
    return abs(a - b) <= relative * max(abs(a), abs(b), 1e-300)


def accessor_floats(folder, gltf, index):
    """The float32 values of accessor `index`, read from the glTF's buffer."""
    accessor = gltf["accessors"][index]
    view = gltf["bufferViews"][accessor["bufferView"]]
    with open(os.path.join(folder, gltf["buffers"][view["buffer"]]["uri"]), "rb") as f:
        data = f.read()
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[accessor["type"]]
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    return struct.unpack_from(f"<{width * accessor['count']}f", data, start)


def check_bundle(folder):
    manifest = json.load(open(os.path.join(folder, "manifest.json")))
    gltf = json.load(open(os.path.join(folder, manifest["gltf"])))
    primitive = gltf["meshes"][0]["primitives"][0]
    vertices = gltf["accessors"][primitive["attributes"]["POSITION"]]["count"]
    faces = gltf["accessors"][primitive["indices"]]["count"] // 3

    obj = bundle_import.import_bundle(os.path.join(folder, "manifest.json"))
    name = manifest["body"]
    check(len(obj.data.vertices) == vertices, f"{name}: {len(obj.data.vertices)} vertices, the glTF has {vertices}")
    check(len(obj.data.polygons) == faces, f"{name}: {len(obj.data.polygons)} faces, the glTF has {faces}")
    check(len(obj.data.uv_layers) >= 1, f"{name}: no UV map")
    check(len(obj.data.uv_layers[0].data) == 3 * faces, f"{name}: UV corners")
    # Every corner's UV is its vertex's TEXCOORD_0 (s, t) turned back to Blender's (s, 1 - t):
    # the UVs the bundle's textures were baked over, as the painted maps' image textures need.
    texcoords = accessor_floats(folder, gltf, primitive["attributes"]["TEXCOORD_0"])
    uv_layer = obj.data.uv_layers[0]
    worst = 0.0
    for loop in obj.data.loops:
        s_, t_ = texcoords[2 * loop.vertex_index], texcoords[2 * loop.vertex_index + 1]
        u, v = uv_layer.data[loop.index].uv
        worst = max(worst, abs(u - s_), abs(v - (1.0 - t_)))
    check(worst < 1e-6, f"{name}: UVs differ from TEXCOORD_0 by {worst}")

    # The glTF's float32 vertices enclose the exact volume; Blender's axes turn, volumes stay.
    # A painted shell has no exact mass properties (null): nothing to compare with then.
    exact = manifest["mass_properties"]["exact"]
    volume = mesh_volume(obj)
    if exact:
        check(close(volume, exact["volume"], 1e-6), f"{name}: volume {volume}, manifest {exact['volume']}")
        check(obj["plimsoll_exact_mass"] == exact["mass"], f"{name}: plimsoll_exact_mass")
    else:
        check("plimsoll_exact_mass" not in obj, f"{name}: plimsoll_exact_mass without exact mass properties")

    texture = manifest["mass_properties"]["texture"]
    check(obj["plimsoll_body"] == name, f"{name}: plimsoll_body {obj['plimsoll_body']}")
    check(obj["plimsoll_schema"] == f"{manifest['schema_version']}.{manifest['schema_minor']}", "schema")
    check(obj["plimsoll_mass"] == texture["mass"], f"{name}: plimsoll_mass {obj['plimsoll_mass']} != {texture['mass']}")
    check(list(obj["plimsoll_center_of_mass"]) == texture["center_of_mass"], f"{name}: centre of mass")
    check(list(obj["plimsoll_inertia"]) == [v for row in texture["inertia"] for v in row], f"{name}: inertia")
    check(obj["plimsoll_drag_coefficient"] == manifest["hydrodynamics"]["drag_coefficient"], "drag")
    # The glTF node's extras, as the glTF importer keeps them.
    check(obj["plimsoll_bundle"]["manifest"] == "manifest.json", f"{name}: extras.plimsoll_bundle")

    maps = manifest.get("painted_maps") or {}
    if maps:
        material = obj.data.materials[0]
        images = {n.image.filepath for n in material.node_tree.nodes if n.type == "TEX_IMAGE"}
        for role, m in maps.items():
            path = os.path.join(folder, m["path"])
            check(any(os.path.samefile(bpy.path.abspath(i), path) for i in images), f"{name}: {role} map")

    graph = manifest.get("water_graph")
    empties = [c for c in obj.children if c.type == "EMPTY"]
    if graph:
        check(len(empties) == graph["nodes"], f"{name}: {len(empties)} empties, {graph['nodes']} nodes")
        total = sum(e["plimsoll_capacity"] for e in empties)
        check(close(total, graph["total_capacity"], 1e-12), f"{name}: capacities {total}")
        nodes = json.load(open(os.path.join(folder, graph["path"])))["nodes"]
        for node in nodes:
            empty = next(e for e in empties if e["plimsoll_node_id"] == str(node["id"]))
            x, y, z = node["position"]
            world = empty.matrix_world.translation
            check(max(abs(world[0] - x), abs(world[1] + z), abs(world[2] - y)) < 1e-6,
                  f"{name}: node {node['id']} at {tuple(world)}, graph says {node['position']}")
    else:
        check(not empties, f"{name}: empties without a water graph")
    print(f"ok: {name}: {vertices} vertices, {faces} faces, volume {volume:.9g}, "
          f"{len(empties)} graph nodes, {len(maps)} painted maps", flush=True)


def main():
    bundles = script_arguments()
    check(bundles, "no bundle folders given")
    plimsoll_blender.register()
    for folder in bundles:
        check_bundle(folder)
    plimsoll_blender.unregister()
    print("test_import_bundle: all passed", flush=True)


run(main)
