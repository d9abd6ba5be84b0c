#!/bin/bash
# One sitting: 3 alternating rounds of {osd_bench (all modes), tessgen pccm}, then tessgen acc/gregory/gregory-osd once.
# Everything pinned to one CPU ($CPU, default 1). Raw output -> $1 (default results_sitting.txt).
# TESSGEN: the tessgen binary (default: the repository's target/release/tessgen; `cargo build --release` first).
set -u
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
MESH="$ROOT/tests/data/meshes/big/catmark_righthanded_L3.obj"
TESSGEN="${TESSGEN:-$ROOT/target/release/tessgen}"
CPU="${CPU:-1}"
OUT="${1:-$HERE/results_sitting.txt}"
MODES=far:2:gregory,far:3:gregory,far:2:bspline,bfr
# Wait (at most 10 min) until CPU $CPU has been >=97% idle over a 3 s window, so other processes
# (not pinned) are not sharing CPU $CPU when a benchmark starts. Logs what it waited.
cpu1_idle_pct() {
  local a b
  a=($(grep "^cpu$CPU " /proc/stat)); sleep 3; b=($(grep "^cpu$CPU " /proc/stat))
  local ta=0 tb=0 i
  for i in 1 2 3 4 5 6 7 8; do ta=$((ta + a[i])); tb=$((tb + b[i])); done
  echo $(( 100 * (b[4] - a[4]) / (tb - ta) ))
}
wait_quiet() {
  local t0=$SECONDS p
  while :; do
    p=$(cpu1_idle_pct)
    if [ "$p" -ge 97 ] || [ $((SECONDS - t0)) -ge 600 ]; then break; fi
  done
  echo "# CPU $CPU idle ${p}% over 3 s before start (waited $((SECONDS - t0)) s); loadavg $(cat /proc/loadavg)"
}
TIME="/usr/bin/time -f #_process_involuntary_context_switches_%c_wall_%e_s"
{
echo "# sitting started $(date -u +%FT%TZ) on $(hostname); $(lscpu | grep 'Model name' | sed 's/  */ /g'); $(nproc) vCPUs; all runs: taskset -c $CPU"
echo "# tessgen binary: $(sha256sum "$TESSGEN" | cut -c1-16) ($TESSGEN)"
echo "# loadavg at start: $(cat /proc/loadavg)"
for r in 1 2 3; do
  CHECK=""; [ $r -gt 1 ] && CHECK="--no-check"
  echo; echo "######## round $r: osd_bench ($(date -u +%T), loadavg $(cat /proc/loadavg))"
  echo "\$ taskset -c $CPU $HERE/osd_bench $MESH --levels 9,17,33 --runs 7 --cruns 15 --modes $MODES $CHECK"
  wait_quiet
  taskset -c $CPU "$HERE/osd_bench" "$MESH" --levels 9,17,33 --runs 7 --cruns 15 --modes $MODES $CHECK
  echo; echo "######## round $r: tessgen pccm ($(date -u +%T), loadavg $(cat /proc/loadavg))"
  echo "\$ taskset -c $CPU $TESSGEN bench $MESH --scheme pccm --levels 9,17,33 --runs 5 --threads 1"
  wait_quiet
  $TIME taskset -c $CPU "$TESSGEN" bench "$MESH" --scheme pccm --levels 9,17,33 --runs 5 --threads 1
done
for s in acc gregory gregory-osd; do
  echo; echo "######## once: tessgen $s ($(date -u +%T), loadavg $(cat /proc/loadavg))"
  echo "\$ taskset -c $CPU $TESSGEN bench $MESH --scheme $s --levels 9,17,33 --runs 5 --threads 1"
  wait_quiet
  $TIME taskset -c $CPU "$TESSGEN" bench "$MESH" --scheme $s --levels 9,17,33 --runs 5 --threads 1
done
echo; echo "# sitting ended $(date -u +%FT%TZ); loadavg $(cat /proc/loadavg)"
} > "$OUT" 2>&1
