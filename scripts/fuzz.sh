#!/usr/bin/env bash
# Coverage-guided fuzzing of tessgen's input paths with AFL++ (cargo-afl),
# on the stable toolchain. Not part of CI (CI replays the checked-in corpus
# in `cargo test -p tessgen-fuzz`).
#
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET] [OUT_DIR] [TARGET...]
#
# Builds the instrumented targets (fuzz/src/bin/fuzz_*.rs) once, fuzzes each
# target for SECONDS (default 600) from fuzz/corpus/<target>, and prints the
# statistics per target (executions, corpus, coverage, crashes, hangs).
# Crashes land in OUT_DIR/<target>/default/crashes: reproduce one with
# `target/afl/release/fuzz_<target> < FILE`, fix it, and check the file in
# under fuzz/regressions/<target>/ (replayed by `cargo test`). To refresh
# the checked-in corpus: `cargo afl cmin -i OUT_DIR/<target>/default/queue
# -o fuzz/corpus/<target> -- target/afl/release/fuzz_<target>`.
#
# Needs: `cargo install cargo-afl` (builds AFL++ on first use; gcc, make).
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-600}
out=${2:-target/afl-out}
shift $(( $# > 2 ? 2 : $# )) || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(obj mesh tags scheme)
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target/afl}
cargo afl build --release -p tessgen-fuzz --features afl
mkdir -p "$out"
for t in "${targets[@]}"; do
  # One rayon thread: deterministic coverage (AFL's stability) and no
  # thread start-up per input.
  RAYON_NUM_THREADS=1 AFL_SKIP_CPUFREQ=1 AFL_NO_UI=1 \
  AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 \
    cargo afl fuzz -i "fuzz/corpus/$t" -o "$out/$t" -t 2000 -V "$secs" \
      "$CARGO_TARGET_DIR/release/fuzz_$t" > "$out/$t.log" 2>&1 || true
done
printf '| target | executions | execs/s | corpus | coverage | crashes | hangs |\n|---|---|---|---|---|---|---|\n'
for t in "${targets[@]}"; do
  s="$out/$t/default/fuzzer_stats"
  [ -f "$s" ] || { echo "| $t | (no stats: see $out/$t.log) |"; continue; }
  g() { awk -F' *: *' -v k="$1" '$1==k{print $2}' "$s"; }
  echo "| $t | $(g execs_done) | $(g execs_per_sec) | $(g corpus_count) | $(g bitmap_cvg) | $(g saved_crashes) | $(g saved_hangs) |"
done
