"""glTF 2.0 scenes from Python: lucent.load, the scene and camera options,
their errors, and the scene archive that carries them to Dask workers."""

import json
import struct

import numpy as np
import pytest

import lucent
from lucent import _archive


def write_triangle(folder):
    """A .gltf with one emissive triangle, two cameras and two scenes, and
    its .bin (positions, then indices)."""
    positions = struct.pack("<9f", -1, -1, 0, 1, -1, 0, 0, 1, 0)
    indices = struct.pack("<3H", 0, 1, 2)
    (folder / "tri.bin").write_bytes(positions + indices)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}, {"nodes": [0]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0, 0, 3]},
            {"camera": 1, "translation": [0, 0, 9]},
        ],
        "cameras": [
            {"type": "perspective", "name": "near", "perspective": {"yfov": 0.8, "aspectRatio": 1.0, "znear": 0.1}},
            {"type": "perspective", "name": "far", "perspective": {"yfov": 0.8, "aspectRatio": 2.0, "znear": 0.1}},
        ],
        "materials": [{"emissiveFactor": [1, 0.5, 0.25]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 6},
        ],
        "buffers": [{"uri": "tri.bin", "byteLength": 42}],
    }
    path = folder / "tri.gltf"
    path.write_text(json.dumps(doc))
    return path


def test_load_and_render_a_gltf_file(tmp_path):
    path = write_triangle(tmp_path)
    scene = lucent.load(path)
    assert scene.width == 1280
    image = scene.render(width=8, height=8, spp=2, progress=False)
    assert image.shape[:2] == (8, 8)
    # The triangle's emission, seen head on at the centre.
    assert np.allclose(image[5, 4, :3], [1, 0.5, 0.25], atol=1e-5)
    assert sorted(scene.files) == sorted([str(path), str(tmp_path / "tri.bin")])
    far = lucent.load(path, camera="far")
    assert (far.width, far.height) == (1280, 640)
    assert lucent.load(path, camera=1).height == 640
    with pytest.warns(UserWarning, match="no camera"):
        framed = lucent.load(path, scene=1)
    assert framed.load_options["scene"] == 1


def test_gltf_options_and_errors(tmp_path):
    path = write_triangle(tmp_path)
    with pytest.raises(lucent.SceneError, match="no camera \"back\""):
        lucent.load(path, camera="back")
    with pytest.raises(lucent.SceneError, match="there is no scene 4"):
        lucent.load(path, scene=4)
    with pytest.raises(ValueError, match="glTF scenes"):
        lucent.load(tmp_path / "x.toml", camera="near")
    with pytest.raises(ValueError, match="index"):
        lucent.load(path, scene=-1)
    (tmp_path / "tri.bin").unlink()
    with pytest.raises(lucent.SceneError, match=r"buffers\[0\]"):
        lucent.load(path)


def test_the_archive_carries_the_buffer_and_the_camera(tmp_path):
    path = write_triangle(tmp_path)
    scene = lucent.load(path, camera="far")
    archive = _archive.build(scene)
    assert sorted(archive.members) == ["tri.bin", "tri.gltf"]
    again = _archive.load(archive, cache_dir=str(tmp_path / "cache"))
    assert again.load_options["camera"] == "far"
    assert (again.width, again.height) == (1280, 640)
