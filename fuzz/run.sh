#!/usr/bin/env bash
# Fuzz every reader (or those named) for SECONDS each, two at a time, with
# the limits of docs/reliability.md: no input may take over a second or
# 2 GB. Needs the nightly toolchain and cargo-fuzz (`cargo install
# cargo-fuzz`). Usage: fuzz/run.sh SECONDS [TARGET...]
# Corpora grow in fuzz/corpus/TARGET (not committed), starting from
# fuzz/seeds/TARGET; crashes land in fuzz/artifacts/TARGET. Each run's last
# lines (executions, coverage) go to fuzz/logs/TARGET.log.
# Leak detection is off: it doubled the time of an input (LeakSanitizer
# scans the heap whenever an input's allocations and frees differ), and a
# leak is not what these campaigns look for; AddressSanitizer stays on.
set -euo pipefail
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
cd "$(dirname "$0")"
seconds=${1:?usage: fuzz/run.sh SECONDS [TARGET...]}
shift
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(ply obj pbrt_parse pbrt_import scene_toml scene_json pfm image lpart checkpoint gltf spd pbrt_files lpart_body pbrt_grammar scene_grammar)
fi
cargo +nightly fuzz build -O
mkdir -p logs
run() {
    local t=$1
    mkdir -p "corpus/$t"
    cargo +nightly fuzz run -O "$t" "corpus/$t" "seeds/$t" -- \
        -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=1 -print_final_stats=1 -detect_leaks=0 \
        >"logs/$t.log" 2>&1 || echo "$t: stopped with a finding (see logs/$t.log and artifacts/$t)"
    grep -E "^#[0-9]+.*(DONE|cov:)" "logs/$t.log" | tail -1 | sed "s/^/$t: /"
}
for ((i = 0; i < ${#targets[@]}; i += 2)); do
    run "${targets[i]}" &
    if [ $((i + 1)) -lt ${#targets[@]} ]; then run "${targets[i + 1]}" & fi
    wait
done
