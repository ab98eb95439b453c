#!/usr/bin/env python3
"""Writes the seeds of the import harness (fuzz_import.c) into
corpus/import/: small model files, valid and invalid, each prefixed with the
byte that picks its format ('o' OBJ, 'p' PLY, 'b' glTF binary, 'g' glTF).
Run again after changing it: python3 tests/fuzz/make_import_seeds.py"""
import base64
import json
import os
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "import")


def write(name, prefix, data):
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(prefix + data)


# OBJ: a quad (two triangles), a triangle, a line and a point; the failures.
OBJ_ROOM = """# quad floor and a lamp triangle
o floor
v 0 0 0
v 1 0 0
v 1 0 1
v 0 0 1
v 0.2 0.9 0.2
v 0.6 0.9 0.2
v 0.2 0.9 0.6
f 1 4 3 2
o lamp
f 5 6 7
o wire
l 1 5
p 6
"""
write("obj-quad-lamp-line-point.obj", b"o", OBJ_ROOM)
write("obj-zero-area.obj", b"o", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n")
write("obj-all-zero-area.obj", b"o", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
write("obj-inf.obj", b"o", "v 0 0 0\nv 1 0 0\nv inf 1 0\nf 1 2 3\n")
write("obj-overflow.obj", b"o", "v 0 0 0\nv 1 0 0\nv 1e39 1 0\nf 1 2 3\n")
write("obj-far.obj", b"o", "v 0 0 0\nv 1 0 0\nv 2e9 1 0\nf 1 2 3\n")
write("obj-index-out-of-range.obj", b"o", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
write("obj-negative-index.obj", b"o", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -3\nf 1 2 -7\n")
write("obj-lines-only.obj", b"o", "v 0 0 0\nv 1 0 0\nl 1 2\n")
write("obj-mtl-missing.obj", b"o", "mtllib room.mtl\nusemtl white\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
write("text-not-a-model.obj", b"o", "this is not a model file\n")

# PLY: ASCII and binary, and a count that cannot fit (before assimp reserves it).
PLY_HEAD = ("ply\nformat {fmt} 1.0\ncomment xrad seed\nelement vertex {nv}\n"
            "property float x\nproperty float y\nproperty float z\n"
            "element face {nf}\nproperty list uchar int vertex_indices\nend_header\n")
write("ply-ascii-quad.ply", b"p",
      PLY_HEAD.format(fmt="ascii", nv=4, nf=1) + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
binary = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
binary += struct.pack("<B3i", 3, 0, 1, 2) + struct.pack("<B3i", 3, 0, 2, 3)
write("ply-binary-two-triangles.ply", b"p",
      PLY_HEAD.format(fmt="binary_little_endian", nv=4, nf=2).encode() + binary)
write("ply-binary-truncated.ply", b"p",
      PLY_HEAD.format(fmt="binary_little_endian", nv=4, nf=2).encode() + binary[:30])
write("ply-ascii-index-out-of-range.ply", b"p",
      PLY_HEAD.format(fmt="ascii", nv=3, nf=1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
write("ply-ascii-count-too-large.ply", b"p",
      PLY_HEAD.format(fmt="ascii", nv=300000, nf=1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")

# glTF: one triangle, embedded buffer (JSON) or BIN chunk (binary).
POS = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
IDX = struct.pack("<3H", 0, 1, 2) + b"\0\0"


def gltf(buf=POS + IDX, uri=True, mode=4, node=None, count=3, icount=3, extra=None):
    g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
         "nodes": [node or {"mesh": 0, "name": "tri"}],
         "meshes": [{"name": "Tri", "primitives": [
             {"attributes": {"POSITION": 0}, "indices": 1, "material": 0, "mode": mode}]}],
         "materials": [{"name": "grey", "emissiveFactor": [0.1, 0.1, 0.1],
                        "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                 "metallicFactor": 0}}],
         "accessors": [
             {"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
              "min": [0, 0, 0], "max": [1, 1, 0]},
             {"bufferView": 1, "componentType": 5123, "count": icount, "type": "SCALAR"}],
         "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                         {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
         "buffers": [{"byteLength": len(buf)}]}
    if uri is True:
        g["buffers"][0]["uri"] = ("data:application/octet-stream;base64," +
                                  base64.b64encode(buf).decode())
    elif uri:
        g["buffers"][0]["uri"] = uri
    if extra:
        extra(g)
    return g


def glb(g, buf=POS + IDX):
    j = json.dumps(g, separators=(",", ":")).encode()
    j += b" " * (-len(j) % 4)
    buf += b"\0" * (-len(buf) % 4)
    total = 12 + 8 + len(j) + 8 + len(buf)
    return (struct.pack("<4sII", b"glTF", 2, total) + struct.pack("<I4s", len(j), b"JSON") + j +
            struct.pack("<I4s", len(buf), b"BIN\0") + buf)


def dumps(g):
    return json.dumps(g, separators=(",", ":"))


def camera(g):
    g["cameras"] = [{"name": "view", "type": "perspective",
                     "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1}}]
    g["nodes"].append({"name": "view", "camera": 0, "translation": [0.3, 0.3, 2]})
    g["scenes"][0]["nodes"].append(1)


write("gltf-triangle.gltf", b"g", dumps(gltf()))
write("gltf-camera-mirror.gltf", b"g",
      dumps(gltf(node={"mesh": 0, "name": "m", "scale": [-1, 1, 1]}, extra=camera)))
write("gltf-missing-bin.gltf", b"g", dumps(gltf(uri="missing.bin")))
write("gltf-index-out-of-range.gltf", b"g",
      dumps(gltf(buf=POS + struct.pack("<3H", 0, 1, 9) + b"\0\0")))
write("gltf-matrix-overflow.gltf", b"g",
      dumps(gltf(node={"mesh": 0, "name": "huge",
                       "matrix": [1e39, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]})))
write("gltf-lines.gltf", b"g", dumps(gltf(mode=1, icount=2)))


def second_material(g):
    # Two materials of one name (glTF allows it), each on a primitive.
    g["materials"].append(dict(g["materials"][0]))
    prim = dict(g["meshes"][0]["primitives"][0], material=1)
    g["meshes"][0]["primitives"].append(prim)


write("gltf-duplicate-material-names.gltf", b"g", dumps(gltf(extra=second_material)))
write("gltf-count-too-large.gltf", b"g", dumps(gltf(count=1000000000, icount=3000000000)))
write("glb-triangle.glb", b"b", glb(gltf(uri=False)))
write("glb-infinite.glb", b"b",
      glb(gltf(uri=False), struct.pack("<9f", 0, 0, 0, float("inf"), 0, 0, 0, 1, 0) + IDX))
write("glb-truncated.glb", b"b", glb(gltf(uri=False))[:100])
