#!/usr/bin/env python3
"""How much denoising buys: relative MSE against a converged reference of
the denoised image at a few sample counts, of the noisy image at those and
more, and the sample count at which the noisy image reaches each denoised
error (interpolated log-log between the noisy measurements).

    scripts/denoise-error.py --lucent target/release/lucent \
        --scene scenes/cornell-box.toml --reference ../shared/references/cornell-box/reference-tungsten.exr \
        --spp 4,16,64 --noisy-spp 4,16,64,256,1024 [--args "--width 512 --height 512"]

Without --reference, lucent renders one with --reference-spp samples
(filter importance sampling, like the denoised renders). Intel Open Image
Denoise must be findable (pip install pyoidn, or LUCENT_OIDN). Prints a
Markdown table; every render uses --filter-importance so that noisy and
denoised images are the same estimator (the denoised ones also get the
clamp of indirect light that --denoise applies by default).
"""

import argparse
import json
import math
import os
import shlex
import subprocess
import sys
import tempfile
import time


def run(cmd):
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{result.stderr}")
    return result.stdout


def rel_mse(lucent, image, reference):
    return json.loads(run([lucent, "diff", image, reference, "--json"]))["rel_mse"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lucent", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--reference")
    ap.add_argument("--reference-spp", type=int, default=4096)
    ap.add_argument("--keep-reference", help="where to keep the reference lucent renders (to reuse with --reference)")
    ap.add_argument("--spp", default="4,16,64")
    ap.add_argument("--noisy-spp", default="4,16,64,256,1024")
    ap.add_argument("--args", default="", help="extra render arguments (size, --env ...)")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    extra = shlex.split(a.args) + ["--threads", str(a.threads), "--quiet"]
    work = tempfile.TemporaryDirectory(prefix="lucent-denoise-")
    tmp = work.name
    reference = a.reference
    if reference is None:
        reference = a.keep_reference or os.path.join(tmp, "reference.exr")
        t = time.time()
        run([a.lucent, "render", a.scene, "-o", reference, "--spp", str(a.reference_spp), "--filter-importance", *extra])
        print(f"reference: {a.reference_spp} spp in {time.time() - t:.0f} s", file=sys.stderr)
    noisy = {}
    for spp in sorted({int(s) for s in a.noisy_spp.split(",")} | {int(s) for s in a.spp.split(",")}):
        out = os.path.join(tmp, f"noisy-{spp}.exr")
        t = time.time()
        run([a.lucent, "render", a.scene, "-o", out, "--spp", str(spp), "--filter-importance", *extra])
        noisy[spp] = (rel_mse(a.lucent, out, reference), time.time() - t)
    rows = []
    for spp in [int(s) for s in a.spp.split(",")]:
        out = os.path.join(tmp, f"denoised-{spp}.exr")
        t = time.time()
        run([a.lucent, "render", a.scene, "-o", out, "--spp", str(spp), "--denoise", *extra])
        seconds = time.time() - t
        err = rel_mse(a.lucent, out, reference)
        # The noisy sample count of equal error, log-log between the two
        # measurements that bracket it (extrapolated past the last).
        pts = sorted(noisy.items())
        equal = None
        for (s0, (e0, _)), (s1, (e1, _)) in zip(pts, pts[1:]):
            if e1 <= err <= e0 or (s1 == pts[-1][0] and err < e1):
                slope = (math.log(e1) - math.log(e0)) / (math.log(s1) - math.log(s0))
                equal = math.exp(math.log(s0) + (math.log(err) - math.log(e0)) / slope)
                break
        rows.append((spp, noisy[spp][0], err, noisy[spp][1], seconds, equal))
    print(f"| spp | noisy rel. MSE | denoised rel. MSE | ratio | time noisy / denoised (s) | noisy spp of equal error |")
    print("|---|---|---|---|---|---|")
    for spp, ne, de, nt, dt, eq in rows:
        eq_s = "beyond the measurements" if eq is None else f"{eq:.0f}"
        print(f"| {spp} | {ne:.3e} | {de:.3e} | {ne / de:.1f}× | {nt:.1f} / {dt:.1f} | {eq_s} |")
    print("\nnoisy: " + ", ".join(f"{s} spp {e:.3e} ({t:.1f} s)" for s, (e, t) in sorted(noisy.items())))


if __name__ == "__main__":
    main()
