"""Shared fixtures of the Python tests: the repository's scenes, the
command-line program to compare with, and tiny scenes."""

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
SCENES = REPO / "scenes"


def cli_path() -> Path:
    """The `lucent` program of this checkout (`LUCENT_CLI` overrides)."""
    path = Path(os.environ.get("LUCENT_CLI", REPO / "target" / "release" / "lucent"))
    if not path.is_file():
        pytest.fail(f"{path} is missing: build it with `cargo build --release -p lucent-cli` and point LUCENT_CLI at it (scripts/test-python.sh does)")
    return path


def run_cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Run the `lucent` program; its output as text."""
    result = subprocess.run([str(cli_path()), *args], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"lucent {' '.join(args)} failed:\n{result.stderr}")
    return result


def tiny_dict() -> dict:
    """A small scene as a dict in the scene-file schema: two spheres, a
    plane, a point light; 32×24 pixels, 4 samples per pixel."""
    return {
        "camera": {"eye": [0, 1, -5], "look_at": [0, 0.5, 0], "fov": 60},
        "render": {"width": 32, "height": 24, "spp": 4},
        "materials": {
            "red": {"matte": {"color": [0.9, 0.1, 0.1]}},
            "floor": {"matte": {"color": [0.8, 0.8, 0.8]}},
        },
        "sphere": [
            {"center": [0, 1, 0], "radius": 1, "material": "red"},
            {"center": [1.5, 0.5, 0.5], "radius": 0.5, "material": "red"},
        ],
        "plane": [{"point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"}],
        "point_light": [{"position": [5, 5, -5]}],
    }


@pytest.fixture
def tiny() -> dict:
    return tiny_dict()
