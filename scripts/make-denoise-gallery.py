#!/usr/bin/env python3
"""The gallery images of docs/denoising.md: noisy and denoised side by side
(glass-and-metal, the BMW, the Cornell box) and the samples per pixel of an
adaptive render.

    bash scripts/test-python.sh        # builds the package into target/py-venv
    target/py-venv/bin/python scripts/make-denoise-gallery.py [--out docs/gallery]

Needs Intel Open Image Denoise (pip install pyoidn) and ../shared for the
BMW.
"""

import argparse
import os

import numpy as np

import lucent

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def side_by_side(path, left, right, tone_map):
    gap = np.ones((left.shape[0], 4, 3), np.float32) * 0.02
    lucent.write(path, np.concatenate([left, gap, right], axis=1), tone_map=tone_map)
    print("wrote", path)


def heat(counts):
    """Samples per pixel as a colour ramp: dark blue (fewest) to yellow (most)."""
    t = (counts - counts.min()) / max(1, counts.max() - counts.min())
    stops = np.array([[0.02, 0.02, 0.15], [0.1, 0.3, 0.8], [0.9, 0.2, 0.2], [1.0, 0.95, 0.3]], np.float32)
    x = t * (len(stops) - 1)
    i = np.minimum(x.astype(int), len(stops) - 2)
    f = (x - i)[..., None]
    return (stops[i] * (1 - f) + stops[i + 1] * f).astype(np.float32)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "gallery"))
    a = ap.parse_args()
    glass = lucent.load(os.path.join(REPO, "scenes", "glass-and-metal.toml"))
    out = glass.render(spp=16, denoise=True, aovs=[], progress=False)
    side_by_side(os.path.join(a.out, "denoise-glass-and-metal.png"), out["noisy"], out["color"], "aces")
    box = lucent.load(os.path.join(REPO, "scenes", "cornell-box.toml"))
    out = box.render(width=400, height=400, spp=4, denoise=True, aovs=[], progress=False)
    side_by_side(os.path.join(a.out, "denoise-cornell-box.png"), out["noisy"], out["color"], "classic")
    bmw = os.path.join(REPO, "..", "shared", "data", "pbrt-v4", "bmw-m6", "bmw-m6.pbrt")
    if os.path.exists(bmw):
        car = lucent.load(bmw, env=os.path.join(REPO, "scenes", "sky.hdr"))
        out = car.render(width=700, height=500, spp=8, denoise=True, aovs=[], progress=False)
        side_by_side(os.path.join(a.out, "denoise-bmw-m6.png"), out["noisy"], out["color"], "classic")
    image = glass.render(spp=256, adaptive=0.02, progress=False)
    counts = glass.last_report["sample_counts"].astype(np.float32)
    print(f"adaptive: mean {counts.mean():.1f} spp, min {counts.min():.0f}, max {counts.max():.0f}")
    lucent.write(os.path.join(a.out, "adaptive-glass-and-metal.png"), image, tone_map="aces")
    lucent.write(os.path.join(a.out, "adaptive-glass-and-metal-spp.png"), heat(counts), tone_map="clamp", srgb=False)
    print("wrote the adaptive render and its samples per pixel")


if __name__ == "__main__":
    main()
