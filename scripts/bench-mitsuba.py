#!/usr/bin/env python3
"""lucent against Mitsuba 3 on the Cornell box, side by side (issue 11, goal 1).

Runs, alternately and ROUNDS times, lucent's whole process rendering
`scenes/cornell-box.toml` and Mitsuba 3's `mi.render` call on the same scene
(`../shared/references/cornell-box/scene-mitsuba3.xml`), at the same size,
samples per pixel and thread count, and prints each run, the medians, the
ratio of the medians and samples per second. Mitsuba is timed as the
references' README says: in a fresh process per round, after one small
warm-up render that pays for its JIT compilation, until the pixels exist.

With `--quality` it also reports the relative MSE of each image against the
Tungsten reference (`lucent diff`'s measure: per pixel and channel
(a-b)^2/(b^2+0.01), averaged) and lucent's equal-quality time: the time
lucent needs to reach Mitsuba's relative MSE, estimated from its measured
speed and its error at this spp under 1/spp convergence.

Set-up (not done by CI; once per machine):

    apt-get install libllvm19
    python3 -m venv target/mi-venv && target/mi-venv/bin/pip install mitsuba numpy
    cargo build --release
    target/mi-venv/bin/python scripts/bench-mitsuba.py --rounds 3 --threads 2

`DRJIT_LIBLLVM_PATH` is set to Debian's libLLVM 19 when it is not set and
that file exists.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
REFERENCE_DIR = ROOT.parent / "shared" / "references" / "cornell-box"
LLVM = Path("/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")

# One Mitsuba render in a fresh interpreter: load, warm up, time, save.
MITSUBA_RUN = r"""
import json, sys, time
import numpy as np
import mitsuba as mi
import drjit as dr
xml, size, spp, threads, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
mi.set_variant("llvm_ad_rgb")
dr.set_thread_count(threads)
scene = mi.load_file(xml, resx=size, resy=size, spp=spp, max_depth=65)
np.array(mi.render(scene, spp=4))
start = time.perf_counter()
image = np.array(mi.render(scene, spp=spp))
seconds = time.perf_counter() - start
if out:
    # NumPy, not mi.Bitmap(...).write: with one thread, writing an EXR
    # never returns (Mitsuba 3.9.1 here).
    np.save(out, image)
print(json.dumps({"seconds": seconds}))
"""


def relative_mse(path: Path, reference) -> float:
    """lucent diff's relative MSE of the EXR at `path` against `reference`."""
    import numpy as np
    import mitsuba as mi

    if path.suffix == ".npy":
        image = np.load(path).astype(np.float64)[..., :3]
    else:
        image = np.array(mi.Bitmap(str(path)), dtype=np.float64)[..., :3]
    if image.shape != reference.shape:
        raise SystemExit(f"error: {path} is {image.shape[1]}×{image.shape[0]}, the reference "
                         f"{reference.shape[1]}×{reference.shape[0]}")
    return float(np.mean((image - reference) ** 2 / (reference**2 + 0.01)))


def run_lucent(binary: Path, args, out: Path) -> float:
    """Wall time of one whole lucent process."""
    cmd = [str(binary), "render", str(ROOT / "scenes" / "cornell-box.toml"),
           "--width", str(args.size), "--height", str(args.size), "--spp", str(args.spp),
           "--threads", str(args.threads), "--quiet", "-o", str(out)]
    start = time.perf_counter()
    subprocess.run(cmd, check=True)
    return time.perf_counter() - start


def run_mitsuba(args, out: Path) -> float:
    """Seconds of Mitsuba's timed `mi.render` call, in a fresh process."""
    cmd = [sys.executable, "-c", MITSUBA_RUN, str(args.xml), str(args.size), str(args.spp),
           str(args.threads), str(out)]
    done = subprocess.run(cmd, check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])["seconds"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3, help="alternating runs of each (default 3)")
    parser.add_argument("--threads", type=int, default=2, help="threads for both (default 2)")
    parser.add_argument("--size", type=int, default=1024, help="image width and height (default 1024)")
    parser.add_argument("--spp", type=int, default=64, help="samples per pixel (default 64)")
    parser.add_argument("--lucent", type=Path, default=ROOT / "target" / "release" / "lucent",
                        help="the lucent binary (default target/release/lucent)")
    parser.add_argument("--baseline", type=Path,
                        help="another lucent binary (an earlier build) to run alternately as well, for "
                             "before/after figures")
    parser.add_argument("--xml", type=Path, default=REFERENCE_DIR / "scene-mitsuba3.xml",
                        help="Mitsuba's scene (default ../shared/references/cornell-box/scene-mitsuba3.xml)")
    parser.add_argument("--quality", action="store_true",
                        help="also compare each image with the Tungsten reference (needs --size 1024)")
    parser.add_argument("--json", action="store_true", help="print one JSON object at the end")
    args = parser.parse_args()

    if args.rounds < 1 or args.threads < 1 or args.size < 1 or args.spp < 1:
        parser.error("--rounds, --threads, --size and --spp must be at least 1")
    if not args.lucent.is_file():
        parser.error(f"{args.lucent} does not exist: run `cargo build --release` first")
    if args.baseline is not None and not args.baseline.is_file():
        parser.error(f"{args.baseline} does not exist")
    if not args.xml.is_file():
        parser.error(f"{args.xml} does not exist (it is in ../shared/references/cornell-box)")
    if "DRJIT_LIBLLVM_PATH" not in os.environ and LLVM.is_file():
        os.environ["DRJIT_LIBLLVM_PATH"] = str(LLVM)
    try:
        import mitsuba  # noqa: F401
    except ImportError:
        parser.error("Mitsuba 3 is not installed in this interpreter: run this script with the "
                     "virtual environment's python that has `pip install mitsuba numpy`")

    samples = args.size * args.size * args.spp
    runs = [("lucent", lambda out: run_lucent(args.lucent, args, out))]
    if args.baseline is not None:
        runs.append(("baseline", lambda out: run_lucent(args.baseline, args, out)))
    runs.append(("mitsuba", lambda out: run_mitsuba(args, out)))
    times = {name: [] for name, _ in runs}
    with tempfile.TemporaryDirectory() as tmp:
        images = {name: Path(tmp) / (f"{name}.npy" if name == "mitsuba" else f"{name}.exr") for name in times}
        for r in range(args.rounds):
            for name, run in runs:
                seconds = run(images[name])
                times[name].append(seconds)
                print(f"round {r + 1}: {name:8} {seconds:8.2f} s  {samples / seconds / 1e6:6.2f} M samples/s",
                      flush=True)
        median = {k: statistics.median(v) for k, v in times.items()}
        result = {"size": args.size, "spp": args.spp, "threads": args.threads, "rounds": args.rounds}
        for name in times:
            result[f"{name}_s"] = times[name]
            result[f"{name}_median_s"] = median[name]
            result[f"{name}_msamples_per_s"] = samples / median[name] / 1e6
        result["speed_ratio"] = median["mitsuba"] / median["lucent"]
        print(f"median: lucent {median['lucent']:.2f} s, Mitsuba {median['mitsuba']:.2f} s: "
              f"lucent is {result['speed_ratio']:.2f}x Mitsuba's speed")
        if "baseline" in median:
            result["baseline_speed_ratio"] = median["mitsuba"] / median["baseline"]
            print(f"baseline {median['baseline']:.2f} s ({result['baseline_speed_ratio']:.2f}x Mitsuba's "
                  f"speed); lucent / baseline time {median['lucent'] / median['baseline']:.3f}")
        if args.quality:
            import numpy as np
            import mitsuba as mi

            reference = np.array(mi.Bitmap(str(REFERENCE_DIR / "reference-tungsten.exr")),
                                 dtype=np.float64)[..., :3]
            err = {k: relative_mse(p, reference) for k, p in images.items()}
            if "baseline" in err:
                result["baseline_rel_mse"] = err["baseline"]
                print(f"relative MSE against Tungsten: baseline {err['baseline']:.3e}")
            # Under 1/spp convergence, lucent reaches Mitsuba's error with
            # spp * err_lucent / err_mitsuba samples.
            equal_s = median["lucent"] * err["lucent"] / err["mitsuba"]
            result.update({"lucent_rel_mse": err["lucent"], "mitsuba_rel_mse": err["mitsuba"],
                           "lucent_equal_quality_s": equal_s,
                           "equal_quality_ratio": median["mitsuba"] / equal_s})
            print(f"relative MSE against Tungsten: lucent {err['lucent']:.3e}, Mitsuba {err['mitsuba']:.3e}; "
                  f"lucent reaches Mitsuba's in about {equal_s:.2f} s "
                  f"({result['equal_quality_ratio']:.2f}x Mitsuba's speed at equal quality)")
    if args.json:
        print(json.dumps(result))


if __name__ == "__main__":
    main()
