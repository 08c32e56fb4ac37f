"""The examples of docs/python.md run as written (```python blocks, in
order, in one namespace, from a directory holding the repository's
scenes/)."""

import os
import re

import pytest

from conftest import REPO

GUIDE = REPO / "docs" / "python.md"


def python_blocks() -> "list[str]":
    return re.findall(r"^```python\n(.*?)^```", GUIDE.read_text(), flags=re.S | re.M)


def test_the_guide_has_examples():
    assert len(python_blocks()) >= 8


def test_the_guide_examples_run(tmp_path, monkeypatch, capsys):
    (tmp_path / "scenes").symlink_to(REPO / "scenes")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for i, block in enumerate(python_blocks()):
        try:
            exec(compile(block, f"{GUIDE}:block{i + 1}", "exec"), namespace)
        except Exception as e:  # pragma: no cover - the message says which block
            pytest.fail(f"example {i + 1} of docs/python.md failed: {e!r}\n{block}")
    out = capsys.readouterr().out
    assert "(90, 160, 3) float32" in out
    assert "scene dict, at camera.fov: expected a field of view strictly between 0 and 180 degrees, got 200" in out
    assert sorted(os.listdir(tmp_path)) == ["part-1.lpart", "scenes", "showcase.exr", "showcase.png"]
