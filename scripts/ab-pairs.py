#!/usr/bin/env python3
"""Two lucent builds on one command, in alternating pairs (issue 28).

Runs `BASELINE ARGS -o TMP -q` and `BUILD ARGS -o TMP -q` ROUNDS times,
swapping which runs first each round, and prints the median user time of
each and the median of the per-pair ratios BUILD / BASELINE with every
ratio. On a shared, noisy machine a pair's two runs see much the same
load, so the paired ratio is steadier than the two medians; its spread
says how large a change the run can resolve.

    scripts/ab-pairs.py --rounds 20 /tmp/lucent-before /tmp/lucent-after -- \\
        render scenes/glass-and-metal.toml --width 400 --height 224 --spp 16 --threads 1
"""

import argparse
import resource
import statistics
import subprocess
import tempfile
from pathlib import Path

import build_pair


def user_seconds(binary: Path, args: list, out: Path) -> float:
    """User CPU seconds of one run (the children's rusage before and after)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    subprocess.run([str(binary), *args, "-o", str(out), "-q"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rounds", type=int, default=10)
    build_pair.add_arguments(parser)
    a = parser.parse_args()
    args = build_pair.lucent_args(parser, a)
    base, build, ratios = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "image.exr"
        for r in range(a.rounds):
            if r % 2 == 0:
                x = user_seconds(a.baseline, args, out)
                y = user_seconds(a.build, args, out)
            else:
                y = user_seconds(a.build, args, out)
                x = user_seconds(a.baseline, args, out)
            base.append(x)
            build.append(y)
            ratios.append(y / x)
    print(f"baseline {a.baseline}: median {statistics.median(base):.3f} s")
    print(f"build    {a.build}: median {statistics.median(build):.3f} s")
    print(f"build / baseline, paired: median {statistics.median(ratios):.3f} "
          f"(from {min(ratios):.3f} to {max(ratios):.3f}): {' '.join(f'{q:.3f}' for q in ratios)}")


if __name__ == "__main__":
    main()
