#!/usr/bin/env python3
"""A small speed change between two lucent builds, read from time shares (issue 28).

Wall and user times on a shared 2-core machine move by ±10% from run to
run, more than the 2–6% a single optimisation gives. What moves much less
is the *share* of the time that `perf` finds in functions which a change
does not touch (the ray traversals, say, when the change is in the
integrator): if the builds do the same work in those functions, the
build that spends less time elsewhere gives them a larger share, and

    time(build) / time(baseline) = share(baseline) / share(build).

This runs `perf record -e cpu-clock` on BASELINE and BUILD with the same
lucent arguments, alternating, ROUNDS times each, sums the shares of the
symbols matching GROUP (a regular expression) in each profile, and prints
every share, the medians, the implied time ratio and how many rounds the
build's share was the larger.

Check first that the group's functions are really unchanged: the same
instructions a sample in a callgrind run of each build (`valgrind
--tool=callgrind`, then `callgrind_annotate`); a function that the change
inlines into or out of another invalidates the measure. Both builds
should be fresh (each in an empty target directory): incremental builds
lay code out differently and move figures by 1–2%.

    scripts/perf-shares.py --rounds 8 \\
        --group 'MeshBvh::intersect_avx2|MeshBvh::occluded_avx2|Primitive::intersect_closer' \\
        /tmp/lucent-before /tmp/lucent-after -- \\
        render scenes/cornell-box.toml --width 256 --height 256 --spp 32 --threads 1

With `--functions N` it also prints, for each build, the median over the
rounds of the whole process's samples and of the N functions with the
most: noisier than the shares (the machine's speed moves them all), but
it shows where the time moved, and a function the change should have
made cheaper can be checked on its own.

Needs `perf` (Debian `linux-perf`); not run by CI.
"""

import argparse
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import build_pair


def group_share(binary: Path, args: list, group: re.Pattern, tmp: Path) -> tuple:
    """Percent of one run's cpu-clock samples in the symbols matching
    `group`, and the run's samples by symbol."""
    data, image = tmp / "perf.data", tmp / "image.exr"
    subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", "2000", "-o", str(data),
                    str(binary), *args, "-o", str(image), "-q"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    report = subprocess.run(["perf", "report", "-i", str(data), "--no-children", "--sort", "symbol",
                             "--stdio", "-n", "--percent-limit", "0"],
                            check=True, capture_output=True, text=True).stdout
    total, samples = 0.0, {}
    for line in report.splitlines():
        m = re.match(r"\s*([\d.]+)%\s+(\d+)\s+\[.\]\s+(.*)", line)
        if not m:
            continue
        # (The name ends where perf's padding before its next columns starts.)
        symbol = re.split(r"\s{2,}", m.group(3).strip())[0]
        samples[symbol] = samples.get(symbol, 0) + int(m.group(2))
        if group.search(symbol):
            total += float(m.group(1))
    return total, samples


def print_functions(base: list, build: list, count: int) -> None:
    """The medians over the rounds of each build's samples, whole process
    and by function (the `count` functions with the most): a cross-check
    of the shares where a function's own samples move."""
    def median(runs, symbol):
        return statistics.median(run.get(symbol, 0) for run in runs)

    totals = [statistics.median(sum(run.values()) for run in runs) for runs in (base, build)]
    print(f"samples, medians: whole process {totals[0]:.0f} -> {totals[1]:.0f} ({totals[1] / totals[0]:.3f})")
    symbols = set().union(*base, *build)
    top = sorted(symbols, key=lambda s: -(median(base, s) + median(build, s)))[:count]
    for symbol in top:
        a, b = median(base, symbol), median(build, symbol)
        print(f"  {a:8.0f} {b:8.0f} {b - a:+7.0f}  {symbol[:100]}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rounds", type=int, default=8, help="runs of each build, alternating (default 8)")
    parser.add_argument("--group", required=True,
                        help="regular expression of the symbols the change leaves alone")
    parser.add_argument("--functions", type=int, default=0, metavar="N",
                        help="also print the medians of each build's samples, whole process and of the N "
                             "functions with the most (a cross-check: noisy, but it shows where time moved)")
    build_pair.add_arguments(parser)
    a = parser.parse_args()
    args = build_pair.lucent_args(parser, a)
    if shutil.which("perf") is None:
        sys.exit("error: `perf` is not installed (Debian: apt-get install linux-perf)")
    group = re.compile(a.group)
    # Each build's group shares and samples by symbol, a pair per round.
    base, build = [], []
    base_runs, build_runs = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(a.rounds):
            order = [(a.baseline, base, base_runs), (a.build, build, build_runs)]
            if r % 2 == 1:
                order.reverse()
            for binary, shares, runs in order:
                share, by_symbol = group_share(binary, args, group, Path(tmp))
                shares.append(share)
                runs.append(by_symbol)
            print(f"round {r + 1}: baseline {base[-1]:.2f}%, build {build[-1]:.2f}%", flush=True)
    if min(base + build) <= 0.0:
        sys.exit("error: the group matched no samples in some run; check --group against `perf report`")
    mb, mn = statistics.median(base), statistics.median(build)
    larger = sum(y > x for x, y in zip(base, build))
    print(f"group share, median: baseline {mb:.2f}% (from {min(base):.2f}), "
          f"build {mn:.2f}% (from {min(build):.2f})")
    print(f"time(build) / time(baseline) = {mb:.2f} / {mn:.2f} = {mb / mn:.3f}; "
          f"the build's share was larger in {larger} of {a.rounds} rounds")
    if a.functions > 0:
        print_functions(base_runs, build_runs, a.functions)


if __name__ == "__main__":
    main()
