#!/usr/bin/env python3
"""Render the reference scenes of scripts/gltf/make-references.sh with lucent
and compare them with Cycles' renders of the same .glb files.

    python3 scripts/gltf/compare-lucent.py --lucent target/release/lucent \
        [--dir target/gltf-reference] [--spp 256] [--scenes mr-grid,lights] [--gallery docs/gallery]

For each scene NAME in DIR (NAME.glb, NAME.json, NAME.cycles-glb.exr and,
where the world is not black, NAME.env.exr), renders NAME.lucent.exr at the
reference's size and sample count with the environment given by --env,
then runs `lucent diff --json --block 8` against the Cycles render
(NAME.cycles-glb.exr, or the one --reference names: scripts/gltf/make-references.sh
writes NAME.cycles-lambert.exr with LAMBERT=1) and
writes NAME.side-by-side.png (lucent on the left). Prints a Markdown table:
the per-channel means of both images, the ratio of lucent's mean luminance
to Cycles', the pixel relative MSE and the 8×8 block relative MSE, and the
seconds lucent took. With --gallery, copies the side-by-side images there as
gltf-NAME.png. Needs only python3 and the lucent binary.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import time


def luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lucent", required=True)
    ap.add_argument("--dir", default="target/gltf-reference")
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--scenes", default="")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--gallery", default="")
    ap.add_argument("--reference", default="cycles-glb",
                    help="which Cycles render: NAME.REFERENCE.exr (cycles-glb; cycles-lambert with --lambert)")
    args = ap.parse_args()
    names = [n for n in args.scenes.split(",") if n] or sorted(
        f[:-4] for f in os.listdir(args.dir) if f.endswith(".glb")
    )
    rows = []
    for name in names:
        base = os.path.join(args.dir, name)
        reference = f"{base}.{args.reference}.exr"
        if not os.path.exists(reference):
            sys.exit(f"{reference} is missing: run scripts/gltf/make-references.sh {args.dir} first")
        with open(base + ".json") as f:
            meta = json.load(f)
        cmd = [args.lucent, "render", base + ".glb", "-o", base + ".lucent.exr", "--quiet",
               "--width", str(meta["width"]), "--height", str(meta["height"]), "--spp", str(args.spp),
               "--threads", str(args.threads)]
        if meta.get("env"):
            cmd += ["--env", os.path.join(args.dir, meta["env"])]
        start = time.perf_counter()
        subprocess.run(cmd, check=True)
        seconds = time.perf_counter() - start
        out = subprocess.run(
            [args.lucent, "diff", "--json", "--block", "8", base + ".lucent.exr", reference,
             "--side-by-side", base + ".side-by-side.png"],
            check=True, capture_output=True, text=True,
        )
        d = json.loads(out.stdout)
        ratio = luminance(d["mean"]) / max(luminance(d["mean_reference"]), 1e-9)
        rows.append((name, d["mean"], d["mean_reference"], ratio, d["rel_mse"], d["block_rel_mse"], seconds))
        if args.gallery:
            shutil.copy(base + ".side-by-side.png", os.path.join(args.gallery, f"gltf-{name}.png"))
    fmt = lambda c: "(" + ", ".join(f"{v:.3f}" for v in c) + ")"
    print("| scene | lucent mean RGB | Cycles mean RGB | luminance ratio | rel. MSE | 8×8 block rel. MSE | lucent s |")
    print("|---|---|---|---|---|---|---|")
    for name, a, b, ratio, rel, block, s in rows:
        print(f"| {name} | {fmt(a)} | {fmt(b)} | {ratio:.3f} | {rel:.4f} | {block:.5f} | {s:.1f} |")


if __name__ == "__main__":
    main()
