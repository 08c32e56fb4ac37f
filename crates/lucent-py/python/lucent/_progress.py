"""Progress reports for renders: a callable, a tqdm bar, or a bar of text
on stderr."""

import contextlib
import sys
import time
from typing import Any, Callable, Iterator, Optional

Progress = Any  # bool, or callable(done_fraction)


class _TextBar:
    """A one-line bar on stderr, for when tqdm is not installed."""

    WIDTH = 30

    def __init__(self, label: str) -> None:
        self.label = label
        self.start = time.monotonic()
        self.shown = -1

    def __call__(self, fraction: float) -> None:
        cells = int(fraction * self.WIDTH)
        percent = int(fraction * 100)
        if percent == self.shown:
            return
        self.shown = percent
        elapsed = time.monotonic() - self.start
        bar = "#" * cells + "-" * (self.WIDTH - cells)
        sys.stderr.write(f"\r{self.label} [{bar}] {percent:3d}% {elapsed:6.1f} s")
        sys.stderr.flush()

    def close(self) -> None:
        if self.shown >= 0:
            sys.stderr.write("\n")
            sys.stderr.flush()


class _TqdmBar:
    """A tqdm bar of 100 steps (the render reports fractions)."""

    def __init__(self, tqdm: Any, label: str) -> None:
        self.bar = tqdm(total=100, desc=label, unit="%", leave=False)
        self.done = 0

    def __call__(self, fraction: float) -> None:
        n = int(fraction * 100)
        if n > self.done:
            self.bar.update(n - self.done)
            self.done = n

    def close(self) -> None:
        self.bar.close()


@contextlib.contextmanager
def reporter(progress: Progress, label: str = "render") -> Iterator[Optional[Callable[[float], None]]]:
    """The callable to give a render for ``progress``: ``False``/``None``
    → none; ``True`` → a tqdm bar if tqdm is importable, else a text bar
    on stderr; a callable → itself (called with the fraction done, 0 to 1,
    increasing, last with 1.0)."""
    if progress is None or progress is False:
        yield None
        return
    if callable(progress):
        yield progress
        return
    if progress is not True:
        raise TypeError(f"progress must be True, False or a callable, got {type(progress).__name__}")
    try:
        from tqdm.auto import tqdm  # type: ignore
    except ImportError:
        bar: Any = _TextBar(label)
    else:
        bar = _TqdmBar(tqdm, label)
    try:
        yield bar
    finally:
        bar.close()
