"""Denoising with Intel Open Image Denoise (OIDN), opened at run time.

OIDN comes from PyPI's ``pyoidn`` wheel (``pip install lucent[denoise]``
installs it), or from ``$LUCENT_OIDN`` (the library file or its folder), or
from the system's library path."""

import importlib.util
import os
from typing import Any, Dict, Optional

import numpy as np

from . import _image, _native

#: OIDN's quality settings.
QUALITIES = ("default", "fast", "balanced", "high")
#: How the albedo and normal guide the network.
AUX_MODES = ("prefilter", "clean", "noisy")


def _pyoidn_library() -> Optional[str]:
    """The OIDN library of the ``pyoidn`` package installed in this Python,
    found without importing the package."""
    spec = importlib.util.find_spec("pyoidn")
    if spec is None or not spec.submodule_search_locations:
        return None
    folder = os.path.join(list(spec.submodule_search_locations)[0], "oidn", "bin" if os.name == "nt" else "lib")
    for name in ("libOpenImageDenoise.so.2", "libOpenImageDenoise.2.dylib", "OpenImageDenoise.dll"):
        path = os.path.join(folder, name)
        if os.path.isfile(path):
            return path
    return None


def _library() -> Optional[str]:
    """The library to open: ``$LUCENT_OIDN`` is left to the extension
    (which checks it first); otherwise this Python's ``pyoidn``; otherwise
    the extension's own search (the system's library path)."""
    if os.environ.get("LUCENT_OIDN"):
        return None
    return _pyoidn_library()


def _guide(image: Any, name: str, shape: "tuple[int, ...]") -> Optional[bytes]:
    if image is None:
        return None
    array = np.asarray(image, dtype=np.float32)
    if array.shape != shape:
        raise ValueError(f"{name} must have the image's shape {shape}, got {array.shape}")
    return np.ascontiguousarray(array, dtype="<f4").tobytes()


def denoise(
    color: Any,
    albedo: Any = None,
    normal: Any = None,
    *,
    quality: str = "default",
    aux: str = "prefilter",
    threads: Optional[int] = None,
) -> np.ndarray:
    """Denoise ``color`` (a ``(height, width, 3)`` array of linear radiance)
    with Intel Open Image Denoise's ``RT`` filter in HDR mode, guided by
    ``albedo`` and ``normal`` (arrays of the same shape, as
    ``Scene.render(aovs=["albedo", "normal"])`` returns them; a normal needs
    an albedo). Returns the denoised ``(height, width, 3)`` float32 array.

    ``quality``: ``"default"``, ``"fast"``, ``"balanced"`` or ``"high"``.
    ``aux``: ``"prefilter"`` (denoise the guides first, then use them as
    clean: OIDN's advice), ``"clean"`` (use them as clean, as they are) or
    ``"noisy"``. ``threads``: OIDN's worker threads (default: every core).

    Raises ``RuntimeError`` saying how to get OIDN when it is not found
    (``pip install lucent[denoise]`` or ``pip install pyoidn``)."""
    if quality not in QUALITIES:
        raise ValueError(f"unknown quality {quality!r} (accepted: {', '.join(QUALITIES)})")
    if aux not in AUX_MODES:
        raise ValueError(f"unknown aux {aux!r} (accepted: {', '.join(AUX_MODES)})")
    data, width, height = _image.to_bytes(color, "color")
    shape = (height, width, 3)
    out, _ = _native.denoise(
        data,
        width,
        height,
        _guide(albedo, "albedo", shape),
        _guide(normal, "normal", shape),
        quality,
        aux,
        threads,
        _library(),
    )
    return _image.from_bytes(out, width, height)


def layers(native: Dict[str, Any], width: int, height: int) -> Dict[str, np.ndarray]:
    """The extension's ``aov_images()`` dict as arrays: ``(height, width,
    3)`` for albedo, normal and position, ``(height, width)`` for depth."""
    out = {}
    for name, (channels, data) in native.items():
        array = np.frombuffer(data, dtype="<f4").astype(np.float32)
        out[name] = array.reshape(height, width, channels) if channels > 1 else array.reshape(height, width)
    return out
