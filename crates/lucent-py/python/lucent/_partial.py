"""Partial renders: the samples of a range of sample indices, to be added
to the others (on other machines, at other times) into the full image."""

import os
from typing import Any, List, Tuple, Union

import numpy as np

from . import _image, _native

PathLike = Union[str, "os.PathLike[str]"]


class Partial:
    """The accumulated samples of some sample ranges of a render, made by
    :meth:`lucent.Scene.render_partial` or :func:`lucent.load_partial`.

    Partials of the same scene and settings (the same :attr:`fingerprint`)
    add with ``+`` (and ``sum(parts)``) when their ranges do not overlap;
    partials covering samples ``0 .. spp`` add up to the full render's image
    bit for bit, in any order. A partial pickles (for multiprocessing or
    Dask) as its bytes. Errors (different scenes, overlapping ranges,
    damaged data) raise :class:`lucent.PartialError`.
    """

    __slots__ = ("_native",)

    def __init__(self, native: Any) -> None:
        self._native = native

    @classmethod
    def from_bytes(cls, data: bytes) -> "Partial":
        """A partial from :meth:`to_bytes`'s bytes (checked: damaged data
        raises :class:`lucent.PartialError`)."""
        return cls(_native.Partial.from_bytes(bytes(data)))

    def to_bytes(self) -> bytes:
        """The partial as bytes (the ``.lpart`` file format)."""
        return self._native.to_bytes()

    def __reduce__(self) -> Tuple[Any, Tuple[bytes]]:
        return (Partial.from_bytes, (self.to_bytes(),))

    def __add__(self, other: Any) -> "Partial":
        if isinstance(other, Partial):
            return Partial(self._native.merge(other._native))
        return NotImplemented

    def __radd__(self, other: Any) -> "Partial":
        # sum() starts from 0.
        if isinstance(other, int) and other == 0:
            return self
        return NotImplemented

    @property
    def width(self) -> int:
        """Image width in pixels."""
        return self._native.width

    @property
    def height(self) -> int:
        """Image height in pixels."""
        return self._native.height

    @property
    def spp(self) -> int:
        """Samples per pixel held (the total length of :attr:`ranges`)."""
        return self._native.spp

    @property
    def ranges(self) -> List[range]:
        """The sample ranges held, sorted, as ``range`` objects."""
        return [range(a, b) for a, b in self._native.ranges()]

    @property
    def missing(self) -> List[range]:
        """The sample ranges below the highest one held that are not held
        (empty when the partial is a whole render of ``0 .. spp``)."""
        return [range(a, b) for a, b in self._native.missing()]

    @property
    def fingerprint(self) -> int:
        """The fingerprint of the scene and settings rendered (see
        :meth:`lucent.Scene.fingerprint`)."""
        return self._native.fingerprint

    def image(self) -> np.ndarray:
        """The image of the samples held: a ``(height, width, 3)`` float32
        array of linear radiance."""
        return _image.from_bytes(self._native.image(), self.width, self.height)

    def aovs(self) -> "dict[str, np.ndarray]":
        """The auxiliary images of the samples held (rendered with
        ``aovs``), by name: ``(height, width, 3)`` arrays, ``(height,
        width)`` for depth."""
        from ._denoise import layers

        return layers(self._native.aov_images(), self.width, self.height)

    def save(self, path: PathLike) -> None:
        """Write the partial to ``path`` (an ``.lpart`` file), atomically."""
        self._native.save(os.fspath(path))

    def __eq__(self, other: Any) -> bool:
        if not isinstance(other, Partial):
            return NotImplemented
        return self.to_bytes() == other.to_bytes()

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        ranges = ", ".join(f"{r.start}..{r.stop}" for r in self.ranges)
        return f"<lucent.Partial {self.width}×{self.height}, samples {ranges}, fingerprint {self.fingerprint:#018x}>"


def load_partial(path: PathLike) -> Partial:
    """Read a partial render saved by :meth:`Partial.save` (``.lpart``);
    a damaged or foreign file raises :class:`lucent.PartialError`."""
    return Partial(_native.Partial.load(os.fspath(path)))
