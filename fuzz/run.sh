#!/usr/bin/env bash
# Fuzz every reader (or those named) for SECONDS each, two at a time, with
# the limits of docs/reliability.md: no input may take over a second or
# 2 GB. Needs the nightly toolchain and cargo-fuzz (`cargo install
# cargo-fuzz`). Usage: [JOBS=N] fuzz/run.sh SECONDS [TARGET...]
# With JOBS=N (a machine with many cores), each target in turn runs as N
# libFuzzer jobs sharing its corpus; their logs go to fuzz/logs/TARGET.jobs/
# and the sum of their executions to fuzz/logs/TARGET.log.
# Corpora grow in fuzz/corpus/TARGET (not committed), starting from
# fuzz/seeds/TARGET; crashes land in fuzz/artifacts/TARGET. Each run's last
# lines (executions, coverage) go to fuzz/logs/TARGET.log.
# Leak detection is off: it doubled the time of an input (LeakSanitizer
# scans the heap whenever an input's allocations and frees differ), and a
# leak is not what these campaigns look for; AddressSanitizer stays on.
# Two more of its costs are off by default: the fake stack frames that
# catch a use of a stack address after its function returned
# (detect_stack_use_after_return; safe Rust cannot keep such an address,
# and no unsafe block hands one out), and the allocation and free stacks
# recorded for every block (malloc_context_size=0: an error is still
# reported with its own stack; replay the input for the others). Together
# they cut a scene_grammar corpus replay from 3.45 s to 2.57 s (1,500
# inputs, medians of 3), docs/reliability.md.
# The scene and pbrt-v4 targets write each input to a scratch file, as the
# command line reads a path: in memory (/dev/shm) a corpus replays 15-23% faster
# than on disk (scene_grammar, pbrt_files), so it is the default where it exists.
set -euo pipefail
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:detect_stack_use_after_return=0:malloc_context_size=0}
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
cd "$(dirname "$0")"
seconds=${1:?usage: fuzz/run.sh SECONDS [TARGET...]}
shift
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(ply obj pbrt_parse pbrt_import scene_toml scene_json pfm image lpart checkpoint gltf spd pbrt_files lpart_body pbrt_grammar scene_grammar)
fi
cargo +nightly fuzz build -O
mkdir -p logs
jobs=${JOBS:-1}
flags=(-max_total_time="$seconds" -rss_limit_mb=2048 -timeout=1 -print_final_stats=1 -detect_leaks=0)
# N jobs of one target: the fuzzer binary run from a folder of its own,
# where libFuzzer writes one fuzz-K.log per job.
run_jobs() {
    local t=$1 bin
    bin=$PWD/target/$(rustc -vV | sed -n 's/^host: //p')/release/$t
    mkdir -p "corpus/$t" "logs/$t.jobs" "artifacts/$t"
    rm -f "logs/$t.jobs"/fuzz-*.log
    (cd "logs/$t.jobs" && "$bin" "../../corpus/$t" "../../seeds/$t" -jobs="$jobs" -workers="$jobs" \
        -artifact_prefix="../../artifacts/$t/" "${flags[@]}" >/dev/null 2>&1) ||
        echo "$t: stopped with a finding (see logs/$t.jobs and artifacts/$t)"
    cat "logs/$t.jobs"/fuzz-*.log | grep -E "^#[0-9]+.*DONE" >"logs/$t.log" || true
    local total
    total=$(grep -h "number_of_executed_units" "logs/$t.jobs"/fuzz-*.log | awk '{s += $2} END {print s + 0}')
    echo "executed units of $jobs jobs: $total" >>"logs/$t.log"
    # (and the DONE line of the job with the most coverage)
    echo "$t: $jobs jobs, $total executions; $(awk '/DONE/ {for (i = 1; i < NF; i++) if ($i == "cov:") c = $(i + 1);
        if (c > m) {m = c; l = $0}} END {print l}' "logs/$t.log")"
}
if [ "$jobs" -gt 1 ]; then
    for t in "${targets[@]}"; do run_jobs "$t"; done
    exit 0
fi
run() {
    local t=$1
    mkdir -p "corpus/$t"
    cargo +nightly fuzz run -O "$t" "corpus/$t" "seeds/$t" -- "${flags[@]}" >"logs/$t.log" 2>&1 || echo "$t: stopped with a finding (see logs/$t.log and artifacts/$t)"
    grep -E "^#[0-9]+.*(DONE|cov:)" "logs/$t.log" | tail -1 | sed "s/^/$t: /"
}
for ((i = 0; i < ${#targets[@]}; i += 2)); do
    run "${targets[i]}" &
    if [ $((i + 1)) -lt ${#targets[@]} ]; then run "${targets[i + 1]}" & fi
    wait
done
