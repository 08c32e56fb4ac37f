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
    raise SceneError(
        f"scene dict, at {path or 'the top level'}: cannot use a value of type "
        f"{type(value).__name__} in a scene (numbers, strings, booleans, lists and dicts are accepted)",
        message=f"cannot use a value of type {type(value).__name__} in a scene",
        key=path or None,
    )


def _scalar(value: Any) -> str:
    if isinstance(value, float) and not math.isfinite(value):
        # Not JSON: the loader reports it at this line, with this text.
        return repr(value)
    return json.dumps(value)


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
                    raise SceneError(
                        f"scene dict, at {path or 'the top level'}: keys must be strings, got {key!r}",
                        message=f"keys must be strings, got {key!r}",
                        key=path or None,
                    )
                walk(item, _join(path, key), depth + 1, f"{json.dumps(key)}: ", "," if i < len(items) - 1 else "")
            emit(f"{pad}}}{suffix}", path)
        elif isinstance(value, (list, tuple)) and value:
            items = [_plain(v, f"{path}[{i}]") for i, v in enumerate(value)]
            if all(v is None or isinstance(v, (bool, int, float, str)) for v in items):
                emit(f"{pad}{prefix}[{', '.join(_scalar(v) for v in items)}]{suffix}", path)
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
            emit(f"{pad}{prefix}{_scalar(value)}{suffix}", path)

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
        key = paths[error.line - 1] or None
    where = f"at {key}" if key else "at the top level" if error.line is not None else ""
    text = f"scene dict{', ' + where if where else ''}: {error.message}"
    return SceneError(text, message=error.message, key=key)
