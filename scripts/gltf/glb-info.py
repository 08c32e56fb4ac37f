#!/usr/bin/env python3
"""Summarise .glb files: extensionsUsed, lights, materials, cameras, meshes.

    python3 scripts/gltf/glb-info.py FILE.glb [...] [--json]

Plain Python 3 (no Blender, no numpy): reads the GLB header and its JSON
chunk (glTF 2.0 spec, section 4.4). --json prints the whole JSON chunk.
"""

import json
import struct
import sys


def glb_json(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67 or version != 2:
        raise SystemExit(f"{path}: not a glTF 2.0 binary (magic {magic:#x}, version {version})")
    if length != len(data):
        raise SystemExit(f"{path}: header says {length} bytes, file has {len(data)}")
    chunk_len, chunk_type = struct.unpack_from("<II", data, 12)
    if chunk_type != 0x4E4F534A:
        raise SystemExit(f"{path}: first chunk is not JSON")
    return json.loads(data[20:20 + chunk_len])


def summary(path, doc):
    out = [f"== {path}",
           f"extensionsUsed: {doc.get('extensionsUsed', [])}",
           f"extensionsRequired: {doc.get('extensionsRequired', [])}"]
    for cam in doc.get("cameras", []):
        out.append(f"camera {cam.get('name')!r}: {cam.get('type')} {cam.get(cam.get('type'), {})}")
    for light in doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", []):
        out.append(f"light {light.get('name')!r}: {light}")
    for mat in doc.get("materials", []):
        m = dict(mat)
        name = m.pop("name", None)
        out.append(f"material {name!r}: {json.dumps(m, sort_keys=True)}")
    meshes = doc.get("meshes", [])
    uses = {}
    for node in doc.get("nodes", []):
        if "mesh" in node:
            uses.setdefault(node["mesh"], []).append(node.get("name"))
    for i, mesh in enumerate(meshes):
        out.append(f"mesh {i} {mesh.get('name')!r}: {len(mesh['primitives'])} primitive(s), "
                   f"used by nodes {uses.get(i, [])}")
    out.append(f"nodes: {len(doc.get('nodes', []))}, images: "
               f"{[(im.get('name'), im.get('mimeType')) for im in doc.get('images', [])]}, "
               f"samplers: {doc.get('samplers', [])}")
    return "\n".join(out)


def main(argv):
    dump = "--json" in argv
    files = [a for a in argv if a != "--json"]
    if not files:
        raise SystemExit(__doc__)
    for path in files:
        doc = glb_json(path)
        print(json.dumps(doc, indent=1) if dump else summary(path, doc))


if __name__ == "__main__":
    main(sys.argv[1:])
