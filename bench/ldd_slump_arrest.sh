#!/usr/bin/env bash
# 3D slumps of a Bingham material run to rest, against the yield-stress theories of their mould
# (docs/ldd.md, "Arrest"): a cylinder against Pashias et al. (1996), s′ = s/H = 1 − 2τ′(1 − ln 2τ′)
# with τ′ = τ₀/(ρgH) (ldd::pashias_slump; also printed with the von Mises factor √3 in place of 2,
# ldd::von_mises_cylinder_slump); a cone against Roussel & Coussot's (2005) pancake
# spread, τ₀ = 225ρgΩ²/(128π²R⁵) (ldd::roussel_coussot_spread).
#
#   bench/ldd_slump_arrest.sh [BUILD_DIR] [OUT_DIR] [--case FILE] [--ratios "0.05 0.1 ..."]
#                             [--yield-stresses "20 50 ..."] [--spacing M] [--step S] [--end S]
#                             [--regularization S] [--viscosity PA_S] [--lift-velocity M_S]
#                             [--viscous-stress laplacian|full] [--solver "KEY: VALUE, ..."]
#                             [--stop-at-arrest S]
#
# One run of the case (default cases/ldd_slump_pashias.yaml: H = D = 0.1 m, Δ = 5 mm, δt = 1e-3 s,
# 2 s, m = 1000 s, μ_p 20 Pa·s, about 1.5 min on two threads) per yield stress, given as τ₀ [Pa]
# or as τ′ (τ₀ = τ′ρgH with the case's ρ and H), through bench_ldd run (the code of `rheosim run`,
# OpenMP's default threads). A finished run in OUT_DIR is reused. Prints per run the theory and
# the run's slump or spread, the height's and diameter's change over the last tenth of the run, the yielded
# fraction, the largest stress over τ₀ and whether the run ended arrested (summary.json
# largest_stress_ratio, arrested), the volume drift and the cost. --stop-at-arrest S sets
# time.stop_at_arrest: the run ends once the yield test has held for S seconds.
set -euo pipefail
build=${1:-build}
out=${2:-results/ldd_slump_arrest}
shift $(( $# > 2 ? 2 : $# )) || true
here=$(cd "$(dirname "$0")/.." && pwd)
case_file="$here/cases/ldd_slump_pashias.yaml" ratios="" stresses="" overrides=() tag=""
override() {  # override KEY VALUE: the deck's `KEY: number` becomes `KEY: VALUE`
  overrides+=("-e" "s/\b$1: [0-9.e-]*/$1: $2/")
  tag="${tag}_$1$2"
}
while [ $# -gt 0 ]; do
  case "$1" in
    --case) case_file=$2; shift 2 ;;
    --ratios) ratios=$2; shift 2 ;;
    --yield-stresses) stresses=$2; shift 2 ;;
    --spacing) override spacing "$2"; shift 2 ;;
    --step) override step "$2"; shift 2 ;;
    --end) override end "$2"; shift 2 ;;
    --regularization) override regularization "$2"; shift 2 ;;
    --viscosity) override plastic_viscosity "$2"; shift 2 ;;
    --lift-velocity) override lift_velocity "$2"; shift 2 ;;
    --viscous-stress)  # solver.viscous_stress (a word, not a number)
      overrides+=("-e" "s/^solver: {/solver: {viscous_stress: $2, /")
      tag="${tag}_viscous_stress_$2"
      shift 2 ;;
    --stop-at-arrest)  # time.stop_at_arrest, after the deck's settle_energy_ratio: 0
      overrides+=("-e" "s/settle_energy_ratio: 0}/settle_energy_ratio: 0, stop_at_arrest: $2}/")
      tag="${tag}_stop_at_arrest$2"
      shift 2 ;;
    --solver)  # more solver keys, "KEY: VALUE, ..."
      overrides+=("-e" "s/^solver: {/solver: {$2, /")
      tag="${tag}_$(echo "$2" | tr -c 'A-Za-z0-9.\n' '_')"
      shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
# τ′ → τ₀ = τ′ρgH with the case's density and mould height.
if [ -n "$ratios" ]; then
  stresses=$(python3 - "$case_file" "$ratios" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
rho = float(re.search(r"density: ([0-9.e+-]+)", text).group(1))
height = float(re.search(r"cone: \{height: ([0-9.e+-]+)", text).group(1))
print(" ".join(repr(float(r) * rho * 9.81 * height) for r in sys.argv[2].split()))
PY
)
fi
if [ -z "$stresses" ]; then
  stresses=$(sed -n 's/.*yield_stress: \([0-9.e-]*\).*/\1/p' "$case_file")
fi
mkdir -p "$out"
runs=()
base=$(basename "$case_file" .yaml)
for stress in $stresses; do
  name="${base}_tau${stress}${tag}"
  sed "${overrides[@]}" -e "s/yield_stress: [0-9.e-]*/yield_stress: ${stress}/" "$case_file" > "$out/$name.yaml"
  if [ ! -f "$out/$name/summary.json" ] || grep -q '"status": "interrupted"' "$out/$name/summary.json"; then
    "$build/bin/bench_ldd" run "$out/$name.yaml" "$out/$name" > "$out/$name.log" 2>&1 || true
  fi
  runs+=("$out/$name")
done
python3 - "${runs[@]}" <<'PY'
import csv, json, os, sys
nan = float("nan")
print(f"{'τ₀ Pa':>8} {'theory':>18} {'LDD':>8} {'diff':>8} {'last tenth: Δh, Δd':>20} {'yielded':>8} "
      f"{'σmax/τ₀':>8} {'arrested':>8} {'drift':>7} {'ms/step':>8}  status")
for run in sys.argv[1:]:
    s = json.load(open(os.path.join(run, "summary.json")))
    rows = list(csv.reader(open(os.path.join(run, "spread.csv"))))
    col = {h.split(" ")[0]: k for k, h in enumerate(rows[0])}
    rows = [[float(v) for v in r] for r in rows[1:]]
    last = [r for r in rows if r[0] >= 0.9 * rows[-1][0]]
    dh = last[-1][col["height"]] - last[0][col["height"]]
    dd = last[-1][col["diameter"]] - last[0][col["diameter"]]
    yield_stress = float(open(run + ".yaml").read().split("yield_stress: ")[1].split(",")[0])
    if "pashias" in s:
        p = s["pashias"]
        theory, value = f"s′ {p['slump']:.4f} (τ′ {p['yield_stress_ratio']:.3g})", p["measured_slump"]
        # von Mises: s′ with √3τ′ for 2τ′ (ldd::von_mises_cylinder_slump; absent from runs reused
        # from a build before it)
        vm = p.get("von_mises_slump")
        diff = f"{p['difference']:+8.4f}" + (f" (von Mises s′ {vm:.4f}: {value - vm:+.4f})" if vm is not None else "")
    elif "roussel_coussot" in s:
        r = s["roussel_coussot"]
        theory, value = f"spread {r['diameter']:.4f} m", s["final_spread"]
        diff = f"{100 * r['relative_error']:+7.1f}%"
    else:
        theory, value, diff = "none", nan, ""
    # The τ₀ the mould's formula reads from the slump or spread, as a slump test would.
    implied = s.get("pashias", s.get("roussel_coussot", {})).get("implied_yield_stress")
    diff += f", read as τ₀ {implied:.4g} Pa" if implied is not None else ""
    print(f"{yield_stress:8.4g} {theory:>18} {value:8.4f} {diff:>8} {1e3 * dh:+7.2f}, {1e3 * dd:+7.2f} mm "
          f"{s['yielded_fraction'] or 0:8.3f} {s.get('largest_stress_ratio') or nan:8.4f} {str(s['arrested']):>8} "
          f"{100 * s['volume_drift']:6.2f}% {s['ms_per_step']:8.1f}  "
          f"{s['status']} at {s['time']:.3g} s")
PY
