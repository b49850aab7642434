# Import of a Plimsoll runtime bundle (docs/bundle.md): the body's glTF mesh through Blender's
# own glTF importer, the painted maps as image textures of a material, the water graph's
# nodes as empties parented to the body, and the mass properties as custom properties.
import json
import math
import os

import bpy

from .axes import plimsoll_to_blender

BUNDLE_FORMAT = "plimsoll-runtime-bundle"


class BundleError(Exception):
    """A bundle that cannot be imported; the message names the file and the problem."""


def numpy_bool_shim():
    # Debian 12's Blender 3.4 glTF importer calls numpy.bool, an alias numpy 1.24 removed
    # (Debian 12 ships numpy 1.24.2), so its import fails with AttributeError. numpy.bool_ is
    # the type the importer meant. Newer numpy (2.x) has numpy.bool again and newer importers
    # do not use it: the guard leaves those alone.
    import warnings
    import numpy
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FutureWarning)  # numpy 1.24 warns on the lookup itself
        missing = not hasattr(numpy, "bool")
    if missing:
        numpy.bool = numpy.bool_


def read_manifest(folder):
    path = os.path.join(folder, "manifest.json")
    try:
        with open(path, encoding="utf-8") as f:
            manifest = json.load(f)
    except OSError as e:
        raise BundleError(f"{path}: cannot read: {e.strerror}") from e
    except ValueError as e:
        raise BundleError(f"{path}: not JSON: {e}") from e
    if not isinstance(manifest, dict) or manifest.get("format") != BUNDLE_FORMAT:
        raise BundleError(f"{path}: not a Plimsoll runtime bundle (\"format\" is not \"{BUNDLE_FORMAT}\")")
    if not manifest.get("gltf"):
        raise BundleError(f"{path}: bundle schema {manifest.get('schema_version')}."
                          f"{manifest.get('schema_minor')} has no glTF mesh (since 1.1): export it again")
    return manifest


def bundle_folder(path):
    """The bundle folder of `path`: the folder itself, or the folder of its manifest.json or glTF."""
    return path if os.path.isdir(path) else os.path.dirname(os.path.abspath(path))


def set_mass_properties(obj, prefix, mass):
    """Custom properties `<prefix>mass`, `volume`, `center_of_mass`, `inertia` (row by row),
    in the bundle's units and axes (kg, m^3, m, kg m^2; object space, +y up)."""
    obj[prefix + "mass"] = float(mass["mass"])
    obj[prefix + "volume"] = float(mass["volume"])
    obj[prefix + "center_of_mass"] = [float(v) for v in mass["center_of_mass"]]
    obj[prefix + "inertia"] = [float(v) for row in mass["inertia"] for v in row]


def add_painted_maps(obj, folder, manifest):
    """A material with one image texture per painted map (data, so Non-Color), sampling the
    UV map the bundle was baked over; the permeability map (else the first) drives the base
    colour so it can be seen in the viewport."""
    maps = manifest.get("painted_maps") or {}
    if not maps:
        return None
    material = bpy.data.materials.new(f"plimsoll {manifest.get('body', obj.name)}")
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    shader = next((n for n in nodes if n.type == "BSDF_PRINCIPLED"), None)
    shown = "permeability" if "permeability" in maps else sorted(maps)[0]
    for i, role in enumerate(sorted(maps)):
        path = os.path.join(folder, maps[role]["path"])
        try:
            image = bpy.data.images.load(path, check_existing=True)
        except RuntimeError as e:
            raise BundleError(f"{path}: cannot load image: {e}") from e
        image.colorspace_settings.name = "Non-Color"
        texture = nodes.new("ShaderNodeTexImage")
        texture.name = texture.label = f"plimsoll {role}"
        texture.image = image
        texture.location = (-600, 300 - 300 * i)
        if role == shown and shader is not None:
            links.new(texture.outputs["Color"], shader.inputs["Base Color"])
    obj.data.materials.clear()
    obj.data.materials.append(material)
    return material


def add_graph_nodes(obj, folder, manifest):
    """One empty per water-graph node, parented to the body at the node's position: a cube of
    the node's box, else a sphere of its capacity; id, name, capacity, water (and box) as
    custom properties."""
    graph_info = manifest.get("water_graph")
    if not graph_info:
        return []
    path = os.path.join(folder, graph_info["path"])
    try:
        with open(path, encoding="utf-8") as f:
            graph = json.load(f)
    except (OSError, ValueError) as e:
        raise BundleError(f"{path}: cannot read the water graph: {e}") from e
    empties = []
    for node in graph.get("nodes", []):
        empty = bpy.data.objects.new(f"{obj.name} node {node['id']}", None)
        box = node.get("box")
        if box:
            empty.empty_display_type = "CUBE"
            empty.empty_display_size = 0.5
            sx, sy, sz = plimsoll_to_blender(box)
            empty.scale = (abs(sx), abs(sy), abs(sz))
            empty["plimsoll_box"] = [float(v) for v in box]
        else:
            empty.empty_display_type = "SPHERE"
            empty.empty_display_size = (3.0 * node["capacity"] / (4.0 * math.pi)) ** (1.0 / 3.0)
        empty.location = plimsoll_to_blender(node.get("position", [0.0, 0.0, 0.0]))
        empty["plimsoll_node_id"] = str(node["id"])
        empty["plimsoll_node_name"] = str(node.get("name", ""))
        empty["plimsoll_capacity"] = float(node["capacity"])
        empty["plimsoll_water"] = float(node.get("water", 0.0))
        for collection in obj.users_collection:
            collection.objects.link(empty)
        empty.parent = obj
        empties.append(empty)
    return empties


def import_bundle(path):
    """Imports the bundle at `path` (its folder, manifest.json or glTF). Returns the body's
    mesh object."""
    folder = bundle_folder(path)
    manifest = read_manifest(folder)
    gltf = os.path.join(folder, manifest["gltf"])
    if not os.path.isfile(gltf):
        raise BundleError(f"{gltf}: missing (named by {os.path.join(folder, 'manifest.json')})")
    numpy_bool_shim()
    before = set(bpy.data.objects)
    result = bpy.ops.import_scene.gltf(filepath=gltf)
    if "FINISHED" not in result:
        raise BundleError(f"{gltf}: Blender's glTF importer failed")
    meshes = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
    if len(meshes) != 1:
        raise BundleError(f"{gltf}: expected one mesh, the importer made {len(meshes)}")
    obj = meshes[0]
    obj["plimsoll_bundle_folder"] = folder
    obj["plimsoll_body"] = str(manifest.get("body", ""))
    obj["plimsoll_project"] = str(manifest.get("project", ""))
    obj["plimsoll_schema"] = f"{manifest['schema_version']}.{manifest['schema_minor']}"
    mass = manifest["mass_properties"]
    # "texture" is what the engine simulates with; "exact" (absent for a painted shell) is
    # the same material integrated over the triangles.
    set_mass_properties(obj, "plimsoll_", mass["texture"])
    if mass.get("exact"):
        set_mass_properties(obj, "plimsoll_exact_", mass["exact"])
    for key, value in (manifest.get("hydrodynamics") or {}).items():
        obj["plimsoll_" + key] = float(value)
    add_painted_maps(obj, folder, manifest)
    add_graph_nodes(obj, folder, manifest)
    bpy.context.view_layer.update()  # the empties' world matrices, for whoever reads them next
    return obj
