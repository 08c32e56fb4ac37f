"""The Dask scene-archive unpacker on every input of its fuzzing seeds and
regressions (fuzz/seeds/archive, fuzz/regressions/archive; the fuzzer is
fuzz/python/archive.py): each is refused with ArchiveError or unpacked into
its cache directory, with the scene and any environment map inside it."""

import hashlib
import os
from pathlib import Path

import pytest

from lucent import _archive

ROOT = Path(__file__).resolve().parents[3]
INPUTS = sorted((ROOT / "fuzz" / "seeds" / "archive").glob("*")) + sorted(
    (ROOT / "fuzz" / "regressions" / "archive").glob("*")
)


def test_there_are_inputs():
    assert len(INPUTS) >= 9, INPUTS


def _inside(path, root):
    return os.path.commonpath([os.path.realpath(path), os.path.realpath(root)]) == os.path.realpath(root)


@pytest.mark.parametrize("path", INPUTS, ids=lambda p: f"{p.parent.parent.name}/{p.name}")
def test_archive_input_is_refused_or_unpacked_inside(path, tmp_path):
    data = path.read_bytes()
    try:
        files, manifest = _archive.unpack(data, hashlib.sha256(data).hexdigest(), str(tmp_path))
    except _archive.ArchiveError as e:
        assert "seeds" not in path.parts, f"a seed is refused: {e}"
        assert str(e)
        return
    assert "regressions" not in path.parts, "a hostile archive was unpacked"
    scene, options = _archive.load_arguments(files, manifest)
    assert _inside(scene, files) and os.path.isfile(scene)
    if "env" in options:
        assert _inside(options["env"], files) and os.path.isfile(options["env"])


@pytest.mark.parametrize("name", ["toml-mesh.tar", "pbrt-include-env.tar"])
def test_the_scene_seeds_load(name, tmp_path):
    # Whole scenes: the mesh, the include and the environment map resolve
    # inside the unpacked tree.
    import lucent

    data = (ROOT / "fuzz" / "seeds" / "archive" / name).read_bytes()
    files, manifest = _archive.unpack(data, hashlib.sha256(data).hexdigest(), str(tmp_path))
    scene, options = _archive.load_arguments(files, manifest)
    loaded = lucent.load(scene, **options)
    assert loaded is not None
