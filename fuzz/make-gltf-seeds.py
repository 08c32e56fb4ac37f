#!/usr/bin/env python3
"""Write the glTF fuzzing seeds (fuzz/seeds/gltf/): small, self-contained
files that exercise the importer's paths, made here rather than copied from
anyone's models. Run from the repository root; needs only Python 3."""

import base64
import json
import struct
import zlib

OUT = "fuzz/seeds/gltf"


def png_rgba(w, h, f):
    """A tiny RGBA PNG (no dependencies)."""
    raw = b"".join(b"\0" + b"".join(bytes(f(x, y)) for x in range(w)) for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


class Doc:
    def __init__(self):
        self.bin = bytearray()
        self.j = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": []}], "nodes": [],
                  "meshes": [], "accessors": [], "bufferViews": [], "buffers": []}

    def view(self, data, stride=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride:
            v["byteStride"] = stride
        self.bin += data
        self.j["bufferViews"].append(v)
        return len(self.j["bufferViews"]) - 1

    def acc(self, data, fmt, ctype, count, ty, extra=None):
        a = {"bufferView": self.view(struct.pack("<" + fmt * (len(data)), *data)), "componentType": ctype,
             "count": count, "type": ty}
        a.update(extra or {})
        self.j["accessors"].append(a)
        return len(self.j["accessors"]) - 1

    def root(self, node):
        self.j["nodes"].append(node)
        self.j["scenes"][0]["nodes"].append(len(self.j["nodes"]) - 1)

    def glb(self):
        self.j["buffers"] = [{"byteLength": len(self.bin)}]
        text = json.dumps(self.j, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        b = bytes(self.bin) + b"\0" * (-len(self.bin) % 4)
        total = 28 + len(text) + len(b)
        return (b"glTF" + struct.pack("<II", 2, total) + struct.pack("<I", len(text)) + b"JSON" + text
                + struct.pack("<I", len(b)) + b"BIN\0" + b)

    def gltf(self):
        self.j["buffers"] = [{"byteLength": len(self.bin),
                              "uri": "data:application/octet-stream;base64," + base64.b64encode(self.bin).decode()}]
        return json.dumps(self.j, indent=1).encode()


def quad(d, material=None):
    p = d.acc([-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0], "f", 5126, 4, "VEC3", {"min": [-1, -1, 0], "max": [1, 1, 0]})
    n = d.acc([0, 0, 1] * 4, "f", 5126, 4, "VEC3")
    t = d.acc([0, 1, 1, 1, 1, 0, 0, 0], "f", 5126, 4, "VEC2")
    i = d.acc([0, 1, 2, 0, 2, 3], "H", 5123, 6, "SCALAR")
    prim = {"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": t}, "indices": i}
    if material is not None:
        prim["material"] = material
    d.j["meshes"].append({"primitives": [prim]})
    return len(d.j["meshes"]) - 1


# 1. Textured, alpha-masked, normal-mapped quad, instanced twice, with a
#    camera and every punctual light, as a .glb.
d = Doc()
img = d.view(png_rgba(4, 4, lambda x, y: (60 * x, 60 * y, 200, 0 if x + y < 2 else 255)))
nrm = d.view(png_rgba(2, 2, lambda x, y: (150, 128, 230, 255)))
d.j["images"] = [{"bufferView": img, "mimeType": "image/png"}, {"bufferView": nrm, "mimeType": "image/png"}]
d.j["samplers"] = [{"wrapS": 33648, "wrapT": 33071, "magFilter": 9728}]
d.j["textures"] = [{"source": 0, "sampler": 0}, {"source": 1}]
d.j["materials"] = [{
    "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
        "offset": [0.1, 0], "rotation": 0.5, "scale": [2, 2]}}}, "metallicFactor": 0.3,
        "metallicRoughnessTexture": {"index": 0}},
    "normalTexture": {"index": 1, "scale": 0.7}, "alphaMode": "MASK", "doubleSided": True,
    "emissiveFactor": [0.2, 0.1, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}}]
m = quad(d, 0)
d.root({"mesh": m, "translation": [-1.5, 0, 0]})
d.root({"mesh": m, "translation": [1.5, 0, 0], "rotation": [0, 0.38268343, 0, 0.92387953]})
d.j["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1}}]
d.root({"camera": 0, "translation": [0, 0, 6]})
d.j["extensionsUsed"] = ["KHR_lights_punctual", "KHR_texture_transform", "KHR_materials_emissive_strength"]
d.j["extensions"] = {"KHR_lights_punctual": {"lights": [
    {"type": "point", "intensity": 500}, {"type": "directional", "intensity": 3, "color": [1, 0.9, 0.8]},
    {"type": "spot", "intensity": 900, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}]}}
d.root({"translation": [0, 2, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}})
d.root({"rotation": [-0.5, 0, 0, 0.8660254], "extensions": {"KHR_lights_punctual": {"light": 1}}})
d.root({"translation": [0, 0, 4], "extensions": {"KHR_lights_punctual": {"light": 2}}})
open(f"{OUT}/textured-lights.glb", "wb").write(d.glb())

# 2. A nested hierarchy, a strip and a fan, quantized positions, sparse
#    accessor, the extension materials, no camera, as a .gltf with a data URI.
d = Doc()
d.j["materials"] = [
    {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.5, 0.2, 1], "roughnessFactor": 0.2},
     "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.1},
                    "KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.5},
                    "KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1, 0.8, 0.8]},
                    "KHR_materials_ior": {"ior": 1.33}}},
    {"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0},
     "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                    "KHR_materials_volume": {"thicknessFactor": 1, "attenuationDistance": 2,
                                             "attenuationColor": [0.9, 0.5, 0.5]}}},
    {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.4]}, "alphaMode": "BLEND"},
]
q = d.acc([0, 0, 0, 65535, 0, 0, 0, 65535, 0, 65535, 65535, 0], "H", 5123, 4, "VEC3",
          {"normalized": True, "min": [0, 0, 0], "max": [1, 1, 0]})
strip = d.acc([0, 1, 2, 3], "B", 5121, 4, "SCALAR")
d.j["meshes"].append({"primitives": [{"attributes": {"POSITION": q}, "indices": strip, "mode": 5, "material": 0},
                                      {"attributes": {"POSITION": q}, "mode": 6, "material": 1}]})
base = d.acc([0, 0, 0, 1, 0, 0, 0, 1, 0], "f", 5126, 3, "VEC3", {"min": [0, 0, 0], "max": [1, 2, 0]})
sv = d.view(struct.pack("<H", 2))
vv = d.view(struct.pack("<3f", 0, 2, 0))
sparse = dict(d.j["accessors"][base])
sparse["sparse"] = {"count": 1, "indices": {"bufferView": sv, "componentType": 5123}, "values": {"bufferView": vv}}
d.j["accessors"].append(sparse)
d.j["meshes"].append({"primitives": [{"attributes": {"POSITION": len(d.j["accessors"]) - 1}, "material": 2}]})
d.j["nodes"].append({"mesh": 1, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -2, 1]})
d.root({"mesh": 0, "children": [0], "scale": [2, 2, 2], "translation": [0, -1, 0]})
d.j["extensionsUsed"] = ["KHR_mesh_quantization", "KHR_materials_clearcoat", "KHR_materials_sheen",
                         "KHR_materials_specular", "KHR_materials_ior", "KHR_materials_transmission",
                         "KHR_materials_volume"]
d.j["extensionsRequired"] = ["KHR_mesh_quantization"]
open(f"{OUT}/hierarchy-extensions.gltf", "wb").write(d.gltf())

# 3. Vertex attributes: COLOR_0 (normalised shorts, RGBA), TEXCOORD_1 read
#    by a texture, TANGENT under a normal map, an unlit vertex-coloured
#    copy, as a .glb.
d = Doc()
img = d.view(png_rgba(2, 2, lambda x, y: (200 * x, 100, 50 + 100 * y, 255)))
d.j["images"] = [{"bufferView": img, "mimeType": "image/png"}]
d.j["textures"] = [{"source": 0}]
d.j["materials"] = [
    {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}},
     "normalTexture": {"index": 0}, "alphaMode": "MASK"},
    {"extensions": {"KHR_materials_unlit": {}}},
]
p = d.acc([-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0], "f", 5126, 4, "VEC3", {"min": [-1, -1, 0], "max": [1, 1, 0]})
n = d.acc([0, 0, 1] * 4, "f", 5126, 4, "VEC3")
t0 = d.acc([0, 1, 1, 1, 1, 0, 0, 0], "f", 5126, 4, "VEC2")
t1 = d.acc([1, 1, 0, 1, 0, 0, 1, 0], "f", 5126, 4, "VEC2")
tan = d.acc([1, 0, 0, -1] * 4, "f", 5126, 4, "VEC4")
col = d.acc([65535, 0, 0, 65535, 0, 65535, 0, 65535, 0, 0, 65535, 0, 65535, 65535, 65535, 32768],
            "H", 5123, 4, "VEC4", {"normalized": True})
col3 = d.acc([1, 0.5, 0.25] * 4, "f", 5126, 4, "VEC3")
i = d.acc([0, 1, 2, 0, 2, 3], "H", 5123, 6, "SCALAR")
d.j["meshes"].append({"primitives": [
    {"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": t0, "TEXCOORD_1": t1, "TANGENT": tan, "COLOR_0": col},
     "indices": i, "material": 0},
    {"attributes": {"POSITION": p, "COLOR_0": col3}, "indices": i, "material": 1}]})
d.root({"mesh": 0})
d.j["extensionsUsed"] = ["KHR_materials_unlit"]
open(f"{OUT}/vertex-attributes.glb", "wb").write(d.glb())
