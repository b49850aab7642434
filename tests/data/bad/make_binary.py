#!/usr/bin/env python3
"""Writes the binary files of the bad-input corpus (text files are committed as they are).
Run from this folder; the outputs are committed too, so the tests need no Python."""
import struct

TRIANGLE = struct.pack("<12f", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0) + b"\0\0"  # 50 bytes

# Binary STL whose header claims 1e9 triangles (50 GB) over a body of one.
with open("stl_huge_count.stl", "wb") as f:
    f.write(b"binary STL, bad-input corpus: claims 1e9 triangles".ljust(80, b" "))
    f.write(struct.pack("<I", 1_000_000_000) + TRIANGLE)

# Binary STL that claims 12 triangles and stops after 1 (a cut-off download).
with open("stl_truncated.stl", "wb") as f:
    f.write(b"binary STL, bad-input corpus: cut after 1 of 12 triangles".ljust(80, b" "))
    f.write(struct.pack("<I", 12) + TRIANGLE)

# Binary PLY declaring 8 vertices and 12 faces, cut after two vertices.
with open("ply_binary_truncated.ply", "wb") as f:
    f.write(b"ply\nformat binary_little_endian 1.0\ncomment bad-input corpus: truncated\n"
            b"element vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
            b"element face 12\nproperty list uchar int vertex_indices\nend_header\n")
    f.write(struct.pack("<6f", 0, 0, 0, 1, 0, 0))

# GLB whose header says 4000 bytes, cut after its 12-byte header and a partial chunk header.
with open("glb_truncated.glb", "wb") as f:
    f.write(b"glTF" + struct.pack("<II", 2, 4000) + struct.pack("<I", 3000) + b"JS")
