#!/usr/bin/env python3
"""Writes the binary files of the bad-input corpus (text files are committed as they are).
Run from this folder; the outputs are committed too, so the tests need no Python."""
import json
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

# Binary PLY of a tetrahedron whose second face names vertex 1000000 (assimp: SIGSEGV).
with open("ply_binary_index_past_end.ply", "wb") as f:
    f.write(b"ply\nformat binary_little_endian 1.0\ncomment bad-input corpus: index past the end\n"
            b"element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
            b"element face 2\nproperty list uchar int vertex_indices\nend_header\n")
    f.write(struct.pack("<12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1))
    f.write(struct.pack("<B3i", 3, 0, 2, 1) + struct.pack("<B3i", 3, 0, 1, 1_000_000))

# GLB of 60 bytes whose JSON chunk claims 4 GB (assimp allocated it, then gave up).
with open("glb_huge_chunk.glb", "wb") as f:
    body = b'{"asset":{"version":"2.0"}}    '
    f.write(b"glTF" + struct.pack("<II", 2, 12 + 8 + len(body)))
    f.write(struct.pack("<II", 0xFFFFFFF0, 0x4E4F534A) + body)

# GLB whose JSON chunk (1 byte past a multiple of 4) is followed by 3 bytes of padding and a BIN
# chunk claiming 4 GB with 4 bytes there: assimp looks for BIN after the padding and allocates
# its stated length; a chunk walk without the padding saw an empty chunk there.
with open("glb_bin_after_padding.glb", "wb") as f:
    gltf = json.dumps({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
                       "nodes": [{"mesh": 0}],
                       "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
                       "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3,
                                      "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
                       "bufferViews": [{"buffer": 0, "byteLength": 36}],
                       "buffers": [{"byteLength": 36}]}).encode()
    while len(gltf) % 4 != 1:
        gltf += b" "
    body = struct.pack("<II", len(gltf), 0x4E4F534A) + gltf + b"\0" * 3
    body += struct.pack("<II", 0xFFFFFF00, 0x004E4942) + b"\0" * 4
    f.write(b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body)

# A 16-bit grey PNG of 16 x 16 pixels whose header declares 16384 x 16384 (512 MB decoded).
import zlib
def png_chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
with open("png_huge_declared.png", "wb") as f:
    raw = b"".join(b"\0" + b"\x80\x00" * 16 for _ in range(16))
    f.write(b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", struct.pack(">IIBBBBB", 16384, 16384, 16, 0, 0, 0, 0))
            + png_chunk(b"IDAT", zlib.compress(raw)) + png_chunk(b"IEND", b""))
