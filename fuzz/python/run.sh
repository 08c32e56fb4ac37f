#!/usr/bin/env bash
# Fuzz the Python readers (today: the Dask scene-archive unpacker) for
# SECONDS with atheris, with the limits of docs/reliability.md. Installs
# atheris into target/fuzz-venv (from PyPI) on first use.
# Usage: fuzz/python/run.sh SECONDS
set -euo pipefail
# Each input is unpacked into a folder of its own: in memory where possible
# (see fuzz/run.sh).
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
cd "$(dirname "$0")/../.."
seconds=${1:?usage: fuzz/python/run.sh SECONDS}
venv=target/fuzz-venv
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet atheris==3.0.0
fi
mkdir -p fuzz/corpus/archive fuzz/artifacts/archive fuzz/logs
"$venv/bin/python" fuzz/python/archive.py fuzz/corpus/archive fuzz/seeds/archive \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=1 -print_final_stats=1 \
    -artifact_prefix=fuzz/artifacts/archive/ >fuzz/logs/archive.log 2>&1 \
    || echo "archive: stopped with a finding (see fuzz/logs/archive.log and fuzz/artifacts/archive)"
grep -E "^#[0-9]+.*(DONE|cov:)" fuzz/logs/archive.log | tail -1 | sed "s/^/archive: /"
