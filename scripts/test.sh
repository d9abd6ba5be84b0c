#!/usr/bin/env bash
# The whole test suite, from a fresh Debian machine with a Rust toolchain.
# Installs what it needs, then: format check, clippy, every test (snapshots
# must match: INSTA_UPDATE=no), and generated/ must be up to date.
set -euo pipefail
cd "$(dirname "$0")/.."

need_apt=()
# Tools later stages of the suite use; installed only when missing.
for tool in rustfmt cargo-clippy; do
  command -v "$tool" >/dev/null 2>&1 || rustup component add "${tool#cargo-}" >/dev/null 2>&1 || true
done
if [ "${#need_apt[@]}" -gt 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq "${need_apt[@]}"
fi

export INSTA_UPDATE=no
export CARGO_TERM_COLOR=never

echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy --all-targets -- -D warnings"
cargo clippy --workspace --all-targets -- -D warnings
echo "== cargo test --workspace"
cargo test --workspace
echo "== tessgen generate --check --out generated"
cargo run --quiet -p tessgen -- generate --check --out generated
