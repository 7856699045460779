#!/usr/bin/env python3
"""Writes the seed corpus of gltf_fuzz (tests/fuzz/corpus_gltf): small valid GLB files that use what the glTF
reader checks: a sparse POSITION accessor on an interleaved view (byteStride 24, positions and normals
together), a sparse accessor with no view, normalized integer colours, a strip and a fan, every index type."""
import json
import os
import struct
import sys


def glb(doc, bin_bytes):
    while len(bin_bytes) % 4:
        bin_bytes += b"\0"
    doc["buffers"] = [{"byteLength": len(bin_bytes)}]
    text = json.dumps(doc, separators=(",", ":")).encode()
    while len(text) % 4:
        text += b" "
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(bin_bytes), 0x004E4942) + bin_bytes
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def mesh_doc(attributes, indices, mode, views, accessors):
    primitive = {"attributes": attributes, "mode": mode}
    if indices is not None:
        primitive["indices"] = indices
    return {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [primitive]}], "bufferViews": views, "accessors": accessors}


def interleaved_sparse():
    # 6 vertices, position + normal interleaved; vertices 1, 4 replaced by sparse values.
    points = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0, 0, 1), (1, 0, 1)]
    data = b"".join(struct.pack("<6f", *p, 0, 0, 1) for p in points)
    sparse_at = len(data)
    data += struct.pack("<2H", 1, 4)
    values_at = len(data)
    data += struct.pack("<6f", 2, 0, 0, 0, 0, 2)
    index_at = len(data)
    data += struct.pack("<6B", 0, 1, 2, 3, 4, 5)
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": sparse_at, "byteStride": 24},
             {"buffer": 0, "byteOffset": sparse_at, "byteLength": 4},
             {"buffer": 0, "byteOffset": values_at, "byteLength": 24},
             {"buffer": 0, "byteOffset": index_at, "byteLength": 6}]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                  "sparse": {"count": 2, "indices": {"bufferView": 1, "componentType": 5123}, "values": {"bufferView": 2}}},
                 {"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 6, "type": "VEC3"},
                 {"bufferView": 3, "componentType": 5121, "count": 6, "type": "SCALAR"}]
    return glb(mesh_doc({"POSITION": 0, "NORMAL": 1}, 2, 4, views, accessors), data)


def zeros_sparse_strip():
    # 5 vertices with no view: all given by the sparse part; normalized ubyte colours; a strip of 3 triangles.
    data = struct.pack("<5I", 0, 1, 2, 3, 4)
    values_at = len(data)
    data += b"".join(struct.pack("<3f", x, y, 0) for x, y in [(0, 0), (1, 0), (0, 1), (1, 1), (0, 2)])
    colours_at = len(data)
    data += bytes([255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 255, 10, 20, 30, 40, 1, 2, 3, 4])
    index_at = len(data)
    data += struct.pack("<5I", 0, 1, 2, 3, 4)
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 20},
             {"buffer": 0, "byteOffset": values_at, "byteLength": 60},
             {"buffer": 0, "byteOffset": colours_at, "byteLength": 20},
             {"buffer": 0, "byteOffset": index_at, "byteLength": 20}]
    accessors = [{"componentType": 5126, "count": 5, "type": "VEC3",
                  "sparse": {"count": 5, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 1}}},
                 {"bufferView": 2, "componentType": 5121, "normalized": True, "count": 5, "type": "VEC4"},
                 {"bufferView": 3, "componentType": 5125, "count": 5, "type": "SCALAR"}]
    return glb(mesh_doc({"POSITION": 0, "COLOR_0": 1}, 2, 5, views, accessors), data)


def fan_ushort_colours():
    # A fan of 4 triangles, no indices; RGB colours as normalized unsigned shorts with a stride of 8.
    points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (-1, 1, 0), (-1, 0, 0)]
    data = b"".join(struct.pack("<3f", *p) for p in points)
    colours_at = len(data)
    data += b"".join(struct.pack("<4H", 65535 * i // 5, 1000 * i, 65535 - i, 0) for i in range(6))
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": colours_at},
             {"buffer": 0, "byteOffset": colours_at, "byteLength": 48, "byteStride": 8}]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3"},
                 {"bufferView": 1, "componentType": 5123, "normalized": True, "count": 6, "type": "VEC3"}]
    return glb(mesh_doc({"POSITION": 0, "COLOR_0": 1}, None, 6, views, accessors), data)


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "corpus_gltf")
    os.makedirs(folder, exist_ok=True)
    for name, make in [("interleaved_sparse.glb", interleaved_sparse), ("zeros_sparse_strip.glb", zeros_sparse_strip),
                       ("fan_ushort_colours.glb", fan_ushort_colours)]:
        with open(os.path.join(folder, name), "wb") as f:
            f.write(make())


if __name__ == "__main__":
    main()
