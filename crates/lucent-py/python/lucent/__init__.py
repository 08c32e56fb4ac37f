"""lucent: a ray tracer (Whitted and path tracing, pbrt-v4 scenes), in Python.

    import lucent
    scene = lucent.load("scenes/showcase.toml")
    image = scene.render(width=320, height=240, spp=16)   # float32 (h, w, 3)
    lucent.write("showcase.png", image)

Scenes come from files (:func:`load`: TOML, JSON, pbrt-v4) or dicts
(:meth:`Scene.from_dict`) and are changed with builder methods; renders are
the command-line program's, bit for bit. See ``docs/python.md``.
"""

from . import _native
from ._denoise import denoise
from ._errors import PartialError, SceneError
from ._image import Image, diff, read, show, write
from ._partial import Partial, load_partial
from ._scene import Scene, load

__version__: str = _native.__version__

__all__ = [
    "Image",
    "Partial",
    "PartialError",
    "Scene",
    "SceneError",
    "denoise",
    "diff",
    "load",
    "load_partial",
    "read",
    "show",
    "write",
]
