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

echo "rendered ${#scenes[@]} scenes into docs/gallery/ in $((SECONDS - start)) s"
