#!/usr/bin/env bash
# Re-render every example scene into docs/gallery/<scene-name>.png.
#
# Usage:  scripts/render-gallery.sh      (no arguments; run from anywhere)
#
# Builds lucent in release mode, renders scenes/*.toml with their own
# settings, and checks that scenes/showcase.json (the JSON translation of
# scenes/showcase.toml) renders to exactly the same image.
set -euo pipefail

cd "$(dirname "$0")/.."
if [ "$#" -ne 0 ]; then
  echo "usage: scripts/render-gallery.sh (takes no arguments)" >&2
  exit 2
fi

cargo build --release --quiet
mkdir -p docs/gallery

scenes=(
  showcase
  wide-166-origin wide-166-near wide-175-near
  dof-r2-f50 dof-r2-f80 dof-r2-f120 dof-r6-f80 dof-r2-f80-25spp
  transform-sphere transform-group
  materials falloff shadows spotlight
  bunny bunnies
  media caustic
)

start=$SECONDS
for name in "${scenes[@]}"; do
  cargo run --release --quiet -- render "scenes/$name.toml" -o "docs/gallery/$name.png"
done

# The JSON scene must give a bit-identical image.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cargo run --release --quiet -- render scenes/showcase.json -o "$tmp/showcase.png" --quiet
if cmp -s "$tmp/showcase.png" docs/gallery/showcase.png; then
  echo "scenes/showcase.json renders identically to scenes/showcase.toml"
else
  echo "error: scenes/showcase.json and scenes/showcase.toml render differently" >&2
  exit 1
fi

# pbrt-v4 scenes from ../shared (imported by `lucent render scene.pbrt`),
# at reduced size and sample counts.
shared=../shared
pbrt=0
if [ -d "$shared" ]; then
  render_pbrt() {
    local name=$1 file=$2
    shift 2
    cargo run --release --quiet -- render "$file" -o "docs/gallery/$name.png" --quiet "$@"
    pbrt=$((pbrt + 1))
  }
  render_pbrt pbrt-cornell-box "$shared/references/cornell-box/scene-v4.pbrt" --width 400 --height 400 --spp 128
  render_pbrt pbrt-veach-mis "$shared/references/veach-mis/scene-v4.pbrt" --width 640 --height 360 --spp 64
  render_pbrt pbrt-killeroo-simple "$shared/data/pbrt-v4/killeroos/killeroo-simple.pbrt" --width 350 --height 350 --spp 64
  render_pbrt pbrt-killeroo-coated-gold "$shared/data/pbrt-v4/killeroos/killeroo-coated-gold.pbrt" --width 684 --height 513 --spp 32
  render_pbrt pbrt-bmw-m6 "$shared/data/pbrt-v4/bmw-m6/bmw-m6.pbrt" --env scenes/sky.hdr --width 700 --height 500 --spp 32
else
  echo "../shared is absent: the pbrt-v4 scenes are not rendered" >&2
fi

# glTF: the metallic × roughness grid that scripts/gltf/make-scenes.py
# builds in Blender and Blender exports (run scripts/gltf/make-references.sh
# target/gltf-reference first; Debian's blender package).
gltf=0
if [ -f target/gltf-reference/mr-grid.glb ]; then
  cargo run --release --quiet -- render target/gltf-reference/mr-grid.glb --env scenes/sky.hdr \
    --width 640 --height 480 --spp 256 --max-indirect 10 -o docs/gallery/gltf-mr-grid.png --quiet
  gltf=1
else
  echo "target/gltf-reference/mr-grid.glb is absent: the glTF scene is not rendered" >&2
fi

echo "rendered $((${#scenes[@]} + pbrt + gltf)) scenes into docs/gallery/ in $((SECONDS - start)) s"
