"""Rendering in Jupyter notebooks: an image that refines in place.

``display_progressive(scene, passes=8, ...)`` shows the render after each
pass in one output (an IPython display handle updated in place) and returns
the final image. Without IPython it renders and returns the image.
"""

from typing import Any

import numpy as np

from ._image import Image


def display_progressive(scene: Any, passes: int = 8, tone_map: str = None, srgb: bool = None, **render_args: Any) -> np.ndarray:
    """Render ``scene`` progressively (:meth:`lucent.Scene.render_progressive`
    with ``passes`` and ``render_args``), showing each pass in one notebook
    output that is updated in place; returns the final image (the image
    :meth:`lucent.Scene.render` returns, bit for bit).

    ``tone_map`` and ``srgb`` are for display (default: the scene's own).
    """
    try:
        from IPython.display import display  # type: ignore
    except ImportError:
        display = None
    handle = None
    image = None
    shown_tone_map = tone_map or scene.tone_map
    shown_srgb = scene.srgb if srgb is None else srgb
    for image in scene.render_progressive(passes=passes, **render_args):
        if display is None:
            continue
        picture = Image(image, shown_tone_map, shown_srgb)
        if handle is None:
            handle = display(picture, display_id=True)
        else:
            handle.update(picture)
    assert image is not None
    return image

