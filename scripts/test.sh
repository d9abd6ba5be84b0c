#!/usr/bin/env bash
# The whole test suite, from a fresh Debian machine with a Rust toolchain.
# Installs what it needs, then: format check, clippy, rustdoc (warnings are
# errors), every test (snapshots must match: INSTA_UPDATE=no), and
# generated/ must be up to date.
set -euo pipefail
cd "$(dirname "$0")/.."

# System tools the suite runs, installed only when missing:
#   glslangValidator (glslang-tools)  compiles the emitted GLSL and HLSL to SPIR-V
#   spirv-val (spirv-tools)           validates that SPIR-V
#   Mesa's lavapipe + Vulkan loader   the software GPU the wgpu tests run on
need_apt=()
command -v glslangValidator >/dev/null 2>&1 || need_apt+=(glslang-tools)
command -v spirv-val >/dev/null 2>&1 || need_apt+=(spirv-tools)
ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1 || need_apt+=(mesa-vulkan-drivers)
ldconfig -p 2>/dev/null | grep -q 'libvulkan.so.1' || need_apt+=(libvulkan1)
#   Xvfb and the X11 libraries winit   an X server and the client libraries winit loads at
#   loads (xvfb, libx11-xcb1, …)       run time, for `tessgen view`'s window test (cli/tests/view.rs)
command -v Xvfb >/dev/null 2>&1 || need_apt+=(xvfb)
for lib_pkg in libX11-xcb.so.1:libx11-xcb1 libxkbcommon-x11.so.0:libxkbcommon-x11-0 \
               libXcursor.so.1:libxcursor1 libXrandr.so.2:libxrandr2 libXi.so.6:libxi6; do
  ldconfig -p 2>/dev/null | grep -q "${lib_pkg%%:*}" || need_apt+=("${lib_pkg##*:}")
done
#   node + npm (nodejs, npm)          run Dawn, Chrome's WebGPU, on the emitted WGSL (tests/dawn)
command -v node >/dev/null 2>&1 || need_apt+=(nodejs)
command -v npm >/dev/null 2>&1 || need_apt+=(npm)
if [ "${#need_apt[@]}" -gt 0 ]; then
  echo "== installing ${need_apt[*]}"
  export DEBIAN_FRONTEND=noninteractive
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need_apt[@]}"
fi
for component in rustfmt clippy; do
  rustup component list --installed 2>/dev/null | grep -q "^$component" || rustup component add "$component" || true
done
# wgpu looks for a runtime dir; lavapipe does not need one, silence the warning.
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"

export INSTA_UPDATE=no
export CARGO_TERM_COLOR=never
# A CI run builds once: incremental caches would only take disk.
export CARGO_INCREMENTAL=0

# Dawn (npm `webgpu`, pinned by tests/dawn/package-lock.json) for tests/tests/dawn.rs.
if [ ! -d tests/dawn/node_modules/webgpu ]; then
  echo "== npm ci (tests/dawn: Dawn for the WGSL check)"
  npm ci --prefix tests/dawn --no-audit --no-fund
fi

echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy --all-targets -- -D warnings"
cargo clippy --workspace --all-targets -- -D warnings
echo "== cargo doc (warnings are errors)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps
# The private items too: the internal docs are where a reader finds the
# why, and their links must resolve as the public ones do.
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --document-private-items
echo "== cargo test --workspace"
cargo test --workspace
echo "== tessgen generate --check --out generated"
# The CLI binary `cargo test --workspace` just built for the CLI's tests (the
# test profile writes target/debug): `cargo run -p tessgen` would resolve the
# CLI's features alone and build the runtime a second time.
target/debug/tessgen generate --check --out generated
