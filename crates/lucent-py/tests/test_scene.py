"""Scenes from dicts and the builder methods: the same images as scene
files, changes checked by the library."""

import json
import os
import sys

import pytest

import lucent
from conftest import SCENES, tiny_dict

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    tomllib = pytest.importorskip("tomli")

ARGS = dict(width=32, height=24, spp=2, progress=False)


@pytest.mark.parametrize("name", ["showcase.toml", "cornell-box.toml", "glass-and-metal.toml", "materials.toml"])
def test_the_parsed_toml_file_renders_like_the_file(name):
    path = SCENES / name
    with open(path, "rb") as f:
        d = tomllib.load(f)
    from_file = lucent.load(path).render(**ARGS)
    from_dict = lucent.Scene.from_dict(d, base_dir=SCENES).render(**ARGS)
    assert from_dict.tobytes() == from_file.tobytes()


def test_the_parsed_json_file_renders_like_the_file():
    d = json.loads((SCENES / "showcase.json").read_text())
    assert lucent.Scene.from_dict(d).render(**ARGS).tobytes() == lucent.load(SCENES / "showcase.json").render(**ARGS).tobytes()


@pytest.mark.parametrize("name", ["showcase.toml", "glass-and-metal.toml"])
def test_to_dict_round_trips(name):
    scene = lucent.load(SCENES / name)
    d = scene.to_dict()
    assert d["camera"]["eye"] == tomllib.loads((SCENES / name).read_text())["camera"]["eye"]
    again = lucent.Scene.from_dict(d, base_dir=scene.base_dir)
    assert again.render(**ARGS).tobytes() == scene.render(**ARGS).tobytes()
    assert again.to_dict() == d
    # to_dict is a copy.
    d["camera"]["fov"] = 10
    assert again.to_dict()["camera"] != d["camera"]


def test_properties_of_a_file_scene():
    scene = lucent.load(SCENES / "glass-and-metal.toml")
    assert scene.path == str(SCENES / "glass-and-metal.toml")
    assert scene.base_dir == str(SCENES)
    assert scene.files == sorted([str(SCENES / "glass-and-metal.toml"), str(SCENES / "sky.hdr")])
    assert scene.load_options == {"strict": False, "env": None}
    assert not scene.is_pbrt
    assert (scene.width, scene.height) == tuple(tomllib.loads((SCENES / "glass-and-metal.toml").read_text())["render"][k] for k in ("width", "height"))


def test_properties_of_a_dict_scene(tmp_path, tiny):
    scene = lucent.Scene.from_dict(tiny, base_dir=tmp_path)
    assert scene.path is None
    assert scene.base_dir == str(tmp_path)
    assert scene.files == []
    assert (scene.width, scene.height, scene.spp) == (32, 24, 4)
    assert (scene.tone_map, scene.srgb) == ("classic", True)
    # from_dict copies its argument.
    tiny["camera"]["fov"] = 30
    assert scene.to_dict()["camera"]["fov"] == 60


def test_relative_paths_resolve_against_base_dir():
    d = tomllib.loads((SCENES / "glass-and-metal.toml").read_text())
    scene = lucent.Scene.from_dict(d, base_dir=SCENES)
    assert str(SCENES / "sky.hdr") in scene.files
    with pytest.raises(lucent.SceneError) as info:
        lucent.Scene.from_dict(d, base_dir=SCENES.parent)
    assert info.value.key == "environment.file"


def test_fingerprint_depends_on_what_decides_the_samples(tiny):
    scene = lucent.Scene.from_dict(tiny)
    fp = scene.fingerprint()
    assert isinstance(fp, int)
    assert fp == lucent.Scene.from_dict(tiny_dict()).fingerprint()
    assert scene.fingerprint(threads=1, progress=False) == fp
    assert scene.fingerprint(seed=3) != fp
    assert scene.fingerprint(width=16) != fp
    changed = lucent.Scene.from_dict(tiny).set_camera(fov=50)
    assert changed.fingerprint() != fp
    with pytest.raises(TypeError, match="unexpected keyword arguments: colour"):
        scene.fingerprint(colour=1)


def test_builder_makes_the_same_scene_as_the_dict(tiny):
    scene = lucent.Scene.from_dict({"camera": {"eye": [0, 0, -1], "look_at": [0, 0, 0]}})
    scene.set_camera(eye=[0, 1, -5], look_at=[0, 0.5, 0], fov=60)
    scene.set_render(width=32, height=24, spp=4)
    scene.add_material("red", "matte", color=[0.9, 0.1, 0.1])
    scene.add_material("floor", "matte", color=[0.8, 0.8, 0.8])
    assert scene.add("sphere", center=[0, 1, 0], radius=1, material="red") == 0
    assert scene.add("sphere", center=[1.5, 0.5, 0.5], radius=0.5, material="red") == 1
    assert scene.add("plane", point=[0, 0, 0], normal=[0, 1, 0], material="floor") == 0
    assert scene.add_light("point", position=[5, 5, -5]) == 0
    assert scene.to_dict() == tiny
    assert scene.render(progress=False).tobytes() == lucent.Scene.from_dict(tiny).render(progress=False).tobytes()


def test_builder_changes_and_removes(tiny):
    scene = lucent.Scene.from_dict(tiny)
    scene.update("sphere", 1, radius=0.25, center=None)
    assert scene.to_dict()["sphere"][1] == {"radius": 0.25, "material": "red"}
    scene.remove("sphere", 1)
    assert len(scene.to_dict()["sphere"]) == 1
    scene.remove("point_light", 0)
    assert "point_light" not in scene.to_dict()
    scene.add_light("spot", position=[0, 5, 0], direction=[0, -1, 0])
    scene.set_ambient(color=[0.1, 0.1, 0.1])
    scene.set_camera(fov=None)  # back to the default
    assert "fov" not in scene.to_dict()["camera"]
    image = scene.render(progress=False)
    assert image.shape == (24, 32, 3) and image.max() > 0
    with pytest.raises(IndexError, match="the scene has 1 sphere entry; there is no \\[5\\]"):
        scene.update("sphere", 5, radius=1)
    with pytest.raises(ValueError, match="unknown object kind 'cube'"):
        scene.add("cube", size=1)
    with pytest.raises(ValueError, match="unknown light kind 'area'"):
        scene.add_light("area")


def test_builder_errors_come_at_the_call_and_change_nothing(tiny):
    scene = lucent.Scene.from_dict(tiny)
    before = scene.to_dict()
    with pytest.raises(lucent.SceneError) as info:
        scene.set_camera(fov=500)
    assert info.value.key == "camera.fov"
    with pytest.raises(lucent.SceneError) as info:
        scene.add("sphere", radius=-1)
    assert (info.value.key, info.value.message) == ("sphere[2].radius", "expected a number > 0, got -1")
    with pytest.raises(lucent.SceneError) as info:
        scene.add_material("gold", "metal", color=[1, 1, 0])
    assert info.value.key == "materials.gold.metal" and info.value.message.startswith("unknown material kind `metal`: expected `matte`, `phong`")
    assert scene.to_dict() == before
    # A name is checked when the scene is built: materials may come later.
    scene.add("sphere", radius=1, material="gold")
    with pytest.raises(lucent.SceneError) as info:
        scene.check()
    assert info.value.key == "sphere[2].material"
    scene.add_material("gold", "phong", color=[1, 0.8, 0.2])
    scene.check()


def test_a_loaded_file_changed_by_the_builder_becomes_a_dict_scene():
    scene = lucent.load(SCENES / "showcase.toml")
    original = scene.render(**ARGS)
    scene.set_render(seed=11)
    assert scene.path is None and scene.base_dir == str(SCENES)
    assert scene.render(**ARGS).tobytes() != original.tobytes()
    scene.set_render(seed=1)  # the file's
    assert scene.render(**ARGS).tobytes() == original.tobytes()


def test_pbrt_scene_renders_but_refuses_the_builder(tmp_path):
    path = tmp_path / "s.pbrt"
    path.write_text(
        'LookAt 0 0 -5  0 0 0  0 1 0\nCamera "perspective" "float fov" [ 45 ]\n'
        'Film "rgb" "integer xresolution" [ 40 ] "integer yresolution" [ 30 ]\n'
        'WorldBegin\nLightSource "point" "point3 from" [ 0 4 -4 ]\nShape "sphere" "float radius" [ 1 ]\n'
    )
    scene = lucent.load(path)
    assert scene.is_pbrt and scene.path == str(path) and scene.files == [str(path)]
    assert scene.render(spp=2, progress=False).shape == (30, 40, 3)
    assert scene.render(width=20, height=10, spp=1, progress=False).shape == (10, 20, 3)
    for call in (lambda: scene.to_dict(), lambda: scene.add("sphere", radius=1), lambda: scene.set_camera(fov=30)):
        with pytest.raises(lucent.SceneError, match="not available for a pbrt-v4 scene; convert it first \\(lucent convert s.pbrt -o scene.toml\\)"):
            call()


def test_values_from_numpy_tuples_and_paths(tiny, tmp_path):
    np = pytest.importorskip("numpy")
    d = tiny_dict()
    d["camera"]["eye"] = np.array([0.0, 1.0, -5.0])
    d["camera"]["fov"] = np.int64(60)
    d["sphere"][0]["center"] = (0, 1, 0)
    scene = lucent.Scene.from_dict(d)
    assert scene.render(progress=False).tobytes() == lucent.Scene.from_dict(tiny).render(progress=False).tobytes()
    # to_dict gives plain JSON values back.
    assert scene.to_dict() == tiny
    assert type(scene.to_dict()["camera"]["fov"]) is int


def test_fingerprint_does_not_depend_on_where_the_scene_lies(tmp_path):
    import shutil

    for name in ("glass-and-metal.toml", "sky.hdr"):
        shutil.copy(SCENES / name, tmp_path / name)
    here, there = lucent.load(SCENES / "glass-and-metal.toml"), lucent.load(tmp_path / "glass-and-metal.toml")
    assert here.fingerprint(spp=4) == there.fingerprint(spp=4)
    d = here.to_dict()
    assert lucent.Scene.from_dict(d, base_dir=SCENES).fingerprint() == lucent.Scene.from_dict(d, base_dir=tmp_path).fingerprint()
    (tmp_path / "sky.hdr").write_bytes((SCENES / "sky.hdr").read_bytes()[:-1] + b"\0")
    assert lucent.load(tmp_path / "glass-and-metal.toml").fingerprint(spp=4) != here.fingerprint(spp=4)


def test_media_through_the_builder():
    # A camera inside a sphere of absorbing medium under a white sky: every
    # pixel is exp(-2 sigma_a) (Beer-Lambert, no noise).
    import math

    scene = lucent.Scene.from_dict(
        {
            "camera": {"eye": [0, 0, 0], "look_at": [0, 0, 1], "fov": 90},
            "render": {"width": 4, "height": 4, "spp": 1, "integrator": "path"},
            "environment": {"color": [1, 1, 1]},
            "materials": {"boundary": {"interface": {}}},
        }
    )
    scene.add_medium("tea", sigma_a=[0.5, 1.0, 2.0], sigma_s=[0, 0, 0])
    scene.set_camera(medium="tea")
    scene.add("sphere", center=[0, 0, 0], radius=2, material="boundary", medium_inside="tea")
    image = scene.render(progress=False)
    for c, sigma in enumerate([0.5, 1.0, 2.0]):
        assert abs(float(image[..., c].mean()) - math.exp(-2 * sigma)) < 1e-5
    assert scene.to_dict()["media"] == {"tea": {"homogeneous": {"sigma_a": [0.5, 1.0, 2.0], "sigma_s": [0, 0, 0]}}}
    # An asymmetry out of range is refused (at the call or when the scene
    # is next built).
    with pytest.raises(lucent.SceneError) as e:
        scene.add_medium("fog", g=2)
        scene.check()
    assert "asymmetry" in str(e.value)
