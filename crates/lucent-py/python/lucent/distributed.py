"""Render one image across the machines of a Dask cluster, bit-identical to a local render.

lucent's film sums samples as exact fixed-point integers, so renders of
disjoint ranges of sample indices add up to exactly the image one machine
makes of all of them (:class:`lucent.Partial`). This module splits a
render's samples per pixel into chunks (``[0, 4)``, ``[4, 8)``, ...), renders
each chunk as a Dask task on some worker and adds the partial renders up as
they arrive::

    from dask.distributed import Client
    import lucent, lucent.distributed

    client = Client("tcp://scheduler:8786")
    scene = lucent.load("scenes/cornell-box.toml")
    image = lucent.distributed.render(scene, client, spp=256)

The workers need no shared file system: the scene file and every file it
reads travel once per render as one archive (:mod:`lucent._archive`),
unpacked once per machine into a cache keyed by its SHA-256. A worker that
dies loses only the chunks it was rendering; Dask runs them again
elsewhere, and the image is the same bit for bit.

Dask is an optional dependency (``pip install 'lucent[distributed]'``);
``import lucent`` never imports it, only this module does.
"""

from __future__ import annotations

import math
import os
import sys
import threading
import uuid
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

try:
    import dask
    from dask.distributed import Client, as_completed, get_worker
    from dask.utils import parse_bytes
except ImportError as _e:  # pragma: no cover - depends on the environment
    raise ImportError(
        "lucent.distributed needs Dask's distributed scheduler, which is not installed: "
        "pip install 'lucent[distributed]' (or: pip install 'dask[distributed]')"
    ) from _e

import lucent
from lucent import _archive

__all__ = ["RenderJob", "prepare", "render", "render_partial", "default_chunk", "sample_ranges"]

#: Chunks per worker thread that :func:`default_chunk` aims for: enough that
#: every thread stays busy to the end, and that a lost worker costs little.
CHUNKS_PER_THREAD = 4


class DistributedRenderError(RuntimeError):
    """A distributed render whose parts do not make the image asked for:
    workers that loaded a different scene, or another version of lucent."""


@dataclass(frozen=True)
class RenderJob:
    """A scene ready to be rendered on a cluster: its archive, the render's
    settings and the fingerprint every part must have.

    Made by :func:`prepare`, which reads the scene's files once; after that
    the job needs none of them (the archive holds them), so a job can be
    rendered after the files have moved.
    """

    archive: _archive.SceneArchive
    spp: int
    fingerprint: int
    render_kwargs: Dict[str, Any] = field(default_factory=dict)


def default_chunk(spp: int, threads: int) -> int:
    """Samples per pixel per chunk so that ``spp`` makes about
    :data:`CHUNKS_PER_THREAD` chunks for each of ``threads`` worker threads
    (at least 1 sample per chunk)."""
    return max(1, math.ceil(spp / (CHUNKS_PER_THREAD * max(1, threads))))


def sample_ranges(start: int, end: int, chunk: int) -> List[Tuple[int, int]]:
    """The half-open sample ranges ``[s, s + chunk)`` that cover ``[start, end)``."""
    if chunk < 1:
        raise ValueError(f"chunk must be at least 1 sample per pixel, got {chunk}")
    return [(s, min(s + chunk, end)) for s in range(start, end, chunk)]


#: The render settings besides size, samples and seed that a job carries.
_OVERRIDES = ("integrator", "sampler", "max_depth", "aovs", "filter_importance")


def _render_kwargs(width, height, spp, seed, overrides) -> Dict[str, Any]:
    unknown = sorted(set(overrides) - set(_OVERRIDES))
    if unknown:
        raise TypeError(
            f"unexpected keyword arguments for a distributed render: {', '.join(unknown)} "
            f"(accepted besides spp, width, height, seed: {', '.join(_OVERRIDES)}; "
            "threads per task are chunk_threads)"
        )
    kwargs = {"width": width, "height": height, "spp": spp, "seed": seed, **overrides}
    return {k: v for k, v in kwargs.items() if v is not None}


def prepare(
    scene: Union["lucent.Scene", str, os.PathLike],
    *,
    spp: Optional[int] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    seed: Optional[int] = None,
    **overrides: Any,
) -> RenderJob:
    """Pack ``scene`` (a :class:`lucent.Scene` or a scene file's path) for a
    distributed render with these settings.

    ``spp``, ``width``, ``height``, ``seed`` and the other ``overrides``
    (``integrator``, ``sampler``, ``max_depth``) are those of
    :meth:`lucent.Scene.render`; ``spp`` defaults to the scene's own. The
    job's fingerprint is the local scene's, which every part rendered on
    the cluster must match.
    """
    if not isinstance(scene, lucent.Scene):
        scene = lucent.load(scene)
    kwargs = _render_kwargs(width, height, spp, seed, overrides)
    total = int(spp) if spp is not None else _scene_spp(scene, kwargs)
    if total < 1:
        raise ValueError(f"spp must be at least 1, got {total}")
    kwargs["spp"] = total
    fingerprint = scene.fingerprint(**kwargs)
    return RenderJob(archive=_archive.build(scene), spp=total, fingerprint=fingerprint, render_kwargs=kwargs)


def _scene_spp(scene, kwargs) -> int:
    """The samples per pixel the scene itself asks for."""
    spp = getattr(scene, "spp", None)
    if callable(spp):
        spp = spp(**kwargs)
    if spp is None:
        raise ValueError("give spp: the scene does not say how many samples per pixel to render")
    return int(spp)


# ---- on the workers -------------------------------------------------------

#: Scenes loaded in this worker process, by archive hash: a worker loads a
#: scene once, however many chunks of it it renders. A few are kept, the
#: most recently used last.
_LOADED: "OrderedDict[str, Any]" = OrderedDict()
_LOADED_MAX = 2
_LOAD_LOCK = threading.Lock()


def _loaded_scene(archive: _archive.SceneArchive, cache_dir: Optional[str]):
    """The archive's scene, unpacked and loaded once per worker process."""
    with _LOAD_LOCK:
        scene = _LOADED.get(archive.sha256)
        if scene is None:
            scene = _archive.load(archive, cache_dir)
            _LOADED[archive.sha256] = scene
            while len(_LOADED) > _LOADED_MAX:
                _LOADED.popitem(last=False)
        _LOADED.move_to_end(archive.sha256)
        return scene


def _where() -> str:
    """This worker's address, for messages."""
    try:
        return get_worker().address
    except ValueError:
        return "a worker"


def _ship_archive(archive: _archive.SceneArchive) -> _archive.SceneArchive:
    """The task whose result is the archive on the workers.

    A task rather than scattered data: if every worker that holds the
    archive dies, the scheduler recomputes it from the task (which carries
    the bytes) instead of failing the render.
    """
    return archive


def _render_chunk(
    archive: _archive.SceneArchive,
    start: int,
    end: int,
    render_kwargs: Dict[str, Any],
    fingerprint: int,
    version: str,
    threads: int,
    cache_dir: Optional[str],
):
    """Render samples ``[start, end)`` of the archive's scene on this worker;
    returns the :class:`lucent.Partial`."""
    if lucent.__version__ != version:
        raise DistributedRenderError(
            f"{_where()} runs lucent {lucent.__version__}, the client {version}: install the same version everywhere"
        )
    scene = _loaded_scene(archive, cache_dir)
    part = scene.render_partial(start, end, threads=threads, progress=False, **render_kwargs)
    if part.fingerprint != fingerprint:
        raise DistributedRenderError(
            f"{_where()} loaded a different scene from the archive (fingerprint {part.fingerprint:016x}, "
            f"expected {fingerprint:016x}): a file the scene reads is missing from the archive or differs"
        )
    return part


# ---- on the client --------------------------------------------------------


class _Progress:
    """Samples per pixel done across the cluster: a tqdm bar if tqdm is
    installed, else a line on stderr; or a callable given the fraction done."""

    def __init__(self, progress, total: int, workers: int):
        self.total, self.done = total, 0
        self.callback: Optional[Callable[[float], Any]] = None
        self.bar = None
        self.line = False
        if callable(progress):
            self.callback = progress
        elif progress:
            try:
                from tqdm.auto import tqdm

                self.bar = tqdm(total=total, unit="spp", desc=f"lucent on {workers} workers", leave=False)
            except ImportError:
                self.line = True
                self._print()

    def _print(self):
        percent = 100.0 * self.done / self.total if self.total else 100.0
        sys.stderr.write(f"\rlucent: {self.done}/{self.total} spp ({percent:.0f}%)")
        sys.stderr.flush()

    def add(self, spp: int):
        self.done += spp
        if self.callback is not None:
            self.callback(self.done / self.total if self.total else 1.0)
        if self.bar is not None:
            self.bar.update(spp)
        if self.line:
            self._print()

    def close(self):
        if self.bar is not None:
            self.bar.close()
        if self.line:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _cluster_threads(client: Client) -> int:
    """Worker threads in the cluster now (at least 1)."""
    return max(1, sum(client.nthreads().values()))


def render_partial(
    scene: Union["lucent.Scene", RenderJob, str, os.PathLike],
    client: Client,
    start: int = 0,
    end: Optional[int] = None,
    *,
    spp: Optional[int] = None,
    chunk: Optional[int] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    seed: Optional[int] = None,
    progress: Union[bool, Callable[[float], Any]] = True,
    chunk_threads: int = 1,
    cache_dir: Optional[str] = None,
    **overrides: Any,
):
    """Render samples ``[start, end)`` of ``scene`` on the workers of ``client``;
    returns the merged :class:`lucent.Partial`.

    ``scene`` is a :class:`lucent.Scene`, a scene file's path or a
    :class:`RenderJob` from :func:`prepare` (whose settings are then used,
    and ``spp``, ``width``, ``height``, ``seed`` and ``overrides`` must not
    be given). ``end`` defaults to ``spp``, which defaults to the scene's.
    The range is split into chunks of ``chunk`` samples per pixel (default:
    :func:`default_chunk` for the cluster's thread count), each a Dask task
    that renders on ``chunk_threads`` threads: Dask already runs as many
    tasks at once on a worker as it has threads, so 1 keeps every core busy;
    raise it for workers started with fewer Dask threads than cores.
    ``progress`` is ``True`` (a bar of samples done across the cluster),
    ``False``, or a callable given the fraction done after each chunk.
    ``cache_dir`` is where workers unpack the scene (default:
    ``$LUCENT_DASK_CACHE`` or a directory in their temporary directory).

    Raises what a worker raised (a :class:`lucent.SceneError` for a scene
    that fails to load there), or :class:`DistributedRenderError` if the
    parts are not of this scene.
    """
    if isinstance(scene, RenderJob):
        if spp is not None or width is not None or height is not None or seed is not None or overrides:
            raise TypeError("a RenderJob carries its own settings: give spp, width, height and seed to prepare()")
        job = scene
    else:
        job = prepare(scene, spp=spp, width=width, height=height, seed=seed, **overrides)
    end = job.spp if end is None else int(end)
    start = int(start)
    if not 0 <= start < end <= job.spp:
        raise ValueError(f"sample range [{start}, {end}) is not within [0, {job.spp})")
    if int(chunk_threads) < 1:
        raise ValueError(f"chunk_threads must be at least 1, got {chunk_threads}")
    threads = _cluster_threads(client)
    step = default_chunk(end - start, threads) if chunk is None else int(chunk)
    ranges = sample_ranges(start, end, step)

    token = uuid.uuid4().hex[:12]
    # The archive's bytes travel inside its task; allow them past Dask's
    # warning about large graphs, which is meant for data that belongs in
    # a data set, not for a scene.
    limit = max(
        parse_bytes(dask.config.get("distributed.admin.large-graph-warning-threshold", "10MB")),
        len(job.archive.data) + (1 << 20),
    )
    with dask.config.set({"distributed.admin.large-graph-warning-threshold": limit}):
        shipped = client.submit(_ship_archive, job.archive, key=f"lucent-scene-{token}", pure=False)
    futures = [
        client.submit(
            _render_chunk,
            shipped,
            s,
            e,
            job.render_kwargs,
            job.fingerprint,
            lucent.__version__,
            int(chunk_threads),
            cache_dir,
            key=f"lucent-chunk-{s}-{e}-{token}",
            pure=False,
        )
        for s, e in ranges
    ]
    bar = _Progress(progress, end - start, len(client.nthreads()))
    total = None
    try:
        for future in as_completed(futures):
            part = future.result()
            future.release()  # its sums are ours now; free the worker's copy
            if part.fingerprint != job.fingerprint:
                raise DistributedRenderError(
                    f"a part of samples {part.ranges} has fingerprint {part.fingerprint:016x}, "
                    f"not this scene's {job.fingerprint:016x}"
                )
            total = part if total is None else total + part
            bar.add(part.spp)
    finally:
        bar.close()
        pending = [f for f in futures if not f.done()]
        if pending:
            client.cancel(pending)
        shipped.release()
    if total.spp != end - start:
        raise DistributedRenderError(f"the parts hold {total.spp} samples per pixel, not {end - start}")
    return total


def render(
    scene: Union["lucent.Scene", RenderJob, str, os.PathLike],
    client: Client,
    *,
    spp: Optional[int] = None,
    chunk: Optional[int] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    seed: Optional[int] = None,
    progress: Union[bool, Callable[[float], Any]] = True,
    return_partial: bool = False,
    chunk_threads: int = 1,
    cache_dir: Optional[str] = None,
    **overrides: Any,
):
    """Render ``scene`` with all its samples on the workers of ``client``:
    the float32 ``(height, width, 3)`` linear image, bit-identical to
    ``scene.render(spp=spp, seed=seed, ...)`` on one machine.

    With ``return_partial=True`` the merged :class:`lucent.Partial` is
    returned instead (save it with ``.save(path)``, add more samples to it,
    or take ``.image()``). The other arguments are those of
    :func:`render_partial`.
    """
    total = render_partial(
        scene,
        client,
        spp=spp,
        chunk=chunk,
        width=width,
        height=height,
        seed=seed,
        progress=progress,
        chunk_threads=chunk_threads,
        cache_dir=cache_dir,
        **overrides,
    )
    if total.missing:
        raise DistributedRenderError(f"samples {total.missing} are missing from the merged render")
    return total if return_partial else total.image()
