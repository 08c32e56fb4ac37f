#!/usr/bin/env bash
# Whole-process wall time of lucent against POV-Ray 3.7 on the classic showcase
# (issue 11): scenes/showcase.toml and its translation scenes/povray/showcase.pov,
# 800×600, 9 samples per pixel, 2 threads, the two renderers run alternately.
#
#   scripts/povray-compare.sh [ROUNDS] [--keep DIR]
#
# ROUNDS (default 3): how many times each renderer runs. Prints every run, the
# median of each and the ratio povray/lucent. The images of the last round are
# written to a temporary directory and removed at the end, unless --keep DIR is
# given (they are then copied there as showcase-lucent-WxH.png and
# showcase-povray.png).
#
# Builds nothing: needs target/release/lucent (cargo build --release -p
# lucent-cli) and povray 3.7 on the PATH (Debian: apt-get install povray).
# Environment overrides: LUCENT, POVRAY (the programs), WIDTH, HEIGHT, THREADS.
# BASELINE=/path/to/an/older/lucent adds that build to every round (run between
# lucent and POV-Ray), for before/after figures taken in the same sitting.
#
# lucent:  lucent render scenes/showcase.toml --width 800 --height 600 --spp 9 --threads 2
# POV-Ray: povray +Iscenes/povray/showcase.pov +W800 +H600 +A0.0 +AM1 +R3 +WT2 -D
#          (+AM1 +R3: a 3×3 jittered grid in every pixel that differs from a
#          neighbour by more than the threshold 0.0, i.e. 9 samples)
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0"; }

rounds=3
keep=""
while [ $# -gt 0 ]; do
    case "$1" in
        --keep) [ $# -ge 2 ] || { echo "error: --keep needs a directory" >&2; exit 2; }
                keep="$2"; shift 2 ;;
        --keep=*) keep="${1#--keep=}"; shift ;;
        -h|--help) usage; exit 0 ;;
        *[!0-9]*|'') echo "error: ROUNDS must be a positive whole number, got '$1'" >&2; usage >&2; exit 2 ;;
        *) rounds="$1"; shift ;;
    esac
done
[ "$rounds" -ge 1 ] || { echo "error: ROUNDS must be at least 1" >&2; exit 2; }

lucent="${LUCENT:-target/release/lucent}"
baseline="${BASELINE:-}"
povray="${POVRAY:-povray}"
width="${WIDTH:-800}"
height="${HEIGHT:-600}"
threads="${THREADS:-2}"
scene=scenes/showcase.toml
pov_scene=scenes/povray/showcase.pov

if [ ! -x "$lucent" ]; then
    echo "error: $lucent not found or not executable; build it first: cargo build --release -p lucent-cli" >&2
    exit 1
fi
if [ -n "$baseline" ] && [ ! -x "$baseline" ]; then
    echo "error: BASELINE=$baseline is not an executable file" >&2
    exit 1
fi
if ! command -v "$povray" >/dev/null 2>&1; then
    echo "error: povray not found on the PATH (Debian/Ubuntu: apt-get install povray), or set POVRAY=/path/to/povray" >&2
    exit 1
fi
for f in "$scene" "$pov_scene"; do
    [ -f "$f" ] || { echo "error: $f is missing" >&2; exit 1; }
done

# POV-Ray's default I/O security (Debian's povray.conf) lets it write only to
# the working directory and /tmp, so both render into a directory under /tmp.
tmp="$(mktemp -d "${TMPDIR:-/tmp}/povray-compare.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT

lucent_out="$tmp/showcase-lucent-${width}x${height}.png"
pov_out="$tmp/showcase-povray.png"
lucent_cmd=("$lucent" render "$scene" --width "$width" --height "$height" --spp 9 --threads "$threads" -o "$lucent_out")
baseline_cmd=("$baseline" render "$scene" --width "$width" --height "$height" --spp 9 --threads "$threads" -o "$tmp/baseline.png")
pov_cmd=("$povray" "+I$pov_scene" "+W$width" "+H$height" +A0.0 +AM1 +R3 "+WT$threads" -D
         File_Gamma=sRGB +FN "+O$pov_out")

# Runs a command, its output to a log; prints its wall time in seconds.
timed() {
    local log="$1"; shift
    local t0 t1
    t0=$(date +%s.%N)
    if ! "$@" >"$log" 2>&1; then
        echo "error: this command failed: $*" >&2
        tail -n 20 "$log" >&2
        return 1
    fi
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f\n", b - a }'
}

median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) printf "%.3f\n", v[(NR + 1) / 2]; else printf "%.3f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

echo "commit:   $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet HEAD -- 2>/dev/null || echo ' (with uncommitted changes)')"
echo "machine:  $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //')"
echo "povray:   $("$povray" --version 2>&1 | grep -m1 'POV-Ray' || echo unknown)"
echo "load:     $(cut -d' ' -f1-3 /proc/loadavg) (1, 5, 15 min) before"
echo "lucent:   ${lucent_cmd[*]}"
[ -z "$baseline" ] || echo "baseline: ${baseline_cmd[*]}"
echo "POV-Ray:  ${pov_cmd[*]}"
echo "${width}×${height}, 9 samples per pixel, $threads threads, rounds: $rounds, alternating"
echo

lucent_times=()
baseline_times=()
pov_times=()
for ((i = 1; i <= rounds; i++)); do
    t=$(timed "$tmp/lucent.log" "${lucent_cmd[@]}")
    lucent_times+=("$t")
    printf 'round %d  lucent  %8.3f s\n' "$i" "$t"
    if [ -n "$baseline" ]; then
        t=$(timed "$tmp/baseline.log" "${baseline_cmd[@]}")
        baseline_times+=("$t")
        printf 'round %d  baseline%8.3f s\n' "$i" "$t"
    fi
    t=$(timed "$tmp/povray.log" "${pov_cmd[@]}")
    pov_times+=("$t")
    printf 'round %d  POV-Ray %8.3f s\n' "$i" "$t"
done

ml=$(median "${lucent_times[@]}")
mp=$(median "${pov_times[@]}")
echo
echo "load:     $(cut -d' ' -f1-3 /proc/loadavg) (1, 5, 15 min) after"
echo "median    lucent  ${ml} s   POV-Ray ${mp} s"
awk -v l="$ml" -v p="$mp" 'BEGIN { printf "ratio     POV-Ray / lucent = %.2f: lucent is %.2f× as fast as POV-Ray\n", p / l, p / l }'
if [ -n "$baseline" ]; then
    mb=$(median "${baseline_times[@]}")
    awk -v l="$ml" -v b="$mb" -v p="$mp" 'BEGIN { printf "baseline  median %.3f s: POV-Ray / baseline = %.2f; baseline / lucent = %.3f\n", b, p / b, b / l }'
fi

if [ -n "$keep" ]; then
    mkdir -p "$keep"
    cp "$lucent_out" "$pov_out" "$keep"/
    echo "images:   $keep/$(basename "$lucent_out") $keep/$(basename "$pov_out")"
else
    echo "images:   removed (pass --keep DIR to keep them)"
fi
