"""Auxiliary images from Python, and denoising with Intel Open Image Denoise
(the ``pyoidn`` wheel that scripts/test-python.sh installs)."""

import importlib.util
import os

import numpy as np
import pytest

import lucent
from conftest import SCENES

PLANE = {
    "camera": {"eye": [0, 0, -5], "look_at": [0, 0, 0], "fov": 40},
    "render": {"width": 16, "height": 12, "spp": 4, "integrator": "path"},
    "materials": {"wall": {"diffuse": {"color": [0.5, 0.25, 0.125]}}},
    "plane": [{"point": [0, 0, 0], "normal": [0, 0, -1], "material": "wall"}],
    "point_light": [{"position": [0, 0, -4], "intensity": 3}],
}


def have_oidn() -> bool:
    return importlib.util.find_spec("pyoidn") is not None or bool(os.environ.get("LUCENT_OIDN"))


needs_oidn = pytest.mark.skipif(
    not have_oidn() and os.environ.get("CI") != "true",
    reason="Intel Open Image Denoise not installed (pip install pyoidn)",
)


def test_aovs_of_a_diffuse_plane_are_its_reflectance_and_normal():
    scene = lucent.Scene.from_dict(PLANE)
    out = scene.render(aovs=["albedo", "normal", "position", "depth"], progress=False)
    assert set(out) == {"color", "albedo", "normal", "position", "depth"}
    assert out["albedo"].shape == (12, 16, 3) and out["depth"].shape == (12, 16)
    np.testing.assert_allclose(out["albedo"], np.broadcast_to([0.5, 0.25, 0.125], (12, 16, 3)), atol=4e-6)
    np.testing.assert_allclose(out["normal"], np.broadcast_to([0, 0, -1], (12, 16, 3)), atol=4e-6)
    assert np.all(np.abs(out["position"][..., 2]) < 1e-4)
    assert np.all(out["depth"] >= 5.0 - 1e-4)
    # The colour is the plain render's, bit for bit.
    assert out["color"].tobytes() == scene.render(progress=False).tobytes()
    # An empty list asks for none, and still gives a dict.
    assert set(scene.render(aovs=[], progress=False)) == {"color"}
    with pytest.raises(ValueError, match="aovs must be a list of albedo, normal, position, depth"):
        scene.render(aovs=["colour"], progress=False)
    with pytest.raises(ValueError, match="aovs must be a list"):
        scene.render(aovs="albedo", progress=False)


def test_partial_aovs_merge_into_the_render_of_all_samples():
    scene = lucent.load(SCENES / "cornell-box.toml")
    kw = dict(width=20, height=20, spp=4, progress=False)
    whole = scene.render(aovs=["normal", "depth"], **kw)
    parts = [scene.render_partial(a, b, aovs=["normal", "depth"], **kw) for a, b in [(0, 1), (1, 4)]]
    merged = parts[1] + parts[0]
    layers = merged.aovs()
    assert layers["normal"].tobytes() == whole["normal"].tobytes()
    assert layers["depth"].tobytes() == whole["depth"].tobytes()
    assert merged.image().tobytes() == whole["color"].tobytes()


def test_denoise_checks_its_arguments(monkeypatch):
    image = np.zeros((4, 5, 3), np.float32)
    with pytest.raises(ValueError, match="albedo must have the image's shape"):
        lucent.denoise(image, albedo=np.zeros((5, 4, 3)))
    with pytest.raises(ValueError, match="unknown quality"):
        lucent.denoise(image, quality="best")
    with pytest.raises(ValueError, match="color must have shape"):
        lucent.denoise(np.zeros((4, 5)))
    # Without the library: a RuntimeError that names what is missing.
    monkeypatch.setenv("LUCENT_OIDN", "/no/such/libOpenImageDenoise.so.2")
    with pytest.raises(RuntimeError, match="LUCENT_OIDN names it, but there is no such file"):
        lucent.denoise(image)


@needs_oidn
def test_render_denoise_beats_the_noisy_image():
    scene = lucent.load(SCENES / "cornell-box.toml")
    kw = dict(width=48, height=48, progress=False)
    reference = scene.render(spp=256, **kw)
    out = scene.render(spp=4, denoise=True, aovs=["albedo", "normal"], **kw)
    assert set(out) == {"color", "noisy", "albedo", "normal"}
    mse = lambda a: float(np.mean((a - reference) ** 2))  # noqa: E731
    assert mse(out["color"]) < 0.5 * mse(out["noisy"]), (mse(out["color"]), mse(out["noisy"]))
    # lucent.denoise with the same guides gives the same image.
    again = lucent.denoise(out["noisy"], out["albedo"], out["normal"])
    assert again.tobytes() == out["color"].tobytes()
    # Without aovs, the denoised image alone.
    assert scene.render(spp=4, denoise=True, **kw).tobytes() == out["color"].tobytes()
    # Colour alone works too.
    alone = lucent.denoise(out["noisy"])
    assert np.isfinite(alone).all() and mse(alone) < mse(out["noisy"])
    # A normal needs an albedo.
    with pytest.raises(RuntimeError, match="normal image can only be used together with an albedo"):
        lucent.denoise(out["noisy"], normal=out["normal"])


def test_adaptive_sampling_from_python_is_the_cli_render():
    scene = lucent.load(SCENES / "cornell-box.toml")
    image = scene.render(width=24, height=24, spp=40, adaptive=0.05, progress=False)
    counts = scene.last_report["sample_counts"]
    assert counts.shape == (24, 24) and counts.max() == 40 and counts.min() >= 16
    again = scene.render(width=24, height=24, spp=40, adaptive=0.05, threads=1, progress=False)
    assert again.tobytes() == image.tobytes()
    with pytest.raises(ValueError, match="adaptive must be a threshold"):
        scene.render(width=24, height=24, adaptive=-1, progress=False)
