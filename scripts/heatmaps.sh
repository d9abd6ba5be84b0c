#!/usr/bin/env bash
# Regenerates the heat maps of docs/accuracy.md: every quad scheme's
# deviation from the exact Catmull-Clark limit (tests/data/cc_limit) on the
# shared closed meshes, one colour range per mesh and measure.
set -euo pipefail
cd "$(dirname "$0")/.."
out=docs/images/heatmaps
mkdir -p "$out"
for mesh in catmark_cube catmark_righthanded catmark_toroidal_tet; do
  cargo run --quiet --release -p tessgen -- compare "tests/data/meshes/$mesh.obj" \
    --schemes pccm,acc,gregory,gregory-osd,g1cc --reference tests/data/cc_limit \
    --heatmap "$out/$mesh.png" --size 320x240 > /dev/null
done
ls -la "$out"
