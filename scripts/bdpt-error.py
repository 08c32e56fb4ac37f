#!/usr/bin/env python3
"""Time to equal error: bidirectional path tracing against the path tracer.

Renders a scene with both integrators at doubling sample counts (another
seed than the reference's), measures each render's relative MSE against a
reference image with `lucent diff --json`, and prints, per integrator, the
seconds and the error of each render, then the time each needs to reach
the error of the other's best render (log-log interpolation between the
two renders that bracket it).

    cargo build --release
    target/release/lucent render scenes/caustic.toml -o ref.exr \\
        --width 240 --height 180 --spp 2048 --seed 99
    python3 scripts/bdpt-error.py scenes/caustic.toml ref.exr \\
        --width 240 --height 180 --path-spp 16,64,256,1024 --bdpt-spp 4,16,64
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time


def render(lucent, scene, out, integrator, spp, args):
    cmd = [lucent, "render", scene, "-o", out, "--integrator", integrator, "--spp", str(spp),
           "--width", str(args.width), "--height", str(args.height), "--seed", "1", "-q"]
    if args.max_depth is not None:
        cmd += ["--max-depth", str(args.max_depth)]
    start = time.perf_counter()
    subprocess.run(cmd, check=True)
    return time.perf_counter() - start


def rel_mse(lucent, image, reference):
    out = subprocess.run([lucent, "diff", "--json", image, reference], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)["rel_mse"]


def time_to(runs, target):
    """Seconds at which the (seconds, error) curve reaches `target`."""
    runs = sorted(runs)
    for (t0, e0), (t1, e1) in zip(runs, runs[1:]):
        if e0 >= target >= e1 and e0 > e1 > 0:
            f = (math.log(e0) - math.log(target)) / (math.log(e0) - math.log(e1))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    if runs and runs[0][1] <= target:
        return runs[0][0]
    return float("nan")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene")
    p.add_argument("reference")
    p.add_argument("--lucent", default="target/release/lucent")
    p.add_argument("--width", type=int, default=240)
    p.add_argument("--height", type=int, default=180)
    p.add_argument("--max-depth", type=int)
    p.add_argument("--path-spp", default="16,64,256,1024")
    p.add_argument("--bdpt-spp", default="4,16,64")
    args = p.parse_args()
    runs = {}
    with tempfile.TemporaryDirectory() as d:
        for integrator, spps in (("path", args.path_spp), ("bdpt", args.bdpt_spp)):
            runs[integrator] = []
            for spp in [int(s) for s in spps.split(",")]:
                out = os.path.join(d, f"{integrator}-{spp}.exr")
                seconds = render(args.lucent, args.scene, out, integrator, spp, args)
                err = rel_mse(args.lucent, out, args.reference)
                runs[integrator].append((seconds, err))
                print(f"{integrator:5} {spp:6} spp {seconds:8.2f} s  relMSE {err:.4e}", flush=True)
    # At the error of each integrator's best render: both times, and how
    # many times faster bdpt is (nan where the other's renders never get
    # there; the error of a converging render falls as 1/time, which the
    # last figure extrapolates).
    for best in ("path", "bdpt"):
        target = min(e for _, e in runs[best])
        tp, tb = time_to(runs["path"], target), time_to(runs["bdpt"], target)
        t_last, e_last = max(runs["path"])
        extrapolated = t_last * e_last / target
        print(f"at {best}'s best error {target:.4e}: path {tp:.2f} s (extrapolated {extrapolated:.1f} s), "
              f"bdpt {tb:.2f} s: bdpt {tp / tb:.1f}x faster ({extrapolated / tb:.1f}x extrapolated)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
