"""A scene and every file it reads, as one archive for machines without the files.

A distributed render sends the scene to its workers once, as a tar archive
that holds the scene file and every file the scene read (meshes, textures,
included pbrt files, environment maps), stored relative to the files'
deepest common directory so that the scene's relative paths keep working
where it is unpacked. A manifest inside says which member is the scene and
with which load options (``strict``, and the ``env`` image remapped into the
archive) to load it.

The archive is deterministic (sorted members, no times or owners), so the
same scene always gives the same bytes and the same SHA-256, which names the
directory it is unpacked into on each worker: a worker unpacks a scene once,
however many chunks it renders, and reuses it for later renders of the same
scene. Unpacking is safe against two processes doing it at once (each
unpacks into a temporary directory and renames it into place) and against
hostile archives (absolute paths, ``..``, links and devices are refused).

This module does not import Dask: it is plain files and bytes.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import shutil
import tarfile
import tempfile
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Any, Dict, List, Optional, Tuple

#: Version of the archive layout; an unpacker refuses another.
FORMAT = 1

#: The manifest's member name. Scene files are stored under ``FILES``, so
#: no scene file can collide with it.
MANIFEST = "manifest.json"
FILES = "files"

#: The name given to a scene that has no file of its own (a dict or builder
#: scene): its description as JSON, placed in the scene's ``base_dir`` so
#: that its relative paths resolve as they did.
DICT_SCENE_NAME = "__lucent_scene__.json"

#: Environment variable naming the directory archives are unpacked into.
CACHE_ENV = "LUCENT_DASK_CACHE"


class ArchiveError(ValueError):
    """A scene archive that cannot be made, or one that is damaged or unsafe to unpack."""


@dataclass(frozen=True)
class SceneArchive:
    """A scene packed for shipping: the tar bytes and what is needed to check and load them.

    ``data`` is the tar archive, ``sha256`` its hex digest (the cache key on
    the workers), ``scene`` the scene member's path inside the archive's
    ``files/`` tree and ``members`` every file it holds (relative to that
    tree), with ``root`` the local directory they were taken from.
    """

    data: bytes
    sha256: str
    scene: str
    members: Tuple[str, ...]
    root: str
    load_options: Dict[str, Any] = field(default_factory=dict)


def _absolute(path: str) -> str:
    """``path`` made absolute and normalised lexically (``a/b/../c`` → ``a/c``).

    Lexical, not ``realpath``: a file reached through a symbolic link is
    stored where the scene sees it, so the scene's relative paths find it.
    """
    return os.path.normpath(os.path.abspath(os.fspath(path)))


def _member_name(path: str, root: str) -> str:
    """The archive name (POSIX separators) of the absolute ``path`` under ``root``."""
    rel = os.path.relpath(path, root)
    return PurePosixPath(*Path(rel).parts).as_posix()


def _scene_source(scene) -> Tuple[str, Optional[bytes], List[str]]:
    """The scene file's absolute path, its bytes if it has no file of its
    own (a dict scene's JSON), and every other file the scene read.
    """
    files = [_absolute(f) for f in (scene.files or [])]
    path = getattr(scene, "path", None)
    if path is not None and os.path.isfile(path):
        scene_path = _absolute(path)
        return scene_path, None, [f for f in files if f != scene_path]
    # A scene made from a dict (or a builder): its description, as JSON, in
    # the directory its relative paths resolve against.
    try:
        description = scene.to_dict()
    except Exception as e:  # the bindings say which scenes have no description
        raise ArchiveError(f"this scene cannot be sent to other machines: it has no scene file and {e}") from e
    base = getattr(scene, "base_dir", None) or os.getcwd()
    try:
        # The very text the bindings give the library for a dict (NumPy
        # values and paths made plain), so the workers parse what we did.
        from lucent._keypath import dump

        text = dump(description)[0].encode("utf-8")
    except ImportError:
        text = json.dumps(description, indent=1).encode("utf-8")
    return os.path.join(_absolute(base), DICT_SCENE_NAME), text, files


def _tar_info(name: str, size: int, directory: bool = False) -> tarfile.TarInfo:
    """A member header with nothing that changes from one machine or run to the next."""
    info = tarfile.TarInfo(name)
    info.size = 0 if directory else size
    info.type = tarfile.DIRTYPE if directory else tarfile.REGTYPE
    info.mode = 0o755 if directory else 0o644
    info.mtime = 0
    info.uid = info.gid = 0
    info.uname = info.gname = ""
    return info


def build(scene) -> SceneArchive:
    """Pack ``scene`` (a :class:`lucent.Scene`) with every file it read into one archive.

    The load options (``strict``, ``env``) are recorded in the manifest,
    ``env`` as the archive member it became. Raises :class:`ArchiveError` if
    a file cannot be read or the files have no common directory (different
    drives on Windows).
    """
    scene_path, scene_bytes, files = _scene_source(scene)
    options = dict(getattr(scene, "load_options", None) or {})
    env = options.get("env")
    if env is not None:
        env = _absolute(env)
        if env not in files:
            files.append(env)
    files = sorted(set(files))
    everything = [scene_path] + files
    try:
        root = os.path.commonpath([os.path.dirname(p) for p in everything])
    except ValueError as e:
        raise ArchiveError(f"the scene's files have no common directory to pack them from: {e}") from e

    names = {p: _member_name(p, root) for p in everything}
    contents: Dict[str, bytes] = {}
    for p in files:
        try:
            with open(p, "rb") as f:
                contents[names[p]] = f.read()
        except OSError as e:
            raise ArchiveError(f"cannot read {p}, which the scene uses: {e.strerror or e}") from e
    if scene_bytes is None:
        try:
            with open(scene_path, "rb") as f:
                scene_bytes = f.read()
        except OSError as e:
            raise ArchiveError(f"cannot read the scene file {scene_path}: {e.strerror or e}") from e
    contents[names[scene_path]] = scene_bytes

    manifest = {
        "format": FORMAT,
        "scene": names[scene_path],
        "strict": bool(options.get("strict", False)),
        "env": names[env] if env is not None else None,
        # glTF scenes: which scene and camera of the file.
        "gltf_scene": options.get("scene"),
        "camera": options.get("camera"),
        "files": {
            name: {"size": len(data), "sha256": hashlib.sha256(data).hexdigest()}
            for name, data in sorted(contents.items())
        },
    }
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w", format=tarfile.PAX_FORMAT) as tar:
        text = json.dumps(manifest, sort_keys=True, indent=1).encode("utf-8")
        tar.addfile(_tar_info(MANIFEST, len(text)), io.BytesIO(text))
        for name, data in sorted(contents.items()):
            tar.addfile(_tar_info(f"{FILES}/{name}", len(data)), io.BytesIO(data))
    data = buffer.getvalue()
    return SceneArchive(
        data=data,
        sha256=hashlib.sha256(data).hexdigest(),
        scene=names[scene_path],
        members=tuple(sorted(contents)),
        root=root,
        load_options={"strict": manifest["strict"], "env": manifest["env"]},
    )


def _safe_name(name: str) -> PurePosixPath:
    """``name`` as a relative path that stays inside the directory it is unpacked into.

    Refuses absolute paths, drive letters, backslashes (a separator on
    Windows) and any ``..`` component, whatever the platform.
    """
    if not name or "\\" in name or "\0" in name:
        raise ArchiveError(f"unsafe member name in scene archive: {name!r}")
    p = PurePosixPath(name)
    if p.is_absolute() or (len(name) > 1 and name[1] == ":"):
        raise ArchiveError(f"scene archive member has an absolute path: {name!r}")
    if any(part == ".." for part in p.parts):
        raise ArchiveError(f"scene archive member leaves the archive ('..'): {name!r}")
    return p


def default_cache_dir() -> str:
    """Where archives are unpacked: ``$LUCENT_DASK_CACHE``, else ``lucent-dask-cache``
    in the temporary directory (shared by every worker process of a machine)."""
    configured = os.environ.get(CACHE_ENV)
    if configured:
        return configured
    user = str(os.getuid()) if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    return os.path.join(tempfile.gettempdir(), f"lucent-dask-cache-{user}")


def _check_manifest(manifest: Any) -> dict:
    """``manifest`` if it has the shape :func:`build` writes: a ``files`` table of
    ``{"sha256": hex}`` entries under safe names, the ``scene`` and any ``env``
    among them, and options of the right types. Anything else, from a damaged
    or hostile archive, is an :class:`ArchiveError` (never a ``KeyError`` or
    a path outside the archive)."""
    if not isinstance(manifest, dict):
        raise ArchiveError("scene archive has a damaged manifest: it is not a JSON object")
    if manifest.get("format") != FORMAT:
        raise ArchiveError(
            f"scene archive format {manifest.get('format')!r} is not {FORMAT}: "
            "the workers run another version of lucent"
        )
    listed = manifest.get("files")
    if not isinstance(listed, dict) or not all(
        isinstance(entry, dict) and isinstance(entry.get("sha256"), str) for entry in listed.values()
    ):
        raise ArchiveError("scene archive has a damaged manifest: `files` is not a table of SHA-256 digests")
    for name in listed:
        _safe_name(name)
    scene, env = manifest.get("scene"), manifest.get("env")
    if not isinstance(scene, str) or scene not in listed:
        raise ArchiveError("scene archive's manifest names no scene among its files")
    if env is not None and (not isinstance(env, str) or env not in listed):
        raise ArchiveError("scene archive's manifest names an environment map that is not among its files")
    gltf_scene, camera = manifest.get("gltf_scene"), manifest.get("camera")
    if gltf_scene is not None and (type(gltf_scene) is not int or gltf_scene < 0):
        raise ArchiveError(f"scene archive's manifest has a bad glTF scene index {gltf_scene!r}")
    if camera is not None and not isinstance(camera, (str, int)):
        raise ArchiveError(f"scene archive's manifest has a bad camera {camera!r}")
    return manifest


def _extract(data: bytes, into: str) -> dict:
    """Unpack the archive ``data`` into the empty directory ``into``, checking every
    member against the manifest; returns the manifest."""
    try:
        return _extract_members(data, into)
    except ArchiveError:
        raise
    except (tarfile.TarError, EOFError, ValueError, OverflowError) as e:
        # Besides TarError, tarfile lets damaged headers escape as
        # ValueError (a negative base-256 member size: "negative seek
        # value") and OverflowError (a size past 2⁶³: "Python int too large
        # to convert to C ssize_t").
        raise ArchiveError(f"not a scene archive, or a damaged one: {e}") from e
    except OSError as e:
        # Members that collide on disk (a file and a directory of one name).
        raise ArchiveError(f"scene archive cannot be unpacked: {e.strerror or e}") from e


def _extract_members(data: bytes, into: str) -> dict:
    tar = tarfile.open(fileobj=io.BytesIO(data), mode="r:")
    with tar:
        members = tar.getmembers()
        for m in members:
            _safe_name(m.name)
            if not (m.isfile() or m.isdir()):
                raise ArchiveError(f"scene archive member is not a plain file: {m.name!r}")
            if m.size < 0:
                raise ArchiveError(f"scene archive member {m.name!r} has a negative size ({m.size} bytes)")
        by_name = {m.name: m for m in members if m.isfile()}
        if MANIFEST not in by_name:
            raise ArchiveError("scene archive has no manifest")
        try:
            manifest = json.loads(tar.extractfile(by_name[MANIFEST]).read().decode("utf-8"))
        except (ValueError, UnicodeDecodeError, RecursionError) as e:
            raise ArchiveError(f"scene archive has a damaged manifest: {e}") from e
        listed = _check_manifest(manifest)["files"]
        stored = {n[len(FILES) + 1 :]: m for n, m in by_name.items() if n.startswith(FILES + "/")}
        if set(listed) != set(stored):
            raise ArchiveError("scene archive's files do not match its manifest")
        for name, member in sorted(stored.items()):
            rel = _safe_name(name)
            content = tar.extractfile(member).read()
            if hashlib.sha256(content).hexdigest() != listed[name]["sha256"]:
                raise ArchiveError(f"scene archive member {name!r} is damaged (its SHA-256 differs)")
            target = os.path.join(into, FILES, *rel.parts)
            os.makedirs(os.path.dirname(target), exist_ok=True)
            with open(target, "wb") as f:
                f.write(content)
        with open(os.path.join(into, MANIFEST), "w", encoding="utf-8") as f:
            json.dump(manifest, f)
    return manifest


def unpack(data: bytes, sha256: str, cache_dir: Optional[str] = None) -> Tuple[str, dict]:
    """Unpack an archive into ``cache_dir/<sha256>`` once; returns that directory's
    ``files`` tree and the manifest.

    The bytes are checked against ``sha256`` first. If the directory is
    already there (an earlier chunk or render, or another worker process of
    this machine) it is used as it is. Otherwise the archive is unpacked
    into a temporary directory beside it and renamed into place, so a
    half-unpacked directory is never seen; of two processes doing this at
    once, one rename wins and the other's copy is removed.
    """
    if hashlib.sha256(data).hexdigest() != sha256:
        raise ArchiveError("scene archive arrived damaged: its SHA-256 differs from the one sent")
    cache = cache_dir or default_cache_dir()
    final = os.path.join(cache, sha256)
    if not os.path.isfile(os.path.join(final, MANIFEST)):
        os.makedirs(cache, exist_ok=True)
        temp = tempfile.mkdtemp(prefix=f".{sha256[:16]}-", dir=cache)
        try:
            _extract(data, temp)
            try:
                os.rename(temp, final)
            except OSError:
                # Someone else's copy got there first (the target exists and
                # is not empty); theirs is the same bytes.
                if not os.path.isfile(os.path.join(final, MANIFEST)):
                    raise
        finally:
            shutil.rmtree(temp, ignore_errors=True)
    with open(os.path.join(final, MANIFEST), encoding="utf-8") as f:
        manifest = json.load(f)
    return os.path.join(final, FILES), manifest


def load(archive: SceneArchive, cache_dir: Optional[str] = None):
    """Unpack ``archive`` (once) and load its scene (a :class:`lucent.Scene`)
    with the options it was loaded with where it was packed."""
    import lucent

    files, manifest = unpack(archive.data, archive.sha256, cache_dir)
    scene_path, options = load_arguments(files, manifest)
    return lucent.load(scene_path, **options)


def load_arguments(files: str, manifest: dict) -> Tuple[str, Dict[str, Any]]:
    """The scene file under the unpacked ``files`` tree and the keyword arguments of
    :func:`lucent.load` that ``manifest`` (checked when it was unpacked) asks for;
    every path lies inside ``files``."""
    manifest = _check_manifest(manifest)
    scene_path = os.path.join(files, *_safe_name(manifest["scene"]).parts)
    options: Dict[str, Any] = {}
    if manifest.get("strict"):
        options["strict"] = True
    if manifest.get("env"):
        options["env"] = os.path.join(files, *_safe_name(manifest["env"]).parts)
    if manifest.get("gltf_scene") is not None:
        options["scene"] = manifest["gltf_scene"]
    if manifest.get("camera") is not None:
        options["camera"] = str(manifest["camera"])
    return scene_path, options
