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

With `--wall N` (for a run on N threads) it compares wall times instead,
and prints each build's median idle time, `wall − CPU / N`: the time the
N cores were not all busy (serial loading and writing, the tail of a
pass), which user times cannot show.

    scripts/ab-pairs.py --wall 2 --rounds 10 /tmp/lucent-before /tmp/lucent-after -- \\
        render scenes/cornell-box.toml --width 512 --height 512 --spp 16 --threads 2
"""

import argparse
import resource
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import build_pair


def run_seconds(binary: Path, args: list, out: Path) -> tuple:
    """Wall, user and user + system CPU seconds of one run (the children's
    rusage before and after)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([str(binary), *args, "-o", str(out), "-q"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    user = after.ru_utime - before.ru_utime
    return wall, user, user + after.ru_stime - before.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rounds", type=int, default=10)
    parser.add_argument("--wall", type=int, metavar="N", help="compare wall times of runs on N threads")
    build_pair.add_arguments(parser)
    a = parser.parse_args()
    args = build_pair.lucent_args(parser, a)
    base, build, ratios = [], [], []
    idle = {"baseline": [], "build": []}

    def measure(which: str, binary: Path, out: Path) -> float:
        wall, user, cpu = run_seconds(binary, args, out)
        if a.wall:
            idle[which].append(wall - cpu / a.wall)
            return wall
        return user

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "image.exr"
        for r in range(a.rounds):
            if r % 2 == 0:
                x = measure("baseline", a.baseline, out)
                y = measure("build", a.build, out)
            else:
                y = measure("build", a.build, out)
                x = measure("baseline", a.baseline, out)
            base.append(x)
            build.append(y)
            ratios.append(y / x)
    kind = "wall" if a.wall else "user"
    print(f"baseline {a.baseline}: median {kind} {statistics.median(base):.3f} s")
    print(f"build    {a.build}: median {kind} {statistics.median(build):.3f} s")
    if a.wall:
        print(f"idle (wall - CPU / {a.wall}), medians: baseline {1000 * statistics.median(idle['baseline']):.0f} ms, "
              f"build {1000 * statistics.median(idle['build']):.0f} ms")
    print(f"build / baseline, paired: median {statistics.median(ratios):.3f} "
          f"(from {min(ratios):.3f} to {max(ratios):.3f}): {' '.join(f'{q:.3f}' for q in ratios)}")


if __name__ == "__main__":
    main()
