#!/usr/bin/env bash
# Counts printer source lines whose emitted-code string literals hold
# arithmetic (an operator between two operands), comments and prose excluded.
# Issue 15's measure of "printers only spell the Plan": report it before and
# after a change to the printers.
set -euo pipefail
cd "$(dirname "$0")/.."
total=0
for f in $(find codegen/src -path "*back*" -name "*.rs" ! -name abi.rs ! -name docs.rs | sort); do
  n=$(grep -E '"[^"]*[A-Za-z0-9_)}]\s*[-+*/%]\s*[A-Za-z0-9_({][^"]*"' "$f" \
      | grep -vE '"\s*//|^\s*//|"[A-Z][a-z]+ [a-z]|format!\("(glsl|hlsl|wgsl|rust)/' | wc -l || true)
  [ "$n" -gt 0 ] && echo "$n $f"
  total=$((total + n))
done
echo "total $total"
