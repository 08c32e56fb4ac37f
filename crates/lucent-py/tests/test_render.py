"""Renders from Python are the command line's, bit for bit; the GIL is
released while rendering; progress is reported."""

import json
import sys
import threading
import time

import numpy as np
import pytest

import lucent
from conftest import SCENES, run_cli


@pytest.mark.parametrize(
    "scene, args",
    [
        ("showcase.toml", dict(width=40, height=30, spp=4, seed=3)),
        ("showcase.json", dict(width=32, height=24, spp=2)),
        ("cornell-box.toml", dict(width=24, height=24, spp=4, seed=1)),
        ("glass-and-metal.toml", dict(width=32, height=20, spp=2)),
        # Bidirectional path tracing, light-tracing splats included.
        ("caustic.toml", dict(width=24, height=18, spp=2, seed=5)),
    ],
)
def test_render_is_the_cli_exr_bit_for_bit(tmp_path, scene, args):
    exr = tmp_path / "cli.exr"
    flags = [f"--{k}={v}" for k, v in args.items()]
    run_cli("render", str(SCENES / scene), "-o", str(exr), "--quiet", *flags)
    expected = lucent.read(exr)

    image = lucent.load(SCENES / scene).render(**args, progress=False)
    assert image.dtype == np.float32
    assert image.shape == (args["height"], args["width"], 3)
    assert image.tobytes() == expected.tobytes()


def test_render_uses_the_scenes_own_settings_when_left_out(tiny):
    scene = lucent.Scene.from_dict(tiny)
    image = scene.render(progress=False)
    assert image.shape == (24, 32, 3)
    assert scene.last_report["spp_added"] == 4
    # Explicit values equal to the scene's give the same image.
    again = scene.render(width=32, height=24, spp=4, seed=0, progress=False)
    assert again.tobytes() == image.tobytes()


def test_thread_count_and_seed(tiny):
    scene = lucent.Scene.from_dict(tiny)
    one = scene.render(threads=1, progress=False)
    two = scene.render(threads=2, progress=False)
    assert one.tobytes() == two.tobytes()
    other_seed = scene.render(seed=7, progress=False)
    assert other_seed.tobytes() != one.tobytes()


def test_render_overrides_the_integrator_like_the_cli(tmp_path):
    exr = tmp_path / "cli.exr"
    run_cli("render", str(SCENES / "showcase.toml"), "-o", str(exr), "--quiet",
            "--width=24", "--height=16", "--spp=2", "--integrator=path", "--sampler=independent", "--max-depth=3")
    image = lucent.load(SCENES / "showcase.toml").render(
        width=24, height=16, spp=2, integrator="path", sampler="independent", max_depth=3, progress=False)
    assert image.tobytes() == lucent.read(exr).tobytes()


def test_bad_render_arguments_are_value_errors(tiny):
    scene = lucent.Scene.from_dict(tiny)
    with pytest.raises(ValueError, match="unknown integrator 'bidir' \\(accepted: whitted, path, bdpt\\)"):
        scene.render(integrator="bidir", progress=False)
    with pytest.raises(ValueError, match="spp must be at least 1"):
        scene.render(spp=0, progress=False)
    with pytest.raises(ValueError, match="threads must be at least 1"):
        scene.render(threads=0, progress=False)
    with pytest.raises(ValueError, match="time must be a positive number of seconds"):
        scene.render(time=-1, progress=False)
    with pytest.raises(OverflowError):
        scene.render(width=-5, progress=False)


def test_progress_callback_gets_increasing_fractions_ending_at_one():
    scene = lucent.load(SCENES / "cornell-box.toml")
    # The waiting thread wakes every 50 ms and reports the fraction when it
    # grew: a render of half a second or more reports several times. How many
    # samples take that long depends on the machine (and on how fast lucent
    # is), so the render grows until it lasts long enough.
    for spp in (24, 96, 384, 1536):
        seen = []
        started = time.monotonic()
        scene.render(width=64, height=64, spp=spp, threads=1, progress=seen.append)
        if time.monotonic() - started >= 0.5:
            break
    assert len(seen) >= 3, seen
    assert seen[-1] == 1.0
    assert all(0 < a < b for a, b in zip(seen, seen[1:])), seen


def test_progress_true_draws_a_bar_and_false_is_silent(tiny, capsys, monkeypatch):
    scene = lucent.Scene.from_dict(tiny)
    scene.render(progress=False)
    assert capsys.readouterr().err == ""
    pytest.importorskip("tqdm")
    scene.render(progress=True)
    assert "render:   0%|" in capsys.readouterr().err  # tqdm's bar, cleared at the end
    # Without tqdm, a bar of text on stderr.
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    scene.render(progress=True)
    err = capsys.readouterr().err
    assert err.startswith("\rrender [") and "] 100%" in err and err.endswith("\n"), repr(err)
    with pytest.raises(TypeError, match="progress must be True, False or a callable"):
        scene.render(progress="yes")


def test_an_exception_in_the_progress_callback_stops_the_render():
    scene = lucent.load(SCENES / "cornell-box.toml")

    def fail(fraction):
        raise RuntimeError(f"stop at {fraction}")

    started = time.monotonic()
    with pytest.raises(RuntimeError, match="stop at"):
        scene.render(width=256, height=256, spp=256, threads=1, progress=fail)
    # Stopped after the rows under way, not after the whole render (minutes).
    assert time.monotonic() - started < 10


def test_the_gil_is_released_while_rendering():
    scene = lucent.load(SCENES / "cornell-box.toml")
    result = {}

    def work():
        result["image"] = scene.render(width=64, height=64, spp=24, threads=1, progress=False)

    worker = threading.Thread(target=work)
    count = 0
    worker.start()
    while worker.is_alive():
        count += 1  # runs only while the render does not hold the GIL
    worker.join()
    assert result["image"].shape == (64, 64, 3)
    assert count > 10_000, count


def test_time_budget_renders_whole_passes():
    scene = lucent.load(SCENES / "showcase.toml")
    started = time.monotonic()
    image = scene.render(width=32, height=24, time=0.3, threads=1, progress=False)
    assert time.monotonic() - started < 5
    assert image.shape == (24, 32, 3)
    assert scene.last_report["spp_added"] >= 1


def test_progressive_passes_end_in_the_full_render(tiny):
    scene = lucent.Scene.from_dict(tiny)
    full = scene.render(spp=6, progress=False)
    images = list(scene.render_progressive(passes=3, spp=6))
    assert len(images) == 3
    assert images[-1].tobytes() == full.tobytes()
    assert images[0].tobytes() != full.tobytes()
    # Path tracer, Sobol sampler.
    cornell = lucent.load(SCENES / "cornell-box.toml")
    full = cornell.render(width=16, height=16, spp=5, progress=False)
    *_, last = cornell.render_progressive(passes=4, width=16, height=16, spp=5)
    assert last.tobytes() == full.tobytes()


def test_progressive_progress_covers_all_passes(tiny):
    seen = []
    list(lucent.Scene.from_dict(tiny).render_progressive(passes=2, progress=seen.append))
    assert seen[-1] == 1.0 and 0.5 in seen
    assert all(a < b for a, b in zip(seen, seen[1:])), seen


def test_report_is_the_cli_json_of_diff(tmp_path):
    a = lucent.load(SCENES / "showcase.toml").render(width=24, height=16, spp=2, progress=False)
    b = lucent.load(SCENES / "showcase.toml").render(width=24, height=16, spp=2, seed=5, progress=False)
    lucent.write(tmp_path / "a.exr", a)
    lucent.write(tmp_path / "b.exr", b)
    cli = json.loads(run_cli("diff", str(tmp_path / "a.exr"), str(tmp_path / "b.exr"), "--json").stdout)
    assert lucent.diff(a, b) == cli
    assert lucent.diff(tmp_path / "a.exr", str(tmp_path / "b.exr")) == cli
    same = lucent.diff(a, a)
    assert same["mse"] == 0 and same["rel_mse"] == 0 and same["max_abs_error"] == 0
