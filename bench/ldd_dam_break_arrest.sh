#!/usr/bin/env bash
# A 2D Bingham dam break run until it stops, against the shallow yield-stress arrest
# h(s) = √(2τ₀(ℓ − s)/(ρg)) (ldd::ThinFilmArrest; docs/ldd.md, "Arrest"): the front over time, the
# final front and the final profile beside the theory's, the kinetic energy and volume drift.
#
#   bench/ldd_dam_break_arrest.sh [BUILD_DIR] [OUT_DIR] [--spacing M] [--step S] [--end S]
#                                 [--regularization S] [--solver "KEY: VALUE, ..."] [--stop-at-arrest S]
#
# Runs cases/ldd_dam_break_arrest.yaml (Δ = 2.5 mm, δt = 1e-3 s, m = 1000 s, 12 s: about 2 min on
# one thread) with the given overrides through bench_ldd run (the code of `rheosim run`).
# --stop-at-arrest S sets time.stop_at_arrest: the run ends once the yield test has held for S seconds.
set -euo pipefail
build=${1:-build}
out=${2:-results/ldd_dam_break_arrest}
shift $(( $# > 2 ? 2 : $# )) || true
spacing=0.0025 step=1.0e-3 end=12.0 regularization=1000 solver="" hold=""
while [ $# -gt 0 ]; do
  case "$1" in
    --spacing) spacing=$2; shift 2 ;;
    --step) step=$2; shift 2 ;;
    --end) end=$2; shift 2 ;;
    --regularization) regularization=$2; shift 2 ;;
    --solver) solver=$2; shift 2 ;;
    --stop-at-arrest) hold=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
here=$(cd "$(dirname "$0")/.." && pwd)
name="dx${spacing}_dt${step}_m${regularization}_end${end}${hold:+_hold$hold}$(echo "${solver:+_$solver}" | tr -d ' ,:' )"
mkdir -p "$out"
sed -e "s/spacing: 0.0025/spacing: ${spacing}/" -e "s/step: 1.0e-3, end: 12.0/step: ${step}, end: ${end}${hold:+, stop_at_arrest: $hold}/" \
    -e "s/regularization: 1000}/regularization: ${regularization}}/" \
    -e "s/^solver: {velocity_tolerance: 1.0e-6}/solver: {velocity_tolerance: 1.0e-6, threads: 1${solver:+, $solver}}/" \
    "$here/cases/ldd_dam_break_arrest.yaml" > "$out/$name.yaml"
rm -rf "${out:?}/$name"
"$build/bin/bench_ldd" run "$out/$name.yaml" "$out/$name" > "$out/$name.log" 2>&1 || true
python3 - "$out/$name" <<'PY'
import csv, json, os, sys
run = sys.argv[1]
s = json.load(open(os.path.join(run, "summary.json")))
arrest = s["thin_film_arrest"]
rows = list(csv.reader(open(os.path.join(run, "front.csv"))))
col = {h.split(" ")[0]: k for k, h in enumerate(rows[0])}
rows = [[float(v) for v in r] for r in rows[1:]]
print(f"{run}: status {s['status']} at t = {s['time']:.4g} s, {s['ms_per_step']:.1f} ms/step; "
      f"max volume drift {100 * s['volume_drift']:.2f} %; yielded fraction {s['yielded_fraction']:.3g}, "
      f"largest stress {s.get('largest_stress_ratio') or float('nan'):.4g} τ₀, arrested {s['arrested']}")
for r in rows[:: max(1, len(rows) // 12)] + [rows[-1]]:
    print(f"  t = {r[0]:6.2f} s  front {r[col['front']]:.4f} m  KE {r[col['kinetic_energy']]:.3g} J/m")
# The front's speed over the last tenth of the run: zero once it has stopped.
last = [r for r in rows if r[0] >= 0.9 * rows[-1][0]]
speed = (last[-1][col["front"]] - last[0][col["front"]]) / max(1e-12, last[-1][0] - last[0][0])
print(f"front speed over the last tenth of the run: {speed:.3g} m/s")
print(f"final front {s['final_spread']:.4f} m; thin-film arrest {arrest['front']:.4f} m past the gate "
      f"(length {arrest['length']:.4f} m from the back wall); runout {100 * arrest['relative_error']:+.1f} %")
if arrest.get("fitted_yield_stress") is not None:  # runs of older builds have no fit
    print(f"final surface read as a shallow arrest: yield stress {arrest['fitted_yield_stress']:.2f} Pa, "
          f"runout {arrest['fitted_length']:.4f} m from the back wall "
          f"({100 * (arrest['fitted_length'] / arrest['length'] - 1):+.1f} %), "
          f"rms height error {1e3 * arrest['fitted_rms_height_error']:.2f} mm")
# The final profile (profile.csv: the top of the fluid nodes per Δ column) beside the theory's.
shape = list(csv.reader(open(os.path.join(run, "profile.csv"))))[1:]
print("final profile, x from the gate:")
for r in shape[:: max(1, len(shape) // 12)]:
    x, h, theory = (float(v) for v in r)
    print(f"  x = {x:+.4f} m  h {h:.4f} m  thin film {theory:.4f} m")
PY
