"""The exceptions of lucent (raised by the extension module and the package)."""

from typing import Optional


class SceneError(ValueError):
    """A scene that cannot be loaded or built.

    ``str(error)`` is the library's complete message: the file, line and
    column, what is wrong, and the offending line with a caret under the
    position. The parts are attributes:

    * ``message``: what is wrong, without the location;
    * ``path``: the scene file (``None`` for a scene made from a dict);
    * ``line``, ``column``: 1-based position in the file, or ``None``;
    * ``line_text``: the text of that line, or ``None``;
    * ``key``: for a scene made from a dict, where in the dict the error
      is, as a key path such as ``"camera.fov"`` or ``"sphere[1].radius"``
      (``None`` when unknown or for a file).
    """

    def __init__(
        self,
        text: str,
        *,
        message: Optional[str] = None,
        path: Optional[str] = None,
        line: Optional[int] = None,
        column: Optional[int] = None,
        line_text: Optional[str] = None,
        key: Optional[str] = None,
    ) -> None:
        super().__init__(text)
        self.message = text if message is None else message
        self.path = path
        self.line = line
        self.column = column
        self.line_text = line_text
        self.key = key


class PartialError(ValueError):
    """Partial renders that cannot be merged (different scenes or
    settings, overlapping sample ranges, different sizes), or damaged
    partial-render data."""
