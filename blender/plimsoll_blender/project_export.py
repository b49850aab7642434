# Export of a Blender mesh object as a Plimsoll project (docs/project-schema.md): the mesh as
# OBJ (its rotation and scale applied, in Plimsoll's +y up axes, with its active UV map), a
# one-body project beside it, then `plimsoll validate` on the mesh.
import json
import os
import shutil
import subprocess

import bpy

from .axes import blender_to_plimsoll


class ExportError(Exception):
    pass


def write_obj(obj, path, depsgraph):
    """Writes `obj`'s evaluated mesh (modifiers applied) as OBJ: vertices through the object's
    rotation and scale (not its location, which becomes the body's position), converted to
    +y up; one `vt` per face corner of the active UV map. Vertices at exactly the same
    position are written once: a mesh split at its UV seams (as a glTF import makes it) is
    then closed again, while its UVs stay per corner. Returns (vertices, faces) written."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        linear = obj.matrix_world.to_3x3()
        uv_layer = mesh.uv_layers.active
        lines = [f"# {obj.name}, exported from Blender by the Plimsoll add-on\n"]
        index_of_position, obj_index = {}, []
        for v in mesh.vertices:
            p = tuple(blender_to_plimsoll(linear @ v.co))
            if p not in index_of_position:
                index_of_position[p] = len(index_of_position) + 1
                lines.append(f"v {p[0]!r} {p[1]!r} {p[2]!r}\n")
            obj_index.append(index_of_position[p])
        if uv_layer is not None:
            for corner in uv_layer.data:
                lines.append(f"vt {corner.uv[0]!r} {corner.uv[1]!r}\n")
        for poly in mesh.polygons:
            if uv_layer is not None:
                corners = " ".join(f"{obj_index[mesh.loops[i].vertex_index]}/{i + 1}" for i in poly.loop_indices)
            else:
                corners = " ".join(str(obj_index[mesh.loops[i].vertex_index]) for i in poly.loop_indices)
            lines.append(f"f {corners}\n")
        # A negative scale mirrors the mesh and turns its faces inside out: reverse them back
        # so they stay counter-clockwise seen from outside, as Plimsoll wants.
        if linear.determinant() < 0:
            lines = [reverse_face(line) for line in lines]
        counts = (len(index_of_position), len(mesh.polygons))
    finally:
        evaluated.to_mesh_clear()
    try:
        with open(path, "w", encoding="utf-8") as f:
            f.writelines(lines)
    except OSError as e:
        raise ExportError(f"{path}: cannot write: {e.strerror}") from e
    return counts


def reverse_face(line):
    if not line.startswith("f "):
        return line
    return "f " + " ".join(reversed(line[2:].split())) + "\n"


def project_json(obj, mesh_file, density, texture_size):
    """A one-body project: the object's name, its mesh, a uniform solid of `density`, placed
    at the object's location (converted to +y up), on flat water at 0."""
    position = [float(c) for c in blender_to_plimsoll(obj.matrix_world.translation)]
    return {
        "schema_version": 1,
        "name": obj.name,
        "medium": {"name": "water", "density": 1000.0, "viscosity": 0.001},
        "water": {"model": "flat", "level": 0.0},
        "bodies": [{
            "name": obj.name,
            "mesh": mesh_file,
            "texture_size": int(texture_size),
            "material": {"density": float(density)},
            "position": position,
        }],
    }


def find_plimsoll(configured=""):
    """The plimsoll executable: `configured` (the add-on's preference), else $PLIMSOLL, else
    `plimsoll` on PATH. None when there is none."""
    for candidate in (configured, os.environ.get("PLIMSOLL", "")):
        if candidate and os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
    return shutil.which("plimsoll")


def validate_mesh(executable, mesh_path, timeout=300):
    """Runs `plimsoll validate MESH --json`. Returns (usable, report text, report dict or None)."""
    try:
        run = subprocess.run([executable, "validate", mesh_path, "--json"], capture_output=True,
                             text=True, timeout=timeout)
    except (OSError, subprocess.TimeoutExpired) as e:
        return False, f"{executable} validate {mesh_path}: {e}", None
    try:
        report = json.loads(run.stdout)
    except ValueError:
        return False, (run.stderr or run.stdout).strip() or f"plimsoll validate exited {run.returncode}", None
    lines = [f"{mesh_path}: {report['triangles']} triangles, {report['vertices']} vertices: "
             f"{'usable' if report['usable'] else 'NOT usable'}"
             f"{'' if report['closed_solid'] else ' (not a closed solid)'}"]
    for problem in report.get("problems", []):
        lines.append(f"  {problem['severity']}: {problem['code']}: {problem['message']}")
    return run.returncode == 0 and report["usable"], "\n".join(lines), report


def show_in_text_block(name, text):
    """Blender's text editor shows what validate said: the text block `name`, replaced."""
    block = bpy.data.texts.get(name) or bpy.data.texts.new(name)
    block.clear()
    block.write(text + "\n")
    return block


def export_project(obj, project_path, density=500.0, texture_size=256, plimsoll=""):
    """Writes `<stem>.obj` and the project `project_path` (`<stem>.plim.json`), then validates
    the mesh. Returns (usable, text): usable is None when no plimsoll executable was found."""
    if obj is None or obj.type != "MESH":
        raise ExportError("select a mesh object to export")
    folder = os.path.dirname(os.path.abspath(project_path))
    base = os.path.basename(project_path)
    stem = base[:-len(".plim.json")] if base.endswith(".plim.json") else os.path.splitext(base)[0]
    mesh_file = stem + ".obj"
    os.makedirs(folder, exist_ok=True)
    write_obj(obj, os.path.join(folder, mesh_file), bpy.context.evaluated_depsgraph_get())
    try:
        with open(project_path, "w", encoding="utf-8") as f:
            json.dump(project_json(obj, mesh_file, density, texture_size), f, indent=2)
            f.write("\n")
    except OSError as e:
        raise ExportError(f"{project_path}: cannot write: {e.strerror}") from e
    executable = find_plimsoll(plimsoll)
    if executable is None:
        text = (f"{project_path} written; plimsoll not found (set the add-on's preference, "
                "$PLIMSOLL or PATH), so the mesh was not validated")
        show_in_text_block("plimsoll validate", text)
        return None, text
    usable, text = validate_mesh(executable, os.path.join(folder, mesh_file))[:2]
    show_in_text_block("plimsoll validate", f"project: {project_path}\n{text}")
    return usable, text
