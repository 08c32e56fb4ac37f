#!/usr/bin/env bash
# Convergence of the path tracer on the Cornell box against the Tungsten
# reference: relative MSE at 16, 64, 256 and 1024 samples per pixel, from
# one progressive render resumed at each step (so the four images are the
# prefixes of one 1024-spp render). Prints one line per step; the figures
# go to docs/performance.md.
#
#   scripts/cornell-convergence.sh [SAMPLER] [OUT_DIR]
#
# SAMPLER is sobol (default) or independent. Needs ../shared and a release
# build (cargo build --release).
set -euo pipefail
cd "$(dirname "$0")/.."
sampler=${1:-sobol}
out=${2:-target/convergence}
ref=../shared/references/cornell-box/reference-tungsten.exr
bin=${LUCENT_BIN:-target/release/lucent}
mkdir -p "$out"
img="$out/cornell-$sampler.exr"
rm -f "$img" "$img.ckpt"
resume=()
prev=0
for spp in 16 64 256 1024; do
    start=$(date +%s.%N)
    "$bin" render scenes/cornell-box.toml -o "$img" --sampler "$sampler" --spp "$spp" \
        --checkpoint-every 1000000 "${resume[@]}" -q
    end=$(date +%s.%N)
    metrics=$("$bin" diff "$img" "$ref" --json)
    echo "{\"sampler\": \"$sampler\", \"spp\": $spp, \"seconds_for_last_$((spp - prev))_spp\": $(echo "$end - $start" | bc), \"diff\": $metrics}"
    resume=(--resume)
    prev=$spp
done
