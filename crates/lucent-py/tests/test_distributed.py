"""Distributed renders on Dask (lucent.distributed, lucent-dask): bit-identical
to local renders, with scene files shipped in an archive, on separate
scheduler and worker processes, and through a worker killed mid-render.

Skipped when Dask is not installed. Images are tiny (32x24, 8 spp) so the
whole file stays well under a minute on 2 cores.
"""

import hashlib
import io
import json
import os
import re
import signal
import socket
import subprocess
import sys
import tarfile
import textwrap

import numpy as np
import pytest

pytest.importorskip("dask.distributed", reason="Dask is not installed (pip install 'lucent[distributed]')")

import lucent  # noqa: E402
from dask.distributed import Client, LocalCluster  # noqa: E402
from lucent import _archive  # noqa: E402
from lucent import distributed as ld  # noqa: E402

SIZE = dict(width=32, height=24, spp=8)

SCENE = """
[camera]
eye = [0, 1.2, -5]
look_at = [0, 0.6, 0]
fov = 50

[render]
integrator = "path"
sampler = "sobol"
width = 32
height = 24
spp = 8
max_depth = 5

[environment]
color = [0.3, 0.35, 0.4]

[materials.red.diffuse]
color = [0.8, 0.2, 0.1]

[materials.grey.diffuse]
color = [0.5, 0.5, 0.5]

[[sphere]]
center = [0, 1, 0]
radius = 1
material = "red"

[[plane]]
point = [0, 0, 0]
normal = [0, 1, 0]
material = "grey"

[[point_light]]
position = [3, 5, -4]
intensity = 30
falloff = "inverse_square"
"""

# A scene that reads two files beside it, by relative paths: a PLY mesh and
# a PNG texture.
TEXTURED_SCENE = """
[camera]
eye = [0, 1.5, -4]
look_at = [0, 0.5, 0]
fov = 55

[render]
integrator = "path"
sampler = "sobol"
width = 32
height = 24
spp = 8
max_depth = 4

[environment]
color = [0.6, 0.6, 0.6]

[textures.stripes.image]
file = "../assets/stripes.png"

[materials.floor.coated_diffuse]
reflectance = "stripes"

[materials.blue.diffuse]
color = [0.1, 0.3, 0.8]

[[mesh]]
file = "../assets/tent.ply"
material = "blue"

[[plane]]
point = [0, 0, 0]
normal = [0, 1, 0]
material = "floor"
"""

TENT_PLY = """ply
format ascii 1.0
element vertex 5
property float x
property float y
property float z
element face 4
property list uchar int vertex_indices
end_header
-1 0 -1
1 0 -1
1 0 1
-1 0 1
0 1.5 0
0 1 4
1 2 4
2 3 4
3 0 4
"""


def identical(a, b):
    """Bit for bit (NaNs and signed zeros included)."""
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def write_scene(directory, text=SCENE, name="scene.toml"):
    path = directory / name
    path.write_text(textwrap.dedent(text))
    return path


def make_textured_project(root):
    """root/scenes/textured.toml reading root/assets/{tent.ply,stripes.png}."""
    (root / "scenes").mkdir(parents=True)
    (root / "assets").mkdir()
    (root / "assets" / "tent.ply").write_text(TENT_PLY)
    stripes = np.zeros((8, 8, 3), np.float32)
    stripes[:, ::2] = [0.9, 0.7, 0.2]
    stripes[:, 1::2] = [0.1, 0.5, 0.3]
    lucent.write(root / "assets" / "stripes.png", stripes, tone_map="clamp")
    return write_scene(root / "scenes", TEXTURED_SCENE, "textured.toml")


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    """Two worker processes of one thread each, started in a directory of
    their own (not where any scene is)."""
    elsewhere = tmp_path_factory.mktemp("worker-cwd")
    # dashboard_address=":0": a scheduler always serves HTTP (metrics, even
    # with the dashboard off), on 8787 unless told otherwise, and two
    # clusters at once would clash there.
    here = os.getcwd()
    os.chdir(elsewhere)
    try:
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    finally:
        os.chdir(here)
    with cluster, Client(cluster) as c:
        c.wait_for_workers(2)
        yield c


def test_import_lucent_does_not_import_dask():
    code = "import sys, lucent; print(sorted(m for m in sys.modules if m.split('.')[0] in ('dask', 'distributed')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_missing_dask_names_the_extra():
    code = (
        "import sys; sys.modules['dask'] = None; sys.modules['dask.distributed'] = None\n"
        "try:\n    import lucent.distributed\nexcept ImportError as e:\n    print(e)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert "pip install 'lucent[distributed]'" in out


def test_sample_ranges_and_default_chunk():
    assert ld.sample_ranges(0, 8, 3) == [(0, 3), (3, 6), (6, 8)]
    assert ld.sample_ranges(4, 8, 2) == [(4, 6), (6, 8)]
    assert ld.default_chunk(64, 2) == 8  # 4 chunks per worker thread
    assert ld.default_chunk(64, 32) == 1
    assert ld.default_chunk(1, 1) == 1
    with pytest.raises(ValueError, match="chunk must be at least 1"):
        ld.sample_ranges(0, 8, 0)


def test_prepare_refuses_what_a_job_cannot_carry(tmp_path):
    scene = lucent.load(write_scene(tmp_path))
    with pytest.raises(TypeError, match="unexpected keyword arguments for a distributed render: threads"):
        ld.prepare(scene, threads=4)
    job = ld.prepare(scene, spp=4, max_depth=2)
    assert job.render_kwargs == {"spp": 4, "max_depth": 2}
    assert job.fingerprint == scene.fingerprint(spp=4, max_depth=2) != scene.fingerprint(spp=4)


def test_render_is_bit_identical_to_local(client, tmp_path):
    scene = lucent.load(write_scene(tmp_path))
    reference = scene.render(progress=False, **SIZE)
    fractions = []
    image = ld.render(scene, client, chunk=2, progress=fractions.append, cache_dir=str(tmp_path / "cache"), **SIZE)
    assert image.dtype == np.float32 and image.shape == (24, 32, 3)
    assert identical(image, reference)
    assert fractions == [0.25, 0.5, 0.75, 1.0]  # 4 chunks of 2 samples

    part = ld.render(
        scene, client, chunk=3, progress=False, return_partial=True, cache_dir=str(tmp_path / "cache"), **SIZE
    )
    assert isinstance(part, lucent.Partial)
    assert (part.spp, part.missing) == (8, [])
    assert part.fingerprint == scene.fingerprint(**SIZE)
    assert identical(part.image(), reference)

    # A range: samples [2, 6) are those of the local partial render, bit for bit.
    some = ld.render_partial(scene, client, 2, 6, chunk=1, progress=False, **SIZE)
    assert some.ranges == [range(2, 6)]
    assert identical(some.image(), scene.render_partial(2, 6, progress=False, **SIZE).image())


def test_aovs_travel_through_a_distributed_render(client, tmp_path):
    scene = lucent.load(write_scene(tmp_path))
    local = scene.render(progress=False, aovs=["albedo", "depth"], **SIZE)
    part = ld.render(
        scene, client, chunk=3, progress=False, return_partial=True, aovs=["albedo", "depth"],
        cache_dir=str(tmp_path / "cache"), **SIZE,
    )
    layers = part.aovs()
    assert identical(part.image(), local["color"])
    assert layers["albedo"].tobytes() == local["albedo"].tobytes()
    assert layers["depth"].tobytes() == local["depth"].tobytes()


def test_dict_scene_is_bit_identical(client, tmp_path):
    d = lucent.load(write_scene(tmp_path)).to_dict()
    scene = lucent.Scene.from_dict(d, base_dir=tmp_path)
    reference = scene.render(progress=False, **SIZE)
    job = ld.prepare(scene, **SIZE)
    assert job.archive.members == (_archive.DICT_SCENE_NAME,)
    assert identical(ld.render(job, client, chunk=2, progress=False, cache_dir=str(tmp_path / "cache")), reference)


def test_scene_files_travel_in_the_archive(client, tmp_path):
    project = tmp_path / "project"
    scene = lucent.load(make_textured_project(project))
    reference = scene.render(progress=False, **SIZE)
    job = ld.prepare(scene, **SIZE)
    assert job.archive.members == ("assets/stripes.png", "assets/tent.ply", "scenes/textured.toml")
    assert job.archive.scene == "scenes/textured.toml"
    assert job.archive.sha256 == hashlib.sha256(job.archive.data).hexdigest()
    assert ld.prepare(scene, **SIZE).archive.data == job.archive.data  # deterministic

    # Only the archive can provide the files now.
    project.rename(tmp_path / "moved-away")
    cache = tmp_path / "cache"
    image = ld.render(job, client, chunk=2, progress=False, cache_dir=str(cache))
    assert identical(image, reference)
    # Unpacked once, into the directory named by the hash, nothing left over.
    assert os.listdir(cache) == [job.archive.sha256]
    unpacked = cache / job.archive.sha256 / "files"
    assert (unpacked / "assets" / "tent.ply").read_text() == TENT_PLY

    # A job whose settings differ from the parts' fails clearly.
    other = ld.RenderJob(job.archive, job.spp, job.fingerprint ^ 1, job.render_kwargs)
    with pytest.raises(ld.DistributedRenderError, match="loaded a different scene from the archive"):
        ld.render(other, client, chunk=4, progress=False, cache_dir=str(cache))


PBRT_MAIN = """LookAt 0 1 -5  0 0.5 0  0 1 0
Camera "perspective" "float fov" 50
Sampler "sobol" "integer pixelsamples" 8
Integrator "volpath" "integer maxdepth" 5
Film "rgb" "integer xresolution" 32 "integer yresolution" 24 "string filename" "x.exr"
WorldBegin
LightSource "infinite" "string filename" "not-shipped.exr"
Include "geometry.pbrt"
"""

PBRT_GEOMETRY = """Material "diffuse" "rgb reflectance" [0.8 0.2 0.1]
Shape "sphere" "float radius" 1
"""


def test_pbrt_scene_with_include_and_env_override(client, tmp_path):
    project = tmp_path / "project"
    (project / "scene").mkdir(parents=True)
    (project / "env").mkdir()
    (project / "scene" / "main.pbrt").write_text(PBRT_MAIN)
    (project / "scene" / "geometry.pbrt").write_text(PBRT_GEOMETRY)
    sky = np.zeros((16, 32, 3), np.float32)
    sky[:8], sky[8:] = [0.5, 0.6, 0.9], [0.2, 0.15, 0.1]
    lucent.write(project / "env" / "sky.exr", sky)
    scene = lucent.load(project / "scene" / "main.pbrt", strict=True, env=project / "env" / "sky.exr")
    reference = scene.render(progress=False)
    job = ld.prepare(scene)
    assert job.archive.members == ("env/sky.exr", "scene/geometry.pbrt", "scene/main.pbrt")
    assert job.archive.load_options == {"strict": True, "env": "env/sky.exr"}
    assert job.spp == 8

    project.rename(tmp_path / "moved-away")
    image = ld.render(job, client, chunk=2, progress=False, cache_dir=str(tmp_path / "cache"))
    assert identical(image, reference) and reference.mean() > 0.1


def _tar(members):
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w") as tar:
        for name, data in members:
            info = tarfile.TarInfo(name)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    data = buffer.getvalue()
    return data, hashlib.sha256(data).hexdigest()


@pytest.mark.parametrize(
    "name, message",
    [
        ("files/../../evil.txt", "leaves the archive ('..'): 'files/../../evil.txt'"),
        ("/tmp/evil.txt", "has an absolute path: '/tmp/evil.txt'"),
        ("files\\..\\evil.txt", "unsafe member name"),
    ],
)
def test_archive_refuses_unsafe_members(tmp_path, name, message):
    manifest = json.dumps({"format": 1, "scene": "s.toml", "files": {}}).encode()
    data, sha = _tar([("manifest.json", manifest), (name, b"x")])
    cache = tmp_path / "cache"
    with pytest.raises(_archive.ArchiveError) as e:
        _archive.unpack(data, sha, str(cache))
    assert message in str(e.value)
    assert os.listdir(cache) == []  # the temporary directory is gone too
    assert not (tmp_path / "evil.txt").exists()


def test_archive_unpacks_once_when_raced(tmp_path):
    from concurrent.futures import ThreadPoolExecutor

    scene = lucent.load(make_textured_project(tmp_path / "project"))
    archive = _archive.build(scene)
    cache = tmp_path / "cache"
    with ThreadPoolExecutor(8) as pool:
        results = list(pool.map(lambda _: _archive.unpack(archive.data, archive.sha256, str(cache)), range(16)))
    assert {files for files, _ in results} == {str(cache / archive.sha256 / "files")}
    assert os.listdir(cache) == [archive.sha256]  # every loser's temporary copy removed
    assert (cache / archive.sha256 / "files" / "assets" / "stripes.png").read_bytes() == (
        tmp_path / "project" / "assets" / "stripes.png"
    ).read_bytes()


def test_archive_refuses_damaged_bytes(tmp_path):
    scene = lucent.load(write_scene(tmp_path))
    archive = _archive.build(scene)
    with pytest.raises(_archive.ArchiveError, match="arrived damaged"):
        _archive.unpack(archive.data[:-1] + b"?", archive.sha256, str(tmp_path / "cache"))


def _start(args, **kwargs):
    return subprocess.Popen(
        args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True, **kwargs
    )


def _stop(processes):
    for p in processes:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGTERM)
    for p in processes:
        try:
            p.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()


def _lucent_dask():
    """The installed `lucent-dask` program (the entry point of pyproject.toml)."""
    script = os.path.join(os.path.dirname(sys.executable), "lucent-dask")
    return [script] if os.path.exists(script) else [sys.executable, "-m", "lucent._dask_cli"]


def test_cli_on_separate_scheduler_and_worker_processes(tmp_path):
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    workdir = tmp_path / "workers"
    workdir.mkdir()
    env = dict(os.environ, LUCENT_DASK_CACHE=str(tmp_path / "cache"))
    dask = [sys.executable, "-m", "dask"]
    processes = [_start(dask + ["scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"])]
    try:
        for _ in range(2):
            processes.append(
                _start(dask + ["worker", address, "--nthreads", "1", "--no-dashboard"], cwd=workdir, env=env)
            )
        with Client(address, timeout=30) as c:
            c.wait_for_workers(2, timeout=30)
        project = tmp_path / "project"
        scene_path = make_textured_project(project)
        out = tmp_path / "out.exr"
        run = subprocess.run(
            _lucent_dask() + ["render", str(scene_path), "--scheduler", address, "-o", str(out), "--chunk", "2"],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert run.returncode == 0, run.stderr
        assert run.stdout == ""
        summary = rf"{re.escape(str(out))}: 32x24, 8 spp in \d+\.\d\d s on 2 workers \(2 threads\)\n"
        assert re.fullmatch(summary, run.stderr), run.stderr
        reference = lucent.load(scene_path).render(progress=False)
        assert identical(lucent.read(out), reference)

        # An .lpart keeps the merged partial render; other settings apply.
        lpart = tmp_path / "out.lpart"
        run = subprocess.run(
            _lucent_dask()
            + ["render", str(scene_path), "--scheduler", address, "-o", str(lpart), "--spp", "4", "--seed", "3"]
            + ["--width", "16", "--height", "12", "--quiet"],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert (run.returncode, run.stderr) == (0, "")
        part = lucent.load_partial(lpart)
        local = lucent.load(scene_path).render_partial(0, 4, width=16, height=12, spp=4, seed=3, progress=False)
        assert part == local
    finally:
        _stop(processes)


def test_entry_point_is_declared():
    tomllib = pytest.importorskip("tomllib")
    root = os.path.join(os.path.dirname(__file__), "..", "..", "..", "pyproject.toml")
    with open(root, "rb") as f:
        project = tomllib.load(f)["project"]
    assert project["scripts"]["lucent-dask"] == "lucent._dask_cli:main"
    assert any(d.startswith("dask[distributed]") for d in project["optional-dependencies"]["distributed"])


def test_a_worker_killed_mid_render_changes_nothing(tmp_path):
    scene = lucent.load(write_scene(tmp_path))
    size = dict(width=128, height=96, spp=96)  # 48 chunks of 2: seconds on 2 workers
    reference = scene.render(progress=False, **size)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        with Client(cluster) as c:
            c.wait_for_workers(2)
            pids = c.run(os.getpid)
            killed = []

            def kill_one(fraction):
                # Early in the render, kill a worker that is rendering a chunk.
                # Read the in-flight keys before the kill: once the scheduler notices the
                # dead worker it drops the address from `processing()`.
                processing = c.processing() if not killed else {}
                busy = sorted(address for address, keys in processing.items() if keys and address in pids)
                if busy:
                    victim = busy[0]
                    os.kill(pids[victim], signal.SIGKILL)
                    killed.append((pids[victim], fraction, processing[victim]))

            image = ld.render(scene, c, chunk=2, progress=kill_one, cache_dir=str(tmp_path / "cache"), **size)
            victim, fraction, in_flight = killed[0]
            assert fraction < 0.5 and any(str(k).startswith("lucent-chunk-") for k in in_flight)
            assert identical(image, reference)
            # The nanny started a new worker process in place of the dead one.
            c.wait_for_workers(2, timeout=30)
            assert victim not in c.run(os.getpid).values()


def test_cli_errors_are_one_line(tmp_path):
    scene = write_scene(tmp_path)
    address = f"tcp://127.0.0.1:{free_port()}"
    cli = _lucent_dask() + ["render"]

    run = subprocess.run(
        cli + [str(scene), "--scheduler", address, "-o", str(tmp_path / "o.exr"), "--timeout", "1"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode == 1
    assert run.stderr.startswith(f"lucent-dask: error: cannot reach the Dask scheduler at {address} within 1 s")
    assert run.stderr.count("\n") == 1 and "Traceback" not in run.stderr
    assert not (tmp_path / "o.exr").exists()

    missing = tmp_path / "missing.toml"
    run = subprocess.run(
        cli + [str(missing), "--scheduler", address, "-o", str(tmp_path / "o.exr")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode == 1
    assert run.stderr.startswith("lucent-dask: error: ") and str(missing) in run.stderr
    assert run.stderr.count("\n") == 1 and "Traceback" not in run.stderr

    run = subprocess.run(cli + [str(scene), "-o", "x.exr"], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2
    assert "the following arguments are required: --scheduler" in run.stderr
