#!/usr/bin/env python3
"""Samples per second of two lucent builds on the path-traced scenes (issue 28, goal 3).

Runs `lucent render SCENE --width W --height H --spp N --threads T --quiet`
for every scene below, alternating the build under test and a baseline
build ROUNDS times, and prints a Markdown table of the medians: samples per
second (width × height × spp over the whole process's wall time, scene
loading included) and the change. Scenes whose files are missing (the
`../shared` ones on a machine without it) are skipped with a note.

    cargo build --release && cp target/release/lucent /tmp/lucent-after
    git stash && cargo build --release && cp target/release/lucent /tmp/lucent-before && git stash pop
    scripts/bench-scenes.py --lucent /tmp/lucent-after --baseline /tmp/lucent-before

The machine is shared and noisy: compare the two builds of one run, not
runs of different days.
"""

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared"

# (name, scene file, width, height, spp, extra arguments)
SCENES = [
    ("Cornell box", ROOT / "scenes/cornell-box.toml", 512, 512, 16, []),
    ("glass-and-metal", ROOT / "scenes/glass-and-metal.toml", 400, 225, 16, []),
    ("media", ROOT / "scenes/media.toml", 400, 250, 16, []),
    ("bunnies (path)", ROOT / "scenes/bunnies.toml", 480, 270, 8, ["--integrator", "path"]),
    ("Veach MIS", SHARED / "references/veach-mis/scene-v4.pbrt", 640, 360, 16, []),
    ("killeroo-simple", SHARED / "data/pbrt-v4/killeroos/killeroo-simple.pbrt", 400, 400, 16, []),
    ("killeroo-coated-gold", SHARED / "data/pbrt-v4/killeroos/killeroo-coated-gold.pbrt", 400, 400, 16, []),
    ("killeroo-gold", SHARED / "data/pbrt-v4/killeroos/killeroo-gold.pbrt", 400, 400, 16, []),
    # Rendered at its start time: lucent has no motion blur (a warning says so).
    ("killeroo-moving", SHARED / "data/pbrt-v4/killeroos/killeroo-moving.pbrt", 400, 400, 16, []),
    # The BMW's own environment map is not shipped: light it with the sky.
    ("BMW M6", SHARED / "data/pbrt-v4/bmw-m6/bmw-m6.pbrt", 480, 270, 8, ["--env", str(ROOT / "scenes/sky.hdr")]),
]


def run(binary: Path, scene: Path, w: int, h: int, spp: int, extra: list, threads: int, out: Path) -> float:
    """Wall seconds of one whole render process."""
    cmd = [str(binary), "render", str(scene), "-o", str(out), "--width", str(w), "--height", str(h),
           "--spp", str(spp), "--threads", str(threads), "--quiet", *extra]
    start = time.perf_counter()
    result = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - start
    if result.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{result.stderr}")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lucent", type=Path, default=ROOT / "target/release/lucent", help="the build under test")
    parser.add_argument("--baseline", type=Path, required=True, help="the build to compare with")
    parser.add_argument("--rounds", type=int, default=3, help="alternating runs of each (default 3)")
    parser.add_argument("--threads", type=int, default=2, help="render threads (default 2)")
    parser.add_argument("--only", help="run only the scenes whose name contains this")
    args = parser.parse_args()
    for binary in (args.lucent, args.baseline):
        if not binary.is_file():
            sys.exit(f"{binary}: no such build")

    print(f"| scene | size, spp | baseline | {args.lucent.name} | change |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "image.exr"
        for name, scene, w, h, spp, extra in SCENES:
            if args.only and args.only.lower() not in name.lower():
                continue
            if not scene.is_file():
                print(f"| {name} | skipped: {scene} is missing | | | |")
                continue
            times = {"after": [], "before": []}
            for _ in range(args.rounds):
                times["after"].append(run(args.lucent, scene, w, h, spp, extra, args.threads, out))
                times["before"].append(run(args.baseline, scene, w, h, spp, extra, args.threads, out))
            samples = w * h * spp
            before = samples / statistics.median(times["before"]) / 1e6
            after = samples / statistics.median(times["after"]) / 1e6
            print(f"| {name} | {w}×{h}, {spp} | {before:.2f} M/s | {after:.2f} M/s | {100 * (after / before - 1):+.0f}% |",
                  flush=True)


if __name__ == "__main__":
    main()
