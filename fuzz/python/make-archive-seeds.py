#!/usr/bin/env python3
"""Write the scene-archive fuzzing seeds (fuzz/seeds/archive/): archives in
the layout ``lucent._archive.build`` writes (a manifest, then the files under
``files/``), made here with ``tarfile`` so that no scene or native module is
needed. Run from the repository root; needs only Python 3."""

import hashlib
import io
import json
import tarfile

OUT = "fuzz/seeds/archive"


def archive(files, scene, env=None, **options):
    manifest = {
        "format": 1,
        "scene": scene,
        "strict": False,
        "env": env,
        "gltf_scene": options.get("gltf_scene"),
        "camera": options.get("camera"),
        "files": {n: {"size": len(d), "sha256": hashlib.sha256(d).hexdigest()} for n, d in sorted(files.items())},
    }
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w", format=tarfile.PAX_FORMAT) as tar:
        def add(name, data):
            info = tarfile.TarInfo(name)
            info.size = len(data)
            info.mtime = 0
            tar.addfile(info, io.BytesIO(data))
        add("manifest.json", json.dumps(manifest, sort_keys=True, indent=1).encode())
        for name, data in sorted(files.items()):
            add(f"files/{name}", data)
    data = out.getvalue()
    # Drop the record padding after the end-of-archive blocks (tarfile
    # reads the archive without it): small seeds mutate faster.
    end = len(data.rstrip(b"\0"))
    return data[: (end + 511) // 512 * 512 + 1024]


scene = (b'[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n[materials.m.matte]\ncolor = [1, 1, 1]\n'
         b'[[mesh]]\nfile = "meshes/tri.ply"\nmaterial = "m"\n')
ply = (b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       b"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
pfm = b"PF\n1 1\n-1.0\n" + b"\0\0\x80\x3f" * 3
pbrt = (b'LookAt 0 0 5  0 0 0  0 1 0\nCamera "perspective"\nWorldBegin\n'
        b'LightSource "infinite" "string filename" "sky.pfm"\nInclude "geometry/sphere.pbrt"\n')
open(f"{OUT}/toml-mesh.tar", "wb").write(archive({"scene.toml": scene, "meshes/tri.ply": ply}, "scene.toml"))
open(f"{OUT}/pbrt-include-env.tar", "wb").write(archive(
    {"scene.pbrt": pbrt, "geometry/sphere.pbrt": b'Shape "sphere"\n', "sky.pfm": pfm}, "scene.pbrt", env="sky.pfm"))
open(f"{OUT}/gltf-options.tar", "wb").write(
    archive({"a/scene.gltf": b'{"asset": {"version": "2.0"}}'}, "a/scene.gltf", gltf_scene=0, camera="Camera"))

# Hostile and damaged archives the unpacker must refuse with ArchiveError
# (fuzz/regressions/archive/; each once escaped as another exception or,
# the environment map, as a path outside the archive).
REG = "fuzz/regressions/archive"


def raw(members, manifest):
    files = dict(members)
    files["manifest.json"] = json.dumps(manifest).encode()
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as tar:
        for name, data in files.items():
            info = tarfile.TarInfo(name)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    return out.getvalue()


def digest(data):
    return {"sha256": hashlib.sha256(data).hexdigest()}


hostile = {
    "manifest-not-an-object": raw({}, [1, 2]),
    "files-entry-not-an-object": raw({"files/s.toml": scene}, {"format": 1, "scene": "s.toml", "files": {"s.toml": 3}}),
    "scene-unhashable": raw({"files/s.toml": scene}, {"format": 1, "scene": ["s.toml"], "files": {"s.toml": digest(scene)}}),
    "env-outside": raw({"files/s.toml": scene},
                       {"format": 1, "scene": "s.toml", "env": "/etc/passwd", "files": {"s.toml": digest(scene)}}),
    "gltf-scene-not-a-number": raw({"files/s.toml": scene},
                                   {"format": 1, "scene": "s.toml", "gltf_scene": "x", "files": {"s.toml": digest(scene)}}),
    "file-and-folder-of-one-name": raw({"files/a": scene, "files/a/b": scene},
                                       {"format": 1, "scene": "a", "files": {"a": digest(scene), "a/b": digest(scene)}}),
}
good = archive({"scene.toml": scene, "meshes/tri.ply": ply}, "scene.toml")
hostile["truncated"] = good[:700]
for name, data in hostile.items():
    open(f"{REG}/{name}.tar", "wb").write(data)
