#!/usr/bin/env bash
# Cycles reference images for lucent's glTF importer: builds the test scenes
# in Blender, exports them as .glb, and renders each with Cycles twice.
#
#   scripts/gltf/make-references.sh OUTDIR [SPP]
#
# OUTDIR (e.g. target/gltf-reference) receives, for every scene NAME:
#   NAME.glb, NAME.blend, NAME.json, NAME.env.exr    make-scenes.py (env: not
#                                                    where the world is black)
#   NAME.cycles-glb.exr    Cycles render of the .glb re-imported into an empty
#                          scene (the reference to compare lucent with)
#   NAME.cycles-blend.exr  Cycles render of the .blend as built (shows what the
#                          export/import round trip loses)
#   NAME.cycles-*.png      8-bit sRGB previews of both
#   logs/NAME-*.log        Blender's output; timings.txt: seconds per step
# SPP: samples per pixel (default 256); images are 320x240.
#
# lucent on the same scene: lucent render OUTDIR/NAME.glb --env OUTDIR/NAME.env.exr
#   --width 320 --height 240 --spp SPP -o NAME.lucent.exr (no --env where the
#   world is black).
#
# Environment: SCENES="mr-grid textured ..." (default: all), THREADS (default
# 2), BLENDER (the program, default blender), MODES ("glb blend" by default;
# "glb" alone halves the time; "lambert" adds NAME.cycles-lambert.exr, the glb
# render with purely diffuse materials made Lambertian, glTF's diffuse;
# "gltf" adds NAME.cycles-gltf.exr, with opaque materials made glTF's
# layering from Cycles nodes). Every Blender run is niced (nice -n 10).
# Needs Blender 3.4 (Debian 12: apt-get install -y blender); idempotent: all
# outputs are rewritten.
set -euo pipefail

usage() { sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0"; }

here="$(cd "$(dirname "$0")" && pwd)"
[ $# -ge 1 ] && [ $# -le 2 ] || { usage >&2; exit 2; }
case "$1" in -h|--help) usage; exit 0 ;; esac
outdir="$1"
spp="${2:-256}"
case "$spp" in ''|*[!0-9]*|0) echo "error: SPP must be a positive whole number, got '$spp'" >&2; exit 2 ;; esac
threads="${THREADS:-2}"
modes="${MODES:-glb blend}"
scenes="${SCENES:-mr-grid textured transmission volume alpha-mask emissive lights instances vertex-colors}"
blender="${BLENDER:-blender}"

if ! command -v "$blender" >/dev/null 2>&1; then
    echo "error: '$blender' not found. Install Blender 3.4: apt-get install -y blender" \
         "(Debian 12), or set BLENDER=/path/to/blender" >&2
    exit 1
fi
version="$("$blender" --version 2>/dev/null | sed -n 's/^Blender \([0-9.]*\).*/\1/p' | head -n 1)"
case "$version" in
    3.4*) ;;
    *) echo "warning: these scripts were written for Blender 3.4, found '${version:-unknown}'" >&2 ;;
esac

mkdir -p "$outdir/logs"
outdir="$(cd "$outdir" && pwd)"
timings="$outdir/timings.txt"
{
    echo "# $(date -u +%Y-%m-%dT%H:%M:%SZ) Blender $version, ${spp} spp, $threads threads, $(nproc) CPUs"
    echo "# step seconds"
} > "$timings"

# run LOG LABEL blender-args...: niced, output to LOG, timed; on failure the
# log's tail is shown and the script stops.
run() {
    local log="$1" label="$2"; shift 2
    local t0 t1
    t0=$(date +%s.%N)
    if ! nice -n 10 "$blender" -b --factory-startup --python-exit-code 1 "$@" >"$log" 2>&1; then
        echo "error: $label failed; the end of $log:" >&2
        tail -n 30 "$log" >&2
        exit 1
    fi
    t1=$(date +%s.%N)
    local secs
    secs=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')
    echo "$label $secs" >> "$timings"
    echo "  $label: ${secs} s"
}

echo "scenes -> $outdir"
# shellcheck disable=SC2086  # $scenes is a word list
run "$outdir/logs/make-scenes.log" make-scenes \
    --python "$here/make-scenes.py" -- "$outdir" $scenes

for name in $scenes; do
    for mode in $modes; do
        out="$outdir/$name.cycles-$mode.exr"
        png="$outdir/$name.cycles-$mode.png"
        case "$mode" in
            glb | lambert | gltf)
                # The .glb re-imported; lambert: purely diffuse materials
                # Lambertian (glTF's diffuse, not Principled v1's Burley);
                # gltf: opaque Principled BSDFs made glTF's layering from
                # Cycles nodes (render-cycles.py --lambert, --gltf-brdf).
                extra=()
                [ "$mode" = lambert ] && extra=(--lambert)
                [ "$mode" = gltf ] && extra=(--gltf-brdf)
                world="$(python3 -c 'import json, sys; print(",".join(map(str, json.load(open(sys.argv[1]))["world"])))' \
                         "$outdir/$name.json")"
                run "$outdir/logs/$name-$mode.log" "$name/$mode" \
                    --python "$here/render-cycles.py" -- "$out" "$spp" \
                    --from-glb "$outdir/$name.glb" --world "$world" --size 320 240 \
                    --threads "$threads" --preview "$png" "${extra[@]}" ;;
            blend)
                run "$outdir/logs/$name-blend.log" "$name/blend" \
                    "$outdir/$name.blend" \
                    --python "$here/render-cycles.py" -- "$out" "$spp" \
                    --threads "$threads" --preview "$png" ;;
            *) echo "error: unknown mode '$mode' in MODES (glb, lambert, gltf, blend)" >&2; exit 2 ;;
        esac
    done
done
echo "done: $timings"
