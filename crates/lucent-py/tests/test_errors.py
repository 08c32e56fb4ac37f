"""Every scene error is a lucent.SceneError (a ValueError) with where it
is: the file, line and column, or the key path in a dict."""

import pickle
import subprocess
import sys

import pytest

import lucent
from conftest import tiny_dict


def raises(f):
    with pytest.raises(lucent.SceneError) as info:
        f()
    return info.value


def test_scene_error_is_a_value_error_that_pickles():
    assert issubclass(lucent.SceneError, ValueError)
    assert issubclass(lucent.PartialError, ValueError)
    e = raises(lambda: lucent.load("/nonexistent/scene.toml"))
    again = pickle.loads(pickle.dumps(e))
    assert type(again) is lucent.SceneError
    assert (str(again), again.path, again.message) == (str(e), e.path, e.message)


def test_missing_file(tmp_path):
    path = tmp_path / "none.toml"
    e = raises(lambda: lucent.load(path))
    assert str(e) == f"{path}: cannot read the scene file: no such file"
    assert (e.path, e.line, e.column, e.message) == (str(path), None, None, "cannot read the scene file: no such file")


def test_unknown_extension(tmp_path):
    (tmp_path / "scene.yaml").write_text("camera: {}\n")
    e = raises(lambda: lucent.load(tmp_path / "scene.yaml"))
    assert e.message == "unknown scene file extension (accepted: .toml, .json)"


def test_toml_wrong_type_has_line_and_column(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = "wide"\n')
    e = raises(lambda: lucent.load(path))
    assert (e.path, e.line, e.column) == (str(path), 4, 7)
    assert e.message == 'invalid type: string "wide", expected a field of view strictly between 0 and 180 degrees'
    assert e.line_text == 'fov = "wide"'
    assert str(e).endswith('4 | fov = "wide"\n  |       ^')


def test_toml_unknown_key(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n\n[[sphere]]\nradius = 1\ncolour = [1, 0, 0]\n')
    e = raises(lambda: lucent.load(path))
    assert (e.line, e.column) == (7, 1)
    assert e.message.startswith("unknown field `colour`, expected one of")


def test_json_error_has_line_and_column(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text('{\n  "camera": {"eye": [0, 0, -5], "look_at": [0, 0, 0]},\n  "sphere": [{"radius": -2}]\n}\n')
    e = raises(lambda: lucent.load(path))
    assert (e.path, e.line) == (str(path), 3)
    assert e.message == "expected a number > 0, got -2"


def test_missing_mesh_file_in_a_scene_file(tmp_path):
    path = tmp_path / "mesh.toml"
    path.write_text(
        '[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n\n'
        '[meshes.m]\nfile = "missing.ply"\n\n[[mesh]]\nmesh = "m"\n'
    )
    e = raises(lambda: lucent.load(path))
    assert e.line == 6
    assert f"{tmp_path / 'missing.ply'}: cannot read the file" in e.message


def test_bad_pbrt_syntax(tmp_path):
    path = tmp_path / "bad.pbrt"
    path.write_text('LookAt 0 0 -5  0 0 0  0 1 0\nCamera "perspective" "float fov" [ 45 ]\nWorldBegin\nShape "sphere" "float radius" [ 1\n')
    e = raises(lambda: lucent.load(path))
    assert (e.path, e.line, e.column) == (str(path), 5, 1)
    assert e.message == 'unexpected end of file in the values of "float radius": no `]` closes the `[` at line 4, column 31'


def test_pbrt_unknown_directive(tmp_path):
    path = tmp_path / "bad.pbrt"
    path.write_text('LookAt 0 0 -5  0 0 0  0 1 0\nCamera "perspective"\nWorldBegin\nSphere 1\n')
    e = raises(lambda: lucent.load(path))
    assert (e.line, e.column) == (4, 1)
    assert "Sphere" in e.message


def test_strict_and_env_are_for_pbrt_and_gltf_only():
    with pytest.raises(ValueError, match=r"strict and env apply to pbrt-v4 \(.pbrt, .pbrt.gz\) and glTF"):
        lucent.load("scene.toml", strict=True)


@pytest.mark.parametrize(
    "change, key, message",
    [
        (lambda d: d["camera"].update(fov=200), "camera.fov",
         "expected a field of view strictly between 0 and 180 degrees, got 200"),
        (lambda d: d["camera"].update(fovv=20), "camera.fovv", "unknown field `fovv`, expected one of"),
        (lambda d: d["sphere"][1].update(radius="big"), "sphere[1].radius",
         'invalid type: string "big", expected a number > 0'),
        (lambda d: d["sphere"][1].update(radius=-1), "sphere[1].radius", "expected a number > 0, got -1"),
        (lambda d: d["sphere"][0].update(material="blue"), "sphere[0].material",
         'sphere #1: material "blue" is not defined (defined: floor, red)'),
        (lambda d: d["materials"]["red"]["matte"].update(color=[1, 2]), "materials.red.matte.color",
         "expected a colour [r, g, b] of three numbers, got 2"),
        (lambda d: d["render"].update(width=float("nan")), "render.width",
         "nan is not a number a scene can hold"),
        (lambda d: d["render"].update(width={1, 2}), "render.width", "cannot use a value of type set in a scene"),
        (lambda d: d.pop("camera"), None, "missing field `camera`"),
        (lambda d: d.update(meshes={"m": {"file": "nope.ply"}}, mesh=[{"mesh": "m"}]), "meshes.m.file",
         "nope.ply: cannot read the file"),
    ],
)
def test_dict_errors_name_the_key_path(change, key, message):
    d = tiny_dict()
    change(d)
    e = raises(lambda: lucent.Scene.from_dict(d))
    assert e.key == key
    assert message in e.message
    assert e.path is None and e.line is None
    assert str(e) == f"scene dict, at {key or 'the top level'}: {e.message}"


def test_from_dict_of_something_else():
    e = raises(lambda: lucent.Scene.from_dict([1, 2]))
    assert e.message == "a scene must be a dict, got list"


def test_errors_never_crash_the_interpreter(tmp_path):
    # Damaged input of every kind, in a child process: it must end with
    # exceptions, not a signal.
    code = """
import lucent, os, sys
tmp = sys.argv[1]
bad = {"x.toml": b"\\xff\\xfe[camera", "y.json": b"{\\"camera\\": ", "z.pbrt": b"Shape \\"trianglemesh\\" \\"point3 P\\" [1 2]\\n",
       "w.pbrt.gz": b"not gzip"}
for name, data in bad.items():
    p = os.path.join(tmp, name)
    open(p, "wb").write(data)
    try:
        lucent.load(p)
    except lucent.SceneError as e:
        print(name, "SceneError")
for d in [{}, {"camera": None}, {"camera": {"eye": "x"}}, {"camera": {"eye": [0, 0, -1], "look_at": [0, 0, 0]}, "sphere": {}},
          {"camera": {"eye": [0, 0, -1], "look_at": [0, 0, 0]}, "render": {"width": 10**12}}]:
    try:
        lucent.Scene.from_dict(d)
    except lucent.SceneError as e:
        print("dict SceneError")
"""
    out = subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split("\n").count("dict SceneError") == 5, out.stdout
    assert len(out.stdout.strip().split("\n")) == 9, out.stdout
