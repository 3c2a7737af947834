#!/usr/bin/env bash
# LDD §4.3 dam break at the seed's four (Δ, δt) pairs, assembled into LDD Table 1's layout with
# the error of each run against the experiment (docs/ldd.md, docs/performance.md LDD sections).
#
#   bench/ldd_dam_break_table1.sh [BUILD_DIR] [OUT_DIR] [PAIRS...]
#   PAIRS default: "0.002:1e-3 0.002:1e-4 0.001:1e-3 0.001:1e-4" (Δ in m : δt in s); a pair
#   may end in ":FLAGS", a comma-separated list of `plain` (`solver.pressure_amg: plain`) and
#   `laplacian` (`solver.viscous_stress: laplacian`, the seed's ∇·(μ∇u), instead of the shipped
#   case's whole stress), e.g. 0.001:1e-4:plain or 0.002:1e-3:laplacian
#
# Each run goes through ldd::run_case (bench_ldd run, the same code as `rheosim run`). Costs on
# the 2-core machine (docs/ldd.md, Cost): Δ = 2 mm, δt = 1e-3 about 4–12 min; Δ = 2 mm, δt = 1e-4
# and Δ = 1 mm, δt = 1e-3 about 1 h each; Δ = 1 mm, δt = 1e-4 (12 000 steps of 203 210 nodes)
# several hours — run it on a quiet machine. Each run writes checkpoint.h5 at every
# frame and every 10 minutes: run the script again after a kill and it goes on from there.
set -euo pipefail
build=${1:-build-ldd}
out=${2:-results/ldd_table1}
shift $(( $# > 2 ? 2 : $# )) || true
pairs=${*:-"0.002:1e-3 0.002:1e-4 0.001:1e-3 0.001:1e-4"}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
for pair in $pairs; do
  IFS=: read -r dx dt flags <<< "$pair"
  name="dx${dx}_dt${dt}${flags:+_${flags//,/_}}"
  edits=(-e "s/spacing: 0.002/spacing: ${dx}/" -e "s/step: 1.0e-3/step: ${dt}/")
  for flag in ${flags//,/ }; do
    case "$flag" in
      plain) edits+=(-e "s/^solver: {velocity_tolerance: 1.0e-6/solver: {velocity_tolerance: 1.0e-6, pressure_amg: plain/") ;;
      laplacian) edits+=(-e "/^solver:/ s/viscous_stress: full/viscous_stress: laplacian/") ;;
      *) echo "unknown flag $flag in $pair (plain, laplacian)" >&2; exit 2 ;;
    esac
  done
  # Kept once written: a run goes on from its checkpoint only with the very deck that started it.
  [ -f "$out/$name.yaml" ] || sed "${edits[@]}" "$here/cases/ldd_dam_break_bingham.yaml" > "$out/$name.yaml"
  # A run that was stopped (killed, or status interrupted) goes on from its checkpoint.h5.
  if ! grep -qE '"status": "(end_time|diverged)"' "$out/$name/summary.json" 2>/dev/null; then
    "$build/bin/bench_ldd" run "$out/$name.yaml" "$out/$name" >> "$out/$name.log" 2>&1 || true
  fi
done
python3 - "$out" $pairs <<'PY'
import csv, json, os, sys
out, pairs = sys.argv[1], sys.argv[2:]
times = [0.09, 0.23, 0.38, 0.56, 0.74, 1.14]
exp = [0.103, 0.198, 0.297, 0.399, 0.499, 0.596]
cols = []
for p in pairs:
    dx, dt, *flags = p.split(':')
    name = f"dx{dx}_dt{dt}" + ("_" + flags[0].replace(",", "_") if flags else "")
    f = os.path.join(out, name, "table1.csv")
    rows = list(csv.reader(open(f)))[1:] if os.path.exists(f) else []
    label = f"Δ={float(dx)*1e3:g} mm δt={dt}" + (f" ({flags[0]})" if flags else "")
    cols.append((label, [float(r[2]) for r in rows] if rows else [float('nan')] * 6))
print("| Time (s) | Exp. Data | " + " | ".join(c[0] for c in cols) + " |")
print("| --- | --- | " + " | ".join("---" for _ in cols) + " |")
for q, t in enumerate(times):
    print(f"| {t:.2f} | {exp[q]:.3f} | " + " | ".join(f"{c[1][q]:.3f}" for c in cols) + " |")
err = []
for _, v in cols:
    d = [abs(a - b) for a, b in zip(v, exp) if a == a]
    err.append(f"{(sum(x*x for x in d)/len(d))**0.5:.3f} / {max(d):.3f}" if d else "-")
print("| RMS / max error (m) | | " + " | ".join(err) + " |")
PY
