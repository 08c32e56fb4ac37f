"""Scene dicts as JSON text for the library's loader, with a map from each
line of that text back to the key path it holds.

The loader reports errors at a line and column of the text it parsed. For a
scene made from a dict that text is made here, one key per line, so a line
names one place in the dict: ``camera.fov``, ``sphere[2].radius``,
``materials.red.matte.color``.
"""

import json
import math
import os
from typing import Any, List, Optional, Tuple

from ._errors import SceneError

_INDENT = "  "


def _join(path: str, key: str) -> str:
    if key.isidentifier():
        return f"{path}.{key}" if path else key
    return f"{path}[{json.dumps(key)}]"


def _plain(value: Any, path: str) -> Any:
    """``value`` as a JSON-ready Python value (NumPy scalars and arrays,
    tuples and paths are accepted)."""
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, (list, tuple, dict)):
        return value
    tolist = getattr(value, "tolist", None)  # NumPy arrays and scalars
    if callable(tolist):
        return tolist()
    raise _error(
        path,
        f"cannot use a value of type {type(value).__name__} in a scene "
        "(numbers, strings, booleans, lists and dicts are accepted)",
    )


def _scalar(value: Any, path: str) -> str:
    if isinstance(value, float) and not math.isfinite(value):
        raise _error(path, f"{value} is not a number a scene can hold (NaN and infinities are not accepted)")
    return json.dumps(value)


def _error(path: str, message: str) -> SceneError:
    return SceneError(f"scene dict, at {path or 'the top level'}: {message}", message=message, key=path or None)


def dump(scene: dict) -> Tuple[str, List[str]]:
    """The JSON text of ``scene`` and, for each of its lines, the key path
    of what that line holds ("" for the top level)."""
    lines: List[str] = []
    paths: List[str] = []

    def emit(text: str, path: str) -> None:
        lines.append(text)
        paths.append(path)

    def walk(value: Any, path: str, depth: int, prefix: str, suffix: str) -> None:
        pad = _INDENT * depth
        value = _plain(value, path)
        if isinstance(value, dict) and value:
            emit(f"{pad}{prefix}{{", path)
            items = list(value.items())
            for i, (key, item) in enumerate(items):
                if not isinstance(key, str):
                    raise _error(path, f"keys must be strings, got {key!r}")
                walk(item, _join(path, key), depth + 1, f"{json.dumps(key)}: ", "," if i < len(items) - 1 else "")
            emit(f"{pad}}}{suffix}", path)
        elif isinstance(value, (list, tuple)) and value:
            items = [_plain(v, f"{path}[{i}]") for i, v in enumerate(value)]
            if all(v is None or isinstance(v, (bool, int, float, str)) for v in items):
                emit(f"{pad}{prefix}[{', '.join(_scalar(v, f'{path}[{i}]') for i, v in enumerate(items))}]{suffix}", path)
                return
            emit(f"{pad}{prefix}[", path)
            for i, item in enumerate(items):
                walk(item, f"{path}[{i}]", depth + 1, "", "," if i < len(items) - 1 else "")
            emit(f"{pad}]{suffix}", path)
        elif isinstance(value, dict):
            emit(f"{pad}{prefix}{{}}{suffix}", path)
        elif isinstance(value, (list, tuple)):
            emit(f"{pad}{prefix}[]{suffix}", path)
        else:
            emit(f"{pad}{prefix}{_scalar(value, path)}{suffix}", path)

    if not isinstance(scene, dict):
        raise SceneError(
            f"a scene must be a dict, got {type(scene).__name__}",
            message=f"a scene must be a dict, got {type(scene).__name__}",
        )
    walk(scene, "", 0, "", "")
    return "\n".join(lines) + "\n", paths


def relocate(error: SceneError, paths: List[str], text_path: str) -> SceneError:
    """``error``, raised for the text of :func:`dump` (named ``text_path``
    in messages), restated for the dict: its key path instead of a line of
    text nobody wrote. An error about another file is returned as it is."""
    if error.path != text_path:
        return error
    key: Optional[str] = None
    if error.line is not None and 1 <= error.line <= len(paths):
        line = error.line
        # The parser reports an error in a value after looking past it: at
        # the `}` or `]` that closes its table when the value is the last
        # one. That error is the value's (but a missing key is the table's).
        text = (error.line_text or "").lstrip()
        at_start = error.column == len(error.line_text or "") - len(text) + 1
        if text[:1] in "}]" and text and at_start and not error.message.startswith("missing field") and line > 1:
            line -= 1
        key = paths[line - 1] or None
    where = f"at {key}" if key else "at the top level" if error.line is not None else ""
    text = f"scene dict{', ' + where if where else ''}: {error.message}"
    return SceneError(text, message=error.message, key=key)
