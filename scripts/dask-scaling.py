#!/usr/bin/env python3
"""How a distributed render scales from 1 to 2 Dask worker processes.

Renders a scene locally (the reference), then with `lucent.distributed` on a
LocalCluster of 1 and of 2 worker processes (1 thread each), and prints each
time, the speed-up from 1 to 2 workers and whether both images are
bit-identical to the local one. The figures in docs/distributed.md come from

    target/py-venv/bin/python scripts/dask-scaling.py

(the defaults: scenes/cornell-box.toml at 1024x1024, 64 spp). Worker start-up
is not timed; what is timed is one `lucent.distributed.render` call: packing
and shipping the scene, loading it on the workers, rendering and merging.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

import lucent
from lucent import distributed
from dask.distributed import Client, LocalCluster

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _time(fn):
    began = time.perf_counter()
    value = fn()
    return value, time.perf_counter() - began


def _identical(a, b):
    """Bit for bit, NaNs and signed zeros included."""
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default=os.path.join(ROOT, "scenes", "cornell-box.toml"))
    parser.add_argument("--width", type=int, default=1024)
    parser.add_argument("--height", type=int, default=1024)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--chunk", type=int, help="samples per pixel per task (default: lucent.distributed's)")
    parser.add_argument("--workers", default="1,2", help="worker process counts to measure (default 1,2)")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()

    scene = lucent.load(args.scene)
    kwargs = dict(width=args.width, height=args.height, spp=args.spp)
    reference, local_s = _time(lambda: scene.render(progress=False, **kwargs))
    results = {"scene": os.path.relpath(args.scene, ROOT), **kwargs, "cpus": os.cpu_count(), "local_s": local_s}
    print(f"local render ({os.cpu_count()} threads): {local_s:.2f} s", file=sys.stderr)
    runs = []
    for n in [int(w) for w in args.workers.split(",")]:
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
            with Client(cluster) as client:
                client.wait_for_workers(n)
                image, seconds = _time(
                    lambda: distributed.render(scene, client, chunk=args.chunk, progress=False, **kwargs)
                )
        same = _identical(image, reference)
        chunk = args.chunk or distributed.default_chunk(args.spp, n)
        runs.append({"workers": n, "chunk": chunk, "seconds": seconds, "bit_identical": same})
        print(
            f"{n} worker process(es), 1 thread each, chunks of {chunk} spp: {seconds:.2f} s, bit-identical: {same}",
            file=sys.stderr,
        )
    results["runs"] = runs
    if len(runs) >= 2:
        results["speedup"] = runs[0]["seconds"] / runs[-1]["seconds"]
        print(
            f"speed-up from {runs[0]['workers']} to {runs[-1]['workers']} workers: {results['speedup']:.2f}x",
            file=sys.stderr,
        )
    if args.json:
        print(json.dumps(results, indent=1))
    return 0 if all(r["bit_identical"] for r in runs) else 1


if __name__ == "__main__":
    sys.exit(main())
