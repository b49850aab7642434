# Helpers shared by the add-on's Blender test scripts (run by scripts/test-blender.sh).
import os
import sys

import bmesh

# The add-on package, imported from the checkout (blender/), not from Blender's add-on folder.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def check(condition, message):
    """Fails the script (exit 1) with `message` unless `condition`."""
    if not condition:
        print(f"FAIL: {message}", flush=True)
        sys.exit(1)


def mesh_volume(obj):
    """The enclosed volume of a mesh object in world space (bmesh, signed: outward faces > 0)."""
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bm.transform(obj.matrix_world)
    volume = bm.calc_volume(signed=True)
    bm.free()
    return volume


def script_arguments():
    """The arguments after Blender's `--`."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def run(main):
    """Runs `main`; any exception fails the script with its traceback (Blender itself would
    print it and carry on)."""
    try:
        main()
    except SystemExit:
        raise
    except BaseException:
        import traceback
        traceback.print_exc()
        sys.exit(1)
