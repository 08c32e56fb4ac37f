#!/usr/bin/env python3
"""Loading speed of glTF against PLY: the same triangles, both ways.

Writes a UV sphere of about N triangles (default 1,000,000) with normals and
texture coordinates as a binary PLY (with a TOML scene that places it) and
as a .glb, then times `lucent check` on each (the whole process: read,
build the BVH, report), alternating, and prints the medians.

    python3 scripts/gltf/load-bench.py --lucent target/release/lucent [--triangles N] [--rounds 5]

Needs only numpy. The files go to a temporary folder, removed afterwards.
"""

import argparse
import json
import os
import statistics
import struct
import subprocess
import tempfile
import time

import numpy as np


def sphere(triangles: int):
    """Positions, normals, uvs and triangle indices of a UV sphere."""
    rows = max(2, int(round((triangles / 2) ** 0.5 / 1.41)))
    cols = max(3, triangles // (2 * rows))
    theta = np.linspace(0.0, np.pi, rows + 1, dtype=np.float64)
    phi = np.linspace(0.0, 2.0 * np.pi, cols + 1, dtype=np.float64)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    n = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    uv = np.stack([p / (2 * np.pi), t / np.pi], axis=-1).reshape(-1, 2)
    i = np.arange(rows)[:, None] * (cols + 1) + np.arange(cols)[None, :]
    a, b, c, d = i, i + 1, i + cols + 1, i + cols + 2
    tris = np.concatenate([np.stack([a, c, b], -1), np.stack([b, c, d], -1)]).reshape(-1, 3)
    return n.astype(np.float32), n.astype(np.float32), uv.astype(np.float32), tris.astype(np.uint32)


def write_ply(path, pos, nrm, uv, tris):
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(pos)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "property float u\nproperty float v\n"
        f"element face {len(tris)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    vertices = np.concatenate([pos, nrm, uv], axis=1).astype("<f4")
    faces = np.zeros(len(tris), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"] = 3
    faces["i"] = tris
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(vertices.tobytes())
        f.write(faces.tobytes())


def write_glb(path, pos, nrm, uv, tris):
    chunks, views, accessors = [], [], []

    def add(array, ty, component, minmax=False):
        data = np.ascontiguousarray(array).tobytes()
        offset = sum(len(c) for c in chunks)
        chunks.append(data + b"\0" * (-len(data) % 4))
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data)})
        acc = {"bufferView": len(views) - 1, "componentType": component, "count": len(array), "type": ty}
        if minmax:
            acc["min"] = array.min(axis=0).tolist()
            acc["max"] = array.max(axis=0).tolist()
        accessors.append(acc)
        return len(accessors) - 1

    p = add(pos.astype("<f4"), "VEC3", 5126, True)
    n = add(nrm.astype("<f4"), "VEC3", 5126)
    # glTF's v runs down the image: the same texels as the PLY's (u, v).
    t = add(np.stack([uv[:, 0], 1.0 - uv[:, 1]], -1).astype("<f4"), "VEC2", 5126)
    i = add(tris.reshape(-1).astype("<u4"), "SCALAR", 5125)
    binary = b"".join(chunks)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 4]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "aspectRatio": 1.0, "znear": 0.1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": t}, "indices": i}]}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(binary)}],
    }
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(binary)
    with open(path, "wb") as f:
        f.write(b"glTF" + struct.pack("<II", 2, total))
        f.write(struct.pack("<I", len(text)) + b"JSON" + text)
        f.write(struct.pack("<I", len(binary)) + b"BIN\0" + binary)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lucent", required=True, help="the lucent binary")
    ap.add_argument("--triangles", type=int, default=1_000_000)
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        pos, nrm, uv, tris = sphere(args.triangles)
        write_ply(os.path.join(d, "sphere.ply"), pos, nrm, uv, tris)
        write_glb(os.path.join(d, "sphere.glb"), pos, nrm, uv, tris)
        with open(os.path.join(d, "sphere.toml"), "w") as f:
            f.write(
                '[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 40\n'
                '[render]\nintegrator = "path"\n'
                '[materials.m.diffuse]\ncolor = [0.5, 0.5, 0.5]\n'
                '[[mesh]]\nfile = "sphere.ply"\nmaterial = "m"\n'
            )
        sizes = {k: os.path.getsize(os.path.join(d, f"sphere.{k}")) for k in ("ply", "glb")}
        times = {"toml": [], "glb": []}
        for _ in range(args.rounds):
            for kind in ("toml", "glb"):
                start = time.perf_counter()
                subprocess.run([args.lucent, "check", os.path.join(d, f"sphere.{kind}")], check=True,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                times[kind].append(time.perf_counter() - start)
        print(f"{len(tris):,} triangles, {len(pos):,} vertices; PLY {sizes['ply']:,} bytes, GLB {sizes['glb']:,} bytes")
        for kind, label in (("toml", "PLY (TOML scene)"), ("glb", "glTF (.glb)")):
            t = times[kind]
            print(f"{label:18} median {statistics.median(t):.3f} s  (min {min(t):.3f}, max {max(t):.3f})")
        print(f"ratio glTF/PLY: {statistics.median(times['glb']) / statistics.median(times['toml']):.3f}")


if __name__ == "__main__":
    main()
