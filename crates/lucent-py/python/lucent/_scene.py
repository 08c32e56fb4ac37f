"""Scenes: loaded from files or made from dicts in the scene-file schema,
changed with builder methods, rendered by the library."""

import copy
import json
import math
import os
import warnings
from typing import Any, Callable, Dict, Iterator, List, Optional, Tuple, Union

import numpy as np

from . import _denoise, _image, _keypath, _native
from ._errors import SceneError
from ._progress import Progress, reporter

PathLike = Union[str, "os.PathLike[str]"]

#: The object tables of the scene-file schema that :meth:`Scene.add` appends to.
OBJECT_KINDS = ("sphere", "plane", "triangle", "quad", "disk", "cylinder", "mesh", "group", "instance")
#: The light kinds of :meth:`Scene.add_light` and their tables.
LIGHT_KINDS = {"point": "point_light", "spot": "spot_light", "directional": "directional_light"}
#: Keyword arguments of a render that change the scene's own settings.
_OVERRIDES = (
    "width",
    "height",
    "spp",
    "seed",
    "integrator",
    "sampler",
    "max_depth",
    "aovs",
    "filter_importance",
    "adaptive",
    "default_max_indirect",
)
#: The auxiliary images a render can return.
AOVS = ("albedo", "normal", "position", "depth")
#: The name under which a dict scene's text is given to the loader: it
#: places relative paths in ``base_dir`` and never exists as a file.
_DICT_NAME = "<scene dict>"


def _is_pbrt(path: str) -> bool:
    name = os.path.basename(path).lower()
    return name.endswith(".pbrt") or name.endswith(".pbrt.gz")


def _is_gltf(path: str) -> bool:
    return os.path.splitext(path)[1].lower() in (".gltf", ".glb")


def load(
    path: PathLike,
    strict: bool = False,
    env: Optional[PathLike] = None,
    scene: Optional[int] = None,
    camera: Optional[Union[str, int]] = None,
) -> "Scene":
    """Load a scene file: lucent's TOML or JSON (``.toml``, ``.json``), a
    pbrt-v4 scene (``.pbrt``, ``.pbrt.gz``) or a glTF 2.0 scene
    (``.gltf``, ``.glb``; see ``docs/gltf.md``).

    The scene is built right away, so every error surfaces here as a
    :class:`lucent.SceneError` with the file, line and column (for glTF, the
    JSON path). ``strict`` makes the pbrt-v4 and glTF importers' warnings
    (unsupported features) errors; ``env`` lights a pbrt-v4 scene with this
    environment image instead of the one it names, and a glTF scene (which
    has none) with it. ``scene`` (an index) and ``camera`` (a name or an
    index) choose among a glTF file's scenes and cameras.
    """
    path = os.path.abspath(os.fspath(path))
    env_path = None if env is None else os.path.abspath(os.fspath(env))
    if not (_is_pbrt(path) or _is_gltf(path)) and (strict or env_path is not None):
        raise ValueError("strict and env apply to pbrt-v4 (.pbrt, .pbrt.gz) and glTF (.gltf, .glb) scenes only")
    if not _is_gltf(path) and (scene is not None or camera is not None):
        raise ValueError("scene and camera apply to glTF scenes (.gltf, .glb) only")
    if scene is not None and (isinstance(scene, bool) or not isinstance(scene, int) or scene < 0):
        raise ValueError(f"scene must be an index ≥ 0, got {scene!r}")
    loaded = Scene(
        _path=path,
        _strict=bool(strict),
        _env=env_path,
        _gltf_scene=scene,
        _camera=None if camera is None else str(camera),
    )
    loaded._source()  # build it now: errors belong to load()
    return loaded


class Scene:
    """A scene to render: made by :func:`lucent.load` or
    :meth:`Scene.from_dict`.

    A scene from a TOML or JSON file, or from a dict, is described by a dict
    in the schema of scene files (``docs/scene-format.md``): ``to_dict()``
    returns it, and the builder methods (``set_camera``, ``add_material``,
    ``add``, ``add_light``, ``set_render``, ...) change it. Each change is
    checked by the library's parser at once (unknown keys, wrong types,
    values out of range raise :class:`lucent.SceneError` and leave the
    scene as it was); the whole scene (names of materials, files) is checked
    when it is next built: by ``render``, ``check`` or ``fingerprint``. A
    pbrt-v4 scene renders as it is; to change it, convert it first
    (``lucent convert scene.pbrt -o scene.toml``) and load the result.
    """

    def __init__(
        self,
        *,
        _path: Optional[str] = None,
        _dict: Optional[dict] = None,
        _base_dir: Optional[str] = None,
        _strict: bool = False,
        _env: Optional[str] = None,
        _gltf_scene: Optional[int] = None,
        _camera: Optional[str] = None,
    ) -> None:
        if _path is None and _dict is None:
            raise TypeError("make a Scene with lucent.load(path) or lucent.Scene.from_dict(d)")
        self._path = _path
        self._dict = _dict
        self._base_dir = _base_dir if _base_dir is not None else os.path.dirname(_path or os.path.join(os.getcwd(), "x"))
        self._strict = _strict
        self._env = _env
        self._gltf_scene = _gltf_scene
        self._camera = _camera
        self._text: Optional[Tuple[str, List[str]]] = None
        self._cache: Optional[Tuple[tuple, Any]] = None
        #: The figures of the last render (``spp_added``, ``seconds``,
        #: ``rays``, ``mrays_per_second``, ``nonfinite``), or ``None``.
        self.last_report: Optional[Dict[str, Any]] = None

    # -- making scenes --------------------------------------------------

    @classmethod
    def from_dict(cls, d: dict, base_dir: Optional[PathLike] = None) -> "Scene":
        """A scene from a dict in the schema of scene files: what a TOML or
        JSON scene file parses to (``tomllib.load``/``json.load``), or what
        :meth:`to_dict` returns.

        Relative paths in it (meshes, images) are relative to ``base_dir``
        (default: the current directory). The scene is built right away;
        errors raise :class:`lucent.SceneError` with the key path of the
        offending value in ``error.key`` (e.g. ``"camera.fov"``).
        NumPy numbers and arrays, tuples and paths are accepted as values.
        """
        base = os.path.abspath(os.fspath(base_dir)) if base_dir is not None else os.getcwd()
        scene = cls(_dict=copy.deepcopy(d) if isinstance(d, dict) else d, _base_dir=base)
        scene._source()
        return scene

    # -- what the scene is ---------------------------------------------

    @property
    def path(self) -> Optional[str]:
        """The scene file (absolute), or ``None`` for a scene made from a
        dict or changed by a builder method since it was loaded."""
        return self._path if self._dict is None else None

    @property
    def base_dir(self) -> str:
        """The directory that relative paths in the scene resolve against
        (the scene file's directory, or ``from_dict``'s ``base_dir``)."""
        return self._base_dir

    @property
    def is_pbrt(self) -> bool:
        """Whether the scene is a pbrt-v4 file."""
        return self._dict is None and self._path is not None and _is_pbrt(self._path)

    @property
    def load_options(self) -> Dict[str, Any]:
        """The options it was loaded with: ``{"strict": bool, "env": str or
        None}``, and for a glTF scene ``"scene"`` and ``"camera"`` too."""
        options: Dict[str, Any] = {"strict": self._strict, "env": self._env}
        if self._path is not None and _is_gltf(self._path):
            options.update(scene=self._gltf_scene, camera=self._camera)
        return options

    @property
    def files(self) -> List[str]:
        """Every file the scene was built from, sorted: the scene file (if
        any), included files, meshes, images."""
        return list(self._source().files())

    @property
    def width(self) -> int:
        """Image width the scene asks for, in pixels."""
        return self._source().width

    @property
    def height(self) -> int:
        """Image height the scene asks for, in pixels."""
        return self._source().height

    @property
    def spp(self) -> int:
        """Samples per pixel the scene asks for."""
        return self._source().spp

    @property
    def tone_map(self) -> str:
        """The tone mapping the scene asks for 8-bit images (``"classic"``,
        ``"clamp"``, ``"reinhard"``, ``"aces"``): pass it to
        :func:`lucent.write` or :func:`lucent.show`."""
        return self._source().display()[0]

    @property
    def srgb(self) -> bool:
        """Whether the scene asks for sRGB-encoded 8-bit images."""
        return self._source().display()[1]

    @property
    def warnings(self) -> List[str]:
        """Non-fatal problems found while building the scene (such as
        skipped degenerate triangles, or pbrt-v4 features not implemented)."""
        return list(self._source().warnings())

    def check(self) -> None:
        """Build the scene, raising :class:`lucent.SceneError` if it cannot
        be built (e.g. after builder calls that name a missing material)."""
        self._source()

    def to_dict(self) -> dict:
        """The scene as a dict in the schema of scene files (a copy:
        changing it does not change the scene). For a file, the parsed
        file; ``Scene.from_dict(scene.to_dict(), scene.base_dir)`` renders
        the same image bit for bit. Values are plain JSON types (lists,
        numbers, strings, booleans). Not for pbrt-v4 scenes."""
        if self._dict is None:
            self._refuse_pbrt("to_dict()")
            assert self._path is not None
            try:
                return json.loads(_native.describe(self._path))
            except SceneError as e:
                raise e from None
        # Through its JSON text: plain lists, numbers and strings (NumPy
        # values and tuples given to the builder come back as such).
        return json.loads(self._dict_text()[0])

    def fingerprint(
        self,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        seed: Optional[int] = None,
        *,
        integrator: Optional[str] = None,
        sampler: Optional[str] = None,
        max_depth: Optional[int] = None,
        filter_importance: Optional[bool] = None,
        **render_options: Any,
    ) -> int:
        """The fingerprint (an int) of everything that decides the samples
        of a render with these keyword arguments (those of :meth:`render`;
        ``threads``, ``time`` and ``progress`` do not matter): partial
        renders merge only when their fingerprints agree. It does not depend
        on where the scene's directory lies; nor on ``aovs``, which the
        parts record themselves."""
        unknown = set(render_options) - {"threads", "time", "progress", "aovs"}
        if unknown:
            raise TypeError(f"fingerprint() got unexpected keyword arguments: {', '.join(sorted(unknown))}")
        ov = dict(
            width=width,
            height=height,
            spp=spp,
            seed=seed,
            integrator=integrator,
            sampler=sampler,
            max_depth=max_depth,
            filter_importance=filter_importance,
        )
        return self._source(**ov).fingerprint()

    def __repr__(self) -> str:
        if self.path is not None:
            return f"<lucent.Scene {self.path!r}>"
        return f"<lucent.Scene from a dict, base_dir={self._base_dir!r}>"

    # -- building --------------------------------------------------------

    def _refuse_pbrt(self, what: str) -> None:
        if self.is_pbrt:
            raise SceneError(
                f"{self._path}: {what} is not available for a pbrt-v4 scene; convert it first "
                f"(lucent convert {os.path.basename(self._path or '')} -o scene.toml) and load the result",
                message=f"{what} is not available for a pbrt-v4 scene; convert it first with lucent convert",
                path=self._path,
            )

    def _dict_text(self) -> Tuple[str, List[str]]:
        if self._text is None:
            self._text = _keypath.dump(self._dict)  # type: ignore[arg-type]
        return self._text

    def _source(self, **overrides: Any) -> Any:
        """The built scene for these overrides (the last one is kept)."""
        key = tuple(overrides.get(k) for k in _OVERRIDES)
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        ov = {k: (list(v) if k == "aovs" else v) for k, v in zip(_OVERRIDES, key) if v is not None}
        if self._dict is None:
            assert self._path is not None
            extra: Dict[str, Any] = {}
            if _is_pbrt(self._path) or _is_gltf(self._path):
                extra = {"strict": self._strict, "env": self._env}
            if _is_gltf(self._path):
                extra.update(gltf_scene=self._gltf_scene, camera=self._camera)
            source = _native.Source.open(self._path, **ov, **extra)
        else:
            text, paths = self._dict_text()
            name = os.path.join(self._base_dir, _DICT_NAME)
            try:
                source = _native.Source.from_json(text, name, **ov)
            except SceneError as e:
                raise _keypath.relocate(e, paths, name) from None
        for w in source.warnings():
            warnings.warn(w, stacklevel=3)
        self._cache = (key, source)
        return source

    def _change(self, change: Callable[[dict], None]) -> "Scene":
        """Apply ``change`` to a copy of the scene's dict; keep it if the
        library's parser accepts the result."""
        self._refuse_pbrt("changing the scene")
        d = self.to_dict()
        change(d)
        text, paths = _keypath.dump(d)
        name = os.path.join(self._base_dir, _DICT_NAME)
        try:
            _native.describe(name, text)
        except SceneError as e:
            raise _keypath.relocate(e, paths, name) from None
        self._dict, self._text, self._cache = d, (text, paths), None
        return self

    def set_camera(self, **params: Any) -> "Scene":
        """Set keys of the ``camera`` table, e.g.
        ``set_camera(eye=[0, 1, -5], look_at=[0, 0, 0], fov=50)``; a key set
        to ``None`` is removed (its default applies). Returns the scene."""
        return self._change(lambda d: _merge(d.setdefault("camera", {}), params))

    def set_render(self, **params: Any) -> "Scene":
        """Set keys of the ``render`` table (``width``, ``height``, ``spp``,
        ``integrator``, ``sampler``, ``max_depth``, ``seed``, ``filter``,
        ``tone_map``, ...); ``None`` removes a key. Returns the scene."""
        return self._change(lambda d: _merge(d.setdefault("render", {}), params))

    def set_environment(self, **params: Any) -> "Scene":
        """Set keys of the ``environment`` table (``color``, ``file``, ...);
        with no arguments, remove the environment. Returns the scene."""
        return self._change(lambda d: _merge(d.setdefault("environment", {}), params) if params else d.pop("environment", None))

    def set_ambient(self, **params: Any) -> "Scene":
        """Set keys of the ``ambient`` table (``color``, ``intensity``);
        with no arguments, remove the ambient light. Returns the scene."""
        return self._change(lambda d: _merge(d.setdefault("ambient", {}), params) if params else d.pop("ambient", None))

    def add_material(self, name: str, kind: str, **params: Any) -> "Scene":
        """Define (or replace) the material ``name`` of kind ``kind``
        (``"matte"``, ``"phong"``, ``"diffuse"``, ``"conductor"``,
        ``"dielectric"``, ``"plastic"``, ...) with its parameters, as
        ``[materials.NAME.KIND]`` in a scene file. Returns the scene."""
        return self._change(lambda d: d.setdefault("materials", {}).__setitem__(name, {kind: params}))

    def add_medium(self, name: str, kind: str = "homogeneous", **params: Any) -> "Scene":
        """Define (or replace) the participating medium ``name`` of kind
        ``kind`` (``"homogeneous"``) with its keys (``sigma_a``,
        ``sigma_s``, ``scale``, ``g``, ``emission``, ``preset``), as
        ``[media.NAME.KIND]`` in a scene file. Objects name it with
        ``medium_inside``/``medium_outside``, the camera with ``medium``.
        Returns the scene."""
        return self._change(lambda d: d.setdefault("media", {}).__setitem__(name, {kind: params}))

    def add_texture(self, name: str, kind: str, **params: Any) -> "Scene":
        """Define (or replace) the texture ``name`` of kind ``kind``, as
        ``[textures.NAME.KIND]`` in a scene file. Returns the scene."""
        return self._change(lambda d: d.setdefault("textures", {}).__setitem__(name, {kind: params}))

    def add_mesh_file(self, name: str, file: PathLike, **params: Any) -> "Scene":
        """Name a mesh file (``.ply``, ``.obj``; relative to ``base_dir``)
        to place with ``add("mesh", mesh=name, ...)``, as ``[meshes.NAME]``.
        Returns the scene."""
        return self._change(lambda d: d.setdefault("meshes", {}).__setitem__(name, {"file": os.fspath(file), **params}))

    def add(self, kind: str, **params: Any) -> int:
        """Add an object: ``kind`` is one of ``sphere``, ``plane``,
        ``triangle``, ``quad``, ``disk``, ``cylinder``, ``mesh``, ``group``,
        ``instance`` and ``params`` its keys as in a ``[[KIND]]`` table, e.g.
        ``add("sphere", center=[0, 1, 0], radius=1, material="red")``.
        Returns its index in that table (for :meth:`update` and
        :meth:`remove`)."""
        if kind not in OBJECT_KINDS:
            raise ValueError(f"unknown object kind {kind!r} (accepted: {', '.join(OBJECT_KINDS)})")
        self._change(lambda d: d.setdefault(kind, []).append(params))
        return len(self._dict[kind]) - 1  # type: ignore[index]

    def add_light(self, kind: str, **params: Any) -> int:
        """Add a light: ``kind`` is ``"point"``, ``"spot"`` or
        ``"directional"`` (or the table name, ``"point_light"``, ...), e.g.
        ``add_light("point", position=[5, 5, -5], intensity=2)``. Returns its
        index in its table. Area lights are objects with ``emission``."""
        table = LIGHT_KINDS.get(kind, kind)
        if table not in LIGHT_KINDS.values():
            raise ValueError(f"unknown light kind {kind!r} (accepted: {', '.join(LIGHT_KINDS)})")
        self._change(lambda d: d.setdefault(table, []).append(params))
        return len(self._dict[table]) - 1  # type: ignore[index]

    def update(self, table: str, index: int, **params: Any) -> "Scene":
        """Change keys of the ``index``-th entry of an object or light table
        (e.g. ``update("sphere", 0, radius=2)``); ``None`` removes a key.
        Returns the scene."""
        table = LIGHT_KINDS.get(table, table)

        def change(d: dict) -> None:
            _entry(d, table, index)
            _merge(d[table][index], params)

        return self._change(change)

    def remove(self, table: str, index: int) -> "Scene":
        """Remove the ``index``-th entry of an object or light table (later
        entries move down by one). Returns the scene."""
        table = LIGHT_KINDS.get(table, table)

        def change(d: dict) -> None:
            _entry(d, table, index)
            del d[table][index]
            if not d[table]:
                del d[table]

        return self._change(change)

    # -- rendering -------------------------------------------------------

    def render(
        self,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        threads: Optional[int] = None,
        seed: Optional[int] = None,
        time: Optional[float] = None,
        progress: Progress = True,
        *,
        integrator: Optional[str] = None,
        sampler: Optional[str] = None,
        max_depth: Optional[int] = None,
        aovs: Optional[List[str]] = None,
        denoise: bool = False,
        denoise_quality: str = "default",
        denoise_aux: str = "prefilter",
        adaptive: Optional[float] = None,
        filter_importance: Optional[bool] = None,
    ) -> Any:
        """Render the scene; returns a ``(height, width, 3)`` float32 array
        of linear radiance: the values ``lucent render -o image.exr``
        writes, bit for bit, for the same scene and arguments.

        With ``aovs`` (a list of ``"albedo"``, ``"normal"``, ``"position"``,
        ``"depth"``; ``[]`` for none, ``None`` for the scene's ``aov``
        list) it returns a dict instead: ``"color"`` and each auxiliary
        image, ``(height, width, 3)`` arrays and ``(height, width)`` for
        depth (see ``docs/denoising.md`` for what each holds).

        ``denoise=True`` denoises the image with Intel Open Image Denoise
        (see :func:`lucent.denoise`; ``denoise_quality`` and
        ``denoise_aux`` are its ``quality`` and ``aux``), guided by albedo
        and normal images rendered for it, with every sample placed in one
        pixel (filter importance sampling) and indirect light clamped at 10
        unless the scene sets ``max_indirect``, as ``lucent render
        --denoise``; the dict then holds the ``"noisy"`` colour too.

        ``filter_importance=True`` places each sample in one pixel (as
        ``--filter-importance``; ``denoise`` does it always).

        ``adaptive`` is a threshold of adaptive sampling (as ``--adaptive``:
        pixels stop once their estimated error is below it; ``spp`` is then
        the most a pixel takes); the samples each pixel took are then in
        ``last_report["sample_counts"]``, a ``(height, width)`` array.

        What is left out comes from the scene. ``spp`` is samples per pixel;
        ``time`` a time budget in seconds (as ``--time``: without ``spp``
        the budget alone decides); ``threads`` the worker count (default:
        every core; the image does not depend on it); ``seed`` the sampler's
        seed; ``integrator`` (``"whitted"``, ``"path"``, ``"bdpt"``), ``sampler``
        (``"stratified"``, ``"sobol"``, ``"independent"``) and ``max_depth``
        as on the command line. ``progress``: ``True`` for a progress bar
        (tqdm if installed, else text on stderr), ``False`` for none, or a
        callable given the fraction done (0 to 1, increasing, last 1.0).

        The GIL is released while rendering; Ctrl-C stops the render and
        raises ``KeyboardInterrupt``. The figures of the render are kept in
        :attr:`last_report`.
        """
        _check_aovs(aovs)
        if denoise_aux not in _denoise.AUX_MODES + ("none",):
            raise ValueError(f"unknown denoise_aux {denoise_aux!r} (accepted: prefilter, clean, noisy, none)")
        asked = aovs
        render_aovs = aovs
        if denoise:
            if denoise_aux != "none":
                # The guides, with the layers asked for (without a list only
                # the denoised image is returned, so the scene's own list
                # does not matter).
                render_aovs = sorted(set(aovs or []) | {"albedo", "normal"}, key=AOVS.index)
        ov = dict(
            width=width,
            height=height,
            spp=spp,
            seed=seed,
            integrator=integrator,
            sampler=sampler,
            max_depth=max_depth,
            aovs=None if render_aovs is None else tuple(render_aovs),
            filter_importance=True if denoise else filter_importance,
            adaptive=adaptive,
            # A denoiser turns fireflies into blotches: indirect light is
            # clamped at 10 unless the scene sets a clamp (as --denoise).
            default_max_indirect=10.0 if denoise else None,
        )
        source = self._source(**ov)
        acc = source.accumulation()
        # With a time budget and no sample count, the budget alone decides
        # (as `lucent render --time`).
        target = _native.MAX_SPP if time is not None and spp is None else None
        with reporter(progress) as callback:
            report = source.render_into(acc, spp=target, threads=threads, time=time, progress=callback)
        counts = acc.sample_counts()
        if counts is not None:
            report["sample_counts"] = np.array(counts, dtype=np.uint32).reshape(acc.height, acc.width)
        self._finish(report)
        image = _image.from_bytes(acc.image(), acc.width, acc.height)
        layers = _denoise.layers(acc.aov_images(), acc.width, acc.height)
        if denoise:
            from ._denoise import denoise as run_denoise

            guide = denoise_aux if denoise_aux != "none" else "noisy"
            albedo = layers.get("albedo") if denoise_aux != "none" else None
            normal = layers.get("normal") if denoise_aux != "none" else None
            clean = run_denoise(image, albedo, normal, quality=denoise_quality, aux=guide, threads=threads)
            if asked is None:
                return clean
            out = {"color": clean, "noisy": image}
            out.update({k: v for k, v in layers.items() if k in asked})
            return out
        if asked is None and not layers:
            return image
        out = {"color": image}
        out.update(layers)
        return out

    def render_progressive(
        self,
        passes: int = 8,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        threads: Optional[int] = None,
        seed: Optional[int] = None,
        progress: Progress = False,
        *,
        integrator: Optional[str] = None,
        sampler: Optional[str] = None,
        max_depth: Optional[int] = None,
    ) -> Iterator[np.ndarray]:
        """Render in ``passes`` steps, yielding the image after each: a
        generator of ``(height, width, 3)`` float32 arrays with more and
        more samples per pixel. The last is the image :meth:`render`
        returns for the same arguments, bit for bit. Arguments as for
        :meth:`render`; ``progress`` covers all the passes."""
        if passes < 1:
            raise ValueError("passes must be at least 1")
        ov = dict(width=width, height=height, spp=spp, seed=seed, integrator=integrator, sampler=sampler, max_depth=max_depth)
        source = self._source(**ov)
        acc = source.accumulation()
        total = source.spp
        targets = sorted({max(1, math.ceil(total * k / passes)) for k in range(1, passes + 1)})
        with reporter(progress) as callback:
            for i, target in enumerate(targets):
                step = None
                if callback is not None:
                    step = (lambda f, i=i: callback((i + f) / len(targets)))
                report = source.render_into(acc, spp=target, threads=threads, progress=step)
                self._finish(report)
                yield _image.from_bytes(acc.image(), acc.width, acc.height)

    def _finish(self, report: Dict[str, Any]) -> None:
        self.last_report = report
        if report["nonfinite"]:
            warnings.warn(f"{report['nonfinite']} samples had NaN or infinite radiance and were discarded", stacklevel=3)

    def render_partial(
        self,
        start: int,
        end: int,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        threads: Optional[int] = None,
        seed: Optional[int] = None,
        time: Optional[float] = None,
        progress: Progress = True,
        *,
        integrator: Optional[str] = None,
        sampler: Optional[str] = None,
        max_depth: Optional[int] = None,
        aovs: Optional[List[str]] = None,
        filter_importance: Optional[bool] = None,
    ) -> "Partial":
        """Render only the samples ``start`` to ``end - 1`` of every pixel;
        returns a :class:`lucent.Partial` to add to the others (``p1 + p2``
        or ``sum(parts)``). Partials covering ``0 .. spp`` add up to
        :meth:`render`'s image bit for bit. Keyword arguments as for
        :meth:`render` (``spp`` is the full render's count, which the
        stratified sampler's sample layout depends on). With ``time``, the
        part may end early: its range is then ``start`` up to the last
        sample finished. ``aovs`` adds auxiliary images to the part
        (:meth:`Partial.aovs`), which merge exactly as the colour does;
        ``filter_importance=True`` places each sample in one pixel, as
        ``render(denoise=True)`` does (for parts to be denoised)."""
        _check_aovs(aovs)
        ov = dict(
            width=width,
            height=height,
            spp=spp,
            seed=seed,
            integrator=integrator,
            sampler=sampler,
            max_depth=max_depth,
            aovs=None if aovs is None else tuple(aovs),
            filter_importance=filter_importance,
        )
        source = self._source(**ov)
        with reporter(progress, "partial") as callback:
            native, report = source.render_partial(int(start), int(end), threads=threads, time=time, progress=callback)
        self._finish(report)
        from ._partial import Partial

        return Partial(native)


def _check_aovs(aovs: Any) -> None:
    if aovs is not None and (isinstance(aovs, str) or any(a not in AOVS for a in aovs)):
        raise ValueError(f"aovs must be a list of {', '.join(AOVS)}; got {aovs!r}")


def _merge(table: dict, params: Dict[str, Any]) -> None:
    for key, value in params.items():
        if value is None:
            table.pop(key, None)
        else:
            table[key] = value


def _entry(d: dict, table: str, index: int) -> None:
    entries = d.get(table)
    if not isinstance(entries, list) or not -len(entries) <= index < len(entries):
        count = len(entries) if isinstance(entries, list) else 0
        raise IndexError(f"the scene has {count} {table} entr{'y' if count == 1 else 'ies'}; there is no [{index}]")
