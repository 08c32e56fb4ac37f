#!/usr/bin/env python3
"""What adaptive sampling buys: the time to reach a relative MSE against a
converged reference, with it and without it.

    scripts/adaptive-error.py --lucent target/release/lucent \
        --scene scenes/cornell-box.toml --reference ../shared/references/cornell-box/reference-tungsten.exr \
        --uniform-spp 8,16,32,64 --adaptive 0.05,0.02,0.01 --max-spp 64 [--args "..."]

Renders the scene with every pixel taking `--uniform-spp` samples, then
adaptively with each threshold (up to `--max-spp` samples a pixel), and
prints each render's wall time, relative MSE and mean samples per pixel;
for each adaptive render, the time a uniform render needs for the same
error (interpolated log-log between the uniform renders that bracket it).
Without --reference, one is rendered with --reference-spp samples.
"""

import argparse
import json
import math
import os
import re
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


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lucent", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--reference")
    ap.add_argument("--reference-spp", type=int, default=4096)
    ap.add_argument("--uniform-spp", default="8,16,32,64")
    ap.add_argument("--adaptive", default="0.05,0.02,0.01")
    ap.add_argument("--max-spp", type=int, default=64)
    ap.add_argument("--args", default="")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    extra = shlex.split(a.args) + ["--threads", str(a.threads)]
    work = tempfile.TemporaryDirectory(prefix="lucent-adaptive-")
    tmp = work.name
    reference = a.reference
    if reference is None:
        reference = os.path.join(tmp, "reference.exr")
        run([a.lucent, "render", a.scene, "-o", reference, "--spp", str(a.reference_spp), "--quiet", *extra])

    def measure(name, flags):
        out = os.path.join(tmp, name + ".exr")
        t = time.time()
        text = run([a.lucent, "render", a.scene, "-o", out, *flags, *extra])
        seconds = time.time() - t
        err = json.loads(run([a.lucent, "diff", out, reference, "--json"]))["rel_mse"]
        m = re.search(r"adaptive sampling: ([0-9.]+) samples per pixel", text)
        return seconds, err, float(m.group(1)) if m else None

    uniform = []
    for spp in [int(s) for s in a.uniform_spp.split(",")]:
        seconds, err, _ = measure(f"uniform-{spp}", ["--spp", str(spp)])
        uniform.append((spp, seconds, err))
    print("| render | seconds | relative MSE | mean spp | uniform seconds for this error |")
    print("|---|---|---|---|---|")
    for spp, seconds, err in uniform:
        print(f"| uniform {spp} spp | {seconds:.1f} | {err:.4e} | {spp} | |")
    for t in a.adaptive.split(","):
        seconds, err, mean = measure(f"adaptive-{t}", ["--spp", str(a.max_spp), "--adaptive", t])
        equal, note = None, ""
        for (s0, t0, e0), (s1, t1, e1) in zip(uniform, uniform[1:]):
            last = (s1, t1, e1) == uniform[-1]
            if e1 <= err <= e0 or (last and err < e1):
                slope = (math.log(t1) - math.log(t0)) / (math.log(e1) - math.log(e0))
                equal = math.exp(math.log(t0) + slope * (math.log(err) - math.log(e0)))
                note = ", extrapolated" if err < e1 else ""
                break
        eq = "beyond the measurements" if equal is None else f"{equal:.1f} ({equal / seconds:.2f}×{note})"
        print(f"| adaptive {t}, ≤ {a.max_spp} spp | {seconds:.1f} | {err:.4e} | {mean:.1f} | {eq} |")


if __name__ == "__main__":
    main()
