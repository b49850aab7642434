#!/usr/bin/env python3
"""The table of the shared real assets: how Plimsoll reads and uses each one.

For every model under ../shared/real-assets (or the folder given), `plimsoll validate --json`
gives the unit applied, the size in metres, the verdict, the repairs and the volumes; Blender
(scripts/blender_sizes.py, one process for every file) gives its own size for the same file
where it can read it (not ASCII FBX). Prints a Markdown table.

    scripts/real_assets_table.py build/editor/plimsoll [../shared/real-assets]
"""
import json
import os
import pathlib
import shutil
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent


def models(folder):
    return sorted(p for p in folder.rglob("*") if p.suffix.lower() in (".fbx", ".glb", ".obj", ".stl"))


def ascii_fbx(path):
    return path.suffix.lower() == ".fbx" and not path.read_bytes()[:18] == b"Kaydara FBX Binary"


def blender_sizes(files):
    if not shutil.which("blender"):
        return {}
    readable = [str(f) for f in files if not ascii_fbx(f)]
    run = subprocess.run(["blender", "-b", "--factory-startup", "--python",
                          str(HERE / "blender_sizes.py"), "--", *readable],
                         capture_output=True, text=True, check=False)
    sizes = {}
    for line in run.stdout.splitlines():
        # Blender's importers print without ending their lines: the reading may follow on one.
        at = line.find('{"file"')
        if at >= 0:
            entry = json.loads(line[at:])
            if "min" in entry:
                sizes[entry["file"]] = [hi - lo for lo, hi in zip(entry["min"], entry["max"])]
    return sizes


def main():
    plimsoll = sys.argv[1] if len(sys.argv) > 1 else "build/editor/plimsoll"
    # Absolute paths: Blender names the files it read that way.
    folder = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else HERE.parent.parent / "shared" / "real-assets").resolve()
    files = models(folder)
    blender = blender_sizes(files)
    print("| file | unit (m per unit) | size as read, m | Blender's size, m | worst axis vs Blender | "
          "verdict | repairs | material volume, m^3 | displacement volume, m^3 |")
    print("|---|---|---|---|---:|---|---|---:|---:|")
    for f in files:
        run = subprocess.run([plimsoll, "validate", "--json", str(f)], capture_output=True, text=True, check=False)
        try:
            j = json.loads(run.stdout)
        except json.JSONDecodeError:
            print(f"| `{f.relative_to(folder)}` | | | | | error: {run.stderr.strip()[:80]} | | | |")
            continue
        size = [hi - lo for lo, hi in zip(j["bounds"]["min"], j["bounds"]["max"])]
        ref = blender.get(str(f))
        if ref:
            worst = max(abs(a - b) / max(b, 1e-3 * max(ref)) for a, b in zip(size, ref))
            ref_text, worst_text = " x ".join(f"{v:.4g}" for v in ref), f"{100 * worst:.2f}%"
        else:
            ref_text, worst_text = ("ASCII FBX: Blender cannot read it" if ascii_fbx(f) else "-"), "-"
        repairs = ", ".join(f"{r['kind']} {r['count']}" for r in j["repairs"]) or "none"
        fmt = lambda v: "-" if v is None else f"{v:.5g}"
        print(f"| `{f.relative_to(folder)}` | {j['unit_scale']:g} | {' x '.join(f'{v:.4g}' for v in size)} | "
              f"{ref_text} | {worst_text} | {j['verdict']} | {repairs} | {fmt(j['material_volume'])} | "
              f"{fmt(j['displacement_volume'])} |")


if __name__ == "__main__":
    main()
