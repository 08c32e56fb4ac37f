#!/usr/bin/env python3
"""Fireflies of a scene at its own settings, and what taming them costs.

Issue 11 (goal 5) counts a firefly as a pixel whose luminance (Rec. 709
weights) is above 1 and above five times the median luminance of its 5×5
neighbourhood (the image's edge pixels repeated beyond it). This renders the
scene as it is, with each variant of its [render] table given on the
command line, and a reference with four times the samples; it prints, for
each, the time, the firefly count, relative MSE against the reference and
the ratio of the image's mean to the reference's (the goal: fewer than 20
fireflies, mean within 2%).

    bash scripts/test-python.sh   # builds and installs the package in target/py-venv
    target/py-venv/bin/python scripts/fireflies.py scenes/glass-and-metal.toml \
        --variant regularize=true --variant max_component=20

Needs the `lucent` Python package and NumPy.
"""

import argparse
import json
import time

import numpy as np

import lucent

LUMINANCE = np.array([0.2126, 0.7152, 0.0722], dtype=np.float64)


def fireflies(image: np.ndarray, floor: float = 1.0, ratio: float = 5.0) -> int:
    """Pixels brighter than `floor` and than `ratio` times the median of
    their 5×5 neighbourhood."""
    y = image.astype(np.float64) @ LUMINANCE
    h, w = y.shape
    padded = np.pad(y, 2, mode="edge")
    window = np.stack([padded[i:i + h, j:j + w] for i in range(5) for j in range(5)])
    median = np.median(window, axis=0)
    return int(((y > floor) & (y > ratio * median)).sum())


def parse_variant(text: str) -> dict:
    """`key=value` (a TOML-like value: true/false, a number, or a string)."""
    key, _, value = text.partition("=")
    if not key or not value:
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    if value in ("true", "false"):
        parsed = value == "true"
    else:
        try:
            parsed = float(value) if any(c in value for c in ".eE") else int(value)
        except ValueError:
            parsed = value
    return {key: parsed}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--variant", action="append", type=parse_variant, default=[],
                        help="a [render] key to set, KEY=VALUE (repeat for several variants)")
    parser.add_argument("--spp", type=int, help="samples per pixel (default: the scene's)")
    args = parser.parse_args()

    base = lucent.load(args.scene)
    spp = args.spp or base.spp

    def render(changes: dict, samples: int):
        scene = lucent.load(args.scene)
        if changes:
            scene.set_render(**changes)
        start = time.perf_counter()
        image = scene.render(spp=samples, progress=False)
        return image, time.perf_counter() - start

    reference, seconds = render({}, 4 * spp)
    print(json.dumps({"variant": "reference", "spp": 4 * spp, "seconds": round(seconds, 1),
                      "fireflies": fireflies(reference)}))
    for changes in [{}] + args.variant:
        image, seconds = render(changes, spp)
        d = lucent.diff(image, reference)
        ratio = [m / r for m, r in zip(d["mean"], d["mean_reference"])]
        print(json.dumps({"variant": changes or "as is", "spp": spp, "seconds": round(seconds, 1),
                          "fireflies": fireflies(image), "rel_mse": round(d["rel_mse"], 5),
                          "mean_ratio": [round(r, 4) for r in ratio]}))


if __name__ == "__main__":
    main()
