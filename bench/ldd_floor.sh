#!/usr/bin/env bash
# Per-step cost of the free-surface runs against the floor of their linear solves
# (docs/performance.md, "LDD free surfaces"): the first 300 steps of the Δ = 2 mm Bingham dam
# break (cases/ldd_dam_break_bingham.yaml, time.end 0.3), the first 20 steps of the 50 000-node
# slump (cases/ldd_slump_abrams.yaml, time.end 0.02) and the first 50 steps of the Δ = 1 mm,
# δt = 1e-4 dam break (the shipped case with spacing 0.001, step 1.0e-4, time.end 0.005), each
# through bench_ldd run (the code of `rheosim run`) on two threads (the fastest of --repeat runs),
# then `bench_ldd floor` on that run (the product, V-cycle and set-up times on its initial cloud,
# the floor per step at the iterations it needed, and measured / floor), then once on one thread.
#
#   bench/ldd_floor.sh [BUILD_DIR] [OUT_DIR] [--repeat N] [--only dam2|slump|dam1]
#
# About 7 min on the 2-core machine; run it with the machine otherwise idle. It prints the host's
# memory bandwidth (bench_ldd bandwidth) before each scene and at the end: the floors of the
# memory-bound solves scale with it, so two runs' tables compare only at the same bandwidth, and
# each floor is timed right after the runs it is compared with.
set -euo pipefail
build=${1:-build}
out=${2:-results/ldd_floor}
shift $(( $# > 2 ? 2 : $# )) || true
repeat=2 only=""
while [ $# -gt 0 ]; do
  case "$1" in
    --repeat) repeat=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
sed -e "s/end: 1.2/end: 0.3/" "$here/cases/ldd_dam_break_bingham.yaml" > "$out/dam2.yaml"
sed -e "s/end: [0-9.]*/end: 0.02/" "$here/cases/ldd_slump_abrams.yaml" > "$out/slump.yaml"
sed -e "s/spacing: 0.002/spacing: 0.001/" -e "s/step: 1.0e-3/step: 1.0e-4/" -e "s/end: 1.2/end: 0.005/" \
    "$here/cases/ldd_dam_break_bingham.yaml" > "$out/dam1.yaml"
grep -q "end: 0.3}" "$out/dam2.yaml" && grep -q "end: 0.02}" "$out/slump.yaml" &&
  grep -q "spacing: 0.001}" "$out/dam1.yaml" && grep -q "step: 1.0e-4, end: 0.005}" "$out/dam1.yaml" ||
  { echo "the case files no longer have the lines this script edits" >&2; exit 2; }
bandwidth() {
  echo "memory bandwidth ($1):"
  "$build/bin/bench_ldd" bandwidth | tail -4
}
for deck in ${only:-dam2 slump dam1}; do
  bandwidth "before $deck"
  best="" best_ms=""
  for r in $(seq 1 "$repeat"); do
    run="$out/${deck}_t2_$r"
    rm -rf "$run"
    OMP_NUM_THREADS=2 "$build/bin/bench_ldd" run "$out/$deck.yaml" "$run" > "$run.log" 2>&1
    ms=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['ms_per_step'])" "$run/summary.json")
    if [ -z "$best" ] || python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < float(sys.argv[2]) else 1)" "$ms" "$best_ms"; then
      best=$run best_ms=$ms
    fi
  done
  # The floor right after the runs it is compared with: the host's speed drifts over minutes.
  OMP_NUM_THREADS=2 "$build/bin/bench_ldd" floor "$best"
  rm -rf "$out/${deck}_t1"
  OMP_NUM_THREADS=1 "$build/bin/bench_ldd" run "$out/$deck.yaml" "$out/${deck}_t1" > "$out/${deck}_t1.log" 2>&1
  python3 - "$out/${deck}_t1" "$best" <<'PY'
import json, sys
for run in sys.argv[1:]:
    s = json.load(open(run + "/summary.json"))
    phases = ", ".join(f"{k} {1e3 * v / s['steps']:.1f}" for k, v in s["phase_seconds"].items())
    it = s["iterations_per_step"]
    print(f"| {run} | {s['nodes']} | {s['threads']} | {s['steps']} | {s['ms_per_step']:.1f} | "
          f"{it['pressure']:.2f} / {it['velocity']:.2f} | {phases} |")
PY
done
bandwidth after
