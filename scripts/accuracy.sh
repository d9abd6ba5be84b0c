#!/usr/bin/env bash
# Regenerates the tables of docs/accuracy.md: every shared mesh with cc_limit
# ground truth, every quad scheme, level 8 (`tessgen compare`). Prints Markdown.
# Extra arguments go to every `compare` (the isolation table: `--isolate 2`).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --quiet --release -p tessgen
bin=target/release/tessgen
ref=tests/data/cc_limit
closed="catmark_cube catmark_torus catmark_toroidal_tet catmark_righthanded"
open="catmark_tent catmark_single_crease catmark_xord_boundary catmark_xord_interior catmark_fvar_bound3 catmark_gregory_test1 catmark_pawn catmark_car catmark_nonquads"
for group in closed open; do
  echo "### ${group} meshes"
  echo
  first=1
  for m in ${!group}; do
    schemes=pccm,acc,gregory,gregory-osd,g1cc
    # `regular` only where every face is regular.
    case $m in catmark_torus|catmark_single_crease) schemes=$schemes,regular ;; esac
    out=$("$bin" compare "tests/data/meshes/$m.obj" --schemes "$schemes" --reference "$ref" "$@" 2>/dev/null)
    if [ $first = 1 ]; then echo "$out" | head -2; first=0; fi
    echo "$out" | tail -n +3
  done
  echo
done
