"""``lucent-dask``: render a scene file on a Dask cluster from the shell.

    lucent-dask render SCENE --scheduler tcp://host:8786 -o out.exr
                [--spp N] [--chunk N] [--width W] [--height H] [--seed S]
                [--strict] [--env IMAGE] [--chunk-threads T] [--timeout SECONDS] [--quiet]

The image is written atomically by :func:`lucent.write` (its extension picks
the format), or, if ``-o`` ends in ``.lpart``, the merged partial render is
saved (:meth:`lucent.Partial.save`) to merge with other renders later. Any
error is one line on stderr and exit status 1; a malformed command line is
exit status 2, as with ``lucent``.
"""

from __future__ import annotations

import argparse
import sys
import time
from typing import List, Optional

PROG = "lucent-dask"


class _Parser(argparse.ArgumentParser):
    """argparse, exiting with status 2 and one line for a malformed command line."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of seconds, got {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {text}")
    return value


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog=PROG, description="Render lucent scenes on a Dask cluster.")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    commands.required = True
    r = commands.add_parser(
        "render",
        help="render a scene file across the cluster's workers",
        description="Render SCENE with its samples spread over the workers of a Dask cluster; "
        "the image is bit-identical to `lucent render` on one machine.",
    )
    r.add_argument("scene", metavar="SCENE", help="scene file (.toml, .json, .pbrt, .pbrt.gz)")
    r.add_argument("--scheduler", required=True, metavar="ADDRESS", help="the Dask scheduler, e.g. tcp://host:8786")
    r.add_argument("-o", "--output", required=True, metavar="OUT", help="image (.exr, .png, .bmp, ...) or .lpart")
    r.add_argument("--spp", type=_positive, help="samples per pixel (default: the scene's)")
    r.add_argument("--chunk", type=_positive, help="samples per pixel per task (default: ~4 tasks per worker thread)")
    r.add_argument("--width", type=_positive, help="image width in pixels")
    r.add_argument("--height", type=_positive, help="image height in pixels")
    r.add_argument("--seed", type=int, help="sampler seed")
    r.add_argument("--strict", action="store_true", help="pbrt-v4 scenes: unsupported features are errors")
    r.add_argument("--env", metavar="IMAGE", help="pbrt-v4 scenes: light the scene with this environment image")
    r.add_argument(
        "--chunk-threads", type=_positive, default=1, metavar="T", help="render threads per task (default 1)"
    )
    r.add_argument(
        "--timeout", type=_seconds, default=30.0, metavar="SECONDS", help="to connect to the scheduler (default 30)"
    )
    r.add_argument("--quiet", action="store_true", help="no progress bar and no summary line")
    return parser


def _render(args) -> None:
    import logging

    import lucent

    # Dask logs a failed connection attempt (and a worker lost mid-render,
    # which it recovers from) on stderr; errors that matter reach us as
    # exceptions and are reported in one line.
    logging.getLogger("distributed").setLevel(logging.CRITICAL)

    try:
        from lucent import distributed
    except ImportError as e:
        raise _Failure(str(e)) from None
    from dask.distributed import Client

    scene = lucent.load(args.scene, strict=args.strict, env=args.env)
    job = distributed.prepare(scene, spp=args.spp, width=args.width, height=args.height, seed=args.seed)
    try:
        client = Client(args.scheduler, timeout=args.timeout)
    except (OSError, TimeoutError, ValueError) as e:
        raise _Failure(f"cannot reach the Dask scheduler at {args.scheduler} within {args.timeout:g} s ({e})") from None
    with client:
        workers = len(client.nthreads())
        if workers == 0:
            client.wait_for_workers(1, timeout=args.timeout)
        began = time.perf_counter()
        total = distributed.render(
            job,
            client,
            chunk=args.chunk,
            progress=not args.quiet and sys.stderr.isatty(),
            return_partial=True,
            chunk_threads=args.chunk_threads,
        )
        seconds = time.perf_counter() - began
        workers, threads = len(client.nthreads()), sum(client.nthreads().values())
    if args.output.lower().endswith(".lpart"):
        total.save(args.output)
    else:
        # 8-bit formats are tone mapped as the scene asks, as `lucent render` does.
        lucent.write(args.output, total.image(), tone_map=scene.tone_map, srgb=scene.srgb)
    if not args.quiet:
        height, width = total.image().shape[:2]
        print(
            f"{args.output}: {width}x{height}, {total.spp} spp in {seconds:.2f} s "
            f"on {workers} workers ({threads} threads)",
            file=sys.stderr,
        )


class _Failure(Exception):
    """An error already phrased for the user."""


def main(argv: Optional[List[str]] = None) -> int:
    """The ``lucent-dask`` program; returns its exit status (0, 1 on any error, 2 for a bad command line)."""
    args = _parser().parse_args(argv)
    try:
        if args.command == "render":
            _render(args)
        return 0
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 1
    except Exception as e:  # every error is one line, never a traceback
        message = str(e).strip() or type(e).__name__
        # Multi-line messages (a scene error shows the offending line and a
        # caret) keep their lines; a traceback never appears.
        print(f"{PROG}: error: {message}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
