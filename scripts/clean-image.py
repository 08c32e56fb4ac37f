#!/usr/bin/env python3
"""What a user gets for a clean image of a scene with caustics: fireflies,
relative MSE and mean against a converged render, noisy and denoised, with
and without a clamp of indirect light (`max_indirect`).

    bash scripts/test-python.sh          # builds the package into target/py-venv
    target/py-venv/bin/python scripts/clean-image.py scenes/glass-and-metal.toml \
        --spp 64 --reference-spp 1024 --clamp 10 --clamp 3

A firefly here is a pixel more than five times brighter (Rec. 709
luminance) than the same pixel of the reference, and brighter than 1. Every
render places samples by filter importance sampling (as --denoise does), so
noisy and denoised share one estimator; the reference is unclamped. Needs
Intel Open Image Denoise (pip install pyoidn). Writes the images it shows
with --out DIR.
"""

import argparse
import os
import time

import numpy as np

import lucent

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def figures(image, reference):
    lum, ref = image @ LUMINANCE, reference @ LUMINANCE
    fireflies = int(np.sum((lum > 5 * ref) & (lum > 1)))
    d = lucent.diff(image, reference)
    ratio = [m / r for m, r in zip(d["mean"], d["mean_reference"])]
    return fireflies, d["rel_mse"], ratio


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--reference-spp", type=int, default=1024)
    ap.add_argument("--clamp", type=float, action="append", default=[])
    ap.add_argument("--out")
    a = ap.parse_args()
    scene = lucent.load(a.scene)
    t = time.time()
    reference = scene.render(spp=a.reference_spp, filter_importance=True, progress=False)
    print(f"reference: {a.reference_spp} spp, {time.time() - t:.0f} s; its own fireflies are 0 by definition")
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        lucent.write(os.path.join(a.out, "reference.exr"), reference)
    print("| variant | fireflies | relative MSE | mean / reference (r, g, b) | seconds |")
    print("|---|---|---|---|---|")
    for clamp in [None] + a.clamp:
        variant = lucent.Scene.from_dict(scene.to_dict(), base_dir=os.path.dirname(os.path.abspath(a.scene)))
        if clamp is not None:
            variant.set_render(max_indirect=clamp)
        t = time.time()
        out = variant.render(spp=a.spp, denoise=True, aovs=[], progress=False)
        seconds = time.time() - t
        name = "as is" if clamp is None else f"max_indirect = {clamp:g}"
        for kind in ("noisy", "color"):
            n, err, ratio = figures(out[kind], reference)
            label = f"{name}, {'denoised' if kind == 'color' else 'noisy'}"
            print(f"| {label} | {n} | {err:.4e} | {', '.join(f'{r:.4f}' for r in ratio)} | {seconds:.1f} |")
            if a.out:
                tag = "plain" if clamp is None else f"clamp{clamp:g}"
                lucent.write(os.path.join(a.out, f"{tag}-{'denoised' if kind == 'color' else 'noisy'}.png"), out[kind], tone_map="aces")


if __name__ == "__main__":
    main()
