"""Images as NumPy arrays: writing, reading and comparing them through the
library, and showing them in notebooks."""

import os
import tempfile
from typing import Any, Dict, Union

import numpy as np

from . import _native

PathLike = Union[str, "os.PathLike[str]"]
TONE_MAPS = ("classic", "clamp", "reinhard", "aces")


def from_bytes(data: bytes, width: int, height: int) -> np.ndarray:
    """A ``(height, width, 3)`` float32 array from the extension's
    little-endian float32 RGB bytes."""
    return np.frombuffer(data, dtype="<f4").astype(np.float32).reshape(height, width, 3)


def to_bytes(image: Any, what: str = "image") -> "tuple[bytes, int, int]":
    """The extension's bytes, width and height for an array-like image of
    shape ``(height, width, 3)``."""
    array = np.asarray(image)
    if array.ndim != 3 or array.shape[2] != 3:
        raise ValueError(f"{what} must have shape (height, width, 3), got {array.shape}")
    if not np.issubdtype(array.dtype, np.number) or np.iscomplexobj(array):
        raise ValueError(f"{what} must hold real numbers, got dtype {array.dtype}")
    height, width = array.shape[:2]
    return np.ascontiguousarray(array, dtype="<f4").tobytes(), width, height


def write(path: PathLike, image: Any, tone_map: str = "classic", srgb: bool = True) -> None:
    """Write ``image`` (a ``(height, width, 3)`` array of linear radiance)
    to ``path``; the extension picks the format.

    ``.png`` and ``.bmp`` are 8-bit: tone mapped with ``tone_map``
    (``"classic"``, ``"clamp"``, ``"reinhard"`` or ``"aces"``) and
    sRGB-encoded when ``srgb``. ``.exr`` (and ``.hdr``) hold the linear
    values as they are. The file is written beside its destination and
    renamed into place when complete: it never exists half-written, and an
    existing file is replaced only by a complete one.

    Raises ``ValueError`` for an unknown extension or tone map, and
    ``OSError`` when the file cannot be written.
    """
    data, width, height = to_bytes(image)
    _native.write_image(os.fspath(path), data, width, height, tone_map, bool(srgb))


def read(path: PathLike) -> np.ndarray:
    """Read an image file as a ``(height, width, 3)`` float32 array of
    linear values: OpenEXR and Radiance HDR as stored, PNG and BMP decoded
    from sRGB. A render written as EXR reads back bit for bit."""
    data, width, height = _native.read_image_file(os.fspath(path))
    return from_bytes(data, width, height)


def _as_image(value: Any, what: str) -> Any:
    if isinstance(value, (str, os.PathLike)):
        return read(value)
    return value


def diff(image: Any, reference: Any) -> Dict[str, Any]:
    """Compare ``image`` with ``reference`` (arrays, or paths of image
    files), as ``lucent diff --json`` does.

    Returns a dict: ``mse`` and ``rel_mse`` (the mean over pixels and
    channels of ``(a-b)**2`` and of ``(a-b)**2 / (b**2 + 0.01)``),
    ``max_abs_error``, ``max_at`` (``[x, y]`` of the largest error, or
    ``None``), ``max_channel`` (``"r"``, ``"g"`` or ``"b"``), ``nonfinite``
    and ``nonfinite_reference`` (pixels left out for a NaN or infinity),
    ``mean`` and ``mean_reference`` (per channel, over the pixels compared),
    ``width`` and ``height``.
    """
    a, aw, ah = to_bytes(_as_image(image, "image"), "image")
    b, bw, bh = to_bytes(_as_image(reference, "reference"), "reference")
    return _native.diff(a, b, aw, ah, bw, bh)


class Image:
    """An image to look at: in a Jupyter notebook it shows itself (as a
    PNG, tone mapped and sRGB-encoded like ``lucent.write`` does).

    ``array`` is the linear ``(height, width, 3)`` float32 array.
    """

    def __init__(self, array: Any, tone_map: str = "classic", srgb: bool = True) -> None:
        to_bytes(array)  # checks the shape
        if tone_map not in TONE_MAPS:
            raise ValueError(f"unknown tone map {tone_map!r} (accepted: {', '.join(TONE_MAPS)})")
        self.array = np.asarray(array, dtype=np.float32)
        self.tone_map = tone_map
        self.srgb = bool(srgb)

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return self.array if dtype is None else self.array.astype(dtype)

    def __repr__(self) -> str:
        h, w = self.array.shape[:2]
        return f"<lucent.Image {w}×{h}, tone_map={self.tone_map!r}, srgb={self.srgb}>"

    def save(self, path: PathLike) -> None:
        """Write the image (see :func:`lucent.write`) with its tone map."""
        write(path, self.array, self.tone_map, self.srgb)

    def png(self) -> bytes:
        """The image encoded as PNG by the library."""
        with tempfile.TemporaryDirectory(prefix="lucent-") as tmp:
            path = os.path.join(tmp, "image.png")
            self.save(path)
            with open(path, "rb") as f:
                return f.read()

    def _repr_png_(self) -> bytes:
        return self.png()


def show(image: Any, tone_map: str = "classic", srgb: bool = True) -> Image:
    """``image`` (an array from a render, or an image file's path) as an
    :class:`Image`, which a notebook displays: ``lucent.show(scene.render())``
    as the last line of a cell shows the render."""
    return Image(_as_image(image, "image"), tone_map, srgb)
