"""In a notebook, a progressive render updates one output in place."""

import sys
import types

import lucent
import lucent.notebook
from conftest import tiny_dict


class FakeHandle:
    def __init__(self, shown):
        self.shown = shown

    def update(self, obj):
        self.shown.append(("update", obj))


def fake_ipython(monkeypatch):
    shown = []

    def display(obj, display_id=False):
        assert display_id is True
        shown.append(("display", obj))
        return FakeHandle(shown)

    ipython = types.ModuleType("IPython")
    ipython.display = types.ModuleType("IPython.display")
    ipython.display.display = display
    monkeypatch.setitem(sys.modules, "IPython", ipython)
    monkeypatch.setitem(sys.modules, "IPython.display", ipython.display)
    return shown


def test_display_progressive_updates_one_output(monkeypatch):
    shown = fake_ipython(monkeypatch)
    scene = lucent.Scene.from_dict(tiny_dict())
    final = lucent.notebook.display_progressive(scene, passes=3, spp=6)
    assert [kind for kind, _ in shown] == ["display", "update", "update"]
    assert all(isinstance(obj, lucent.Image) for _, obj in shown)
    assert shown[-1][1].array.tobytes() == final.tobytes()
    assert final.tobytes() == scene.render(spp=6, progress=False).tobytes()
    png = shown[0][1]._repr_png_()
    assert png.startswith(b"\x89PNG")


def test_display_progressive_without_ipython_just_renders(monkeypatch):
    monkeypatch.setitem(sys.modules, "IPython", None)
    monkeypatch.setitem(sys.modules, "IPython.display", None)
    scene = lucent.Scene.from_dict(tiny_dict())
    final = lucent.notebook.display_progressive(scene, passes=2)
    assert final.tobytes() == scene.render(progress=False).tobytes()
