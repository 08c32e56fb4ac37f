"""The command line shared by the scripts that compare two lucent builds
(`ab-pairs.py`, `perf-shares.py`): `BASELINE BUILD -- LUCENT ARGS`."""

import argparse
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The two builds and lucent's arguments, after `--`."""
    parser.add_argument("baseline", type=Path)
    parser.add_argument("build", type=Path)
    parser.add_argument("args", nargs=argparse.REMAINDER, help="lucent's arguments, after --")


def lucent_args(parser: argparse.ArgumentParser, parsed: argparse.Namespace) -> list:
    """lucent's arguments from `parsed`, without the `--`; an error if none."""
    args = parsed.args[1:] if parsed.args[:1] == ["--"] else parsed.args
    if not args:
        parser.error("give lucent's arguments after --")
    return args
