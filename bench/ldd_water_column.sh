#!/usr/bin/env bash
# 2D water column collapse against Martin & Moyce (1952): front Z = x/a against T = t√(2g/a),
# with the run's energy balance and volume drift (docs/ldd.md, "Water column").
#
#   bench/ldd_water_column.sh [BUILD_DIR] [OUT_DIR] [--spacing M] [--step S] [--gradient G]
#                             [--pbd-velocity V] [--pbd-sweeps N] [--dry-walls include|exclude|extrapolate]
#                             [--pbd-surface full|tangential] [--surface-detection local|umbrella]
#                             [--divergence-probe]
#
# Runs cases/ldd_water_column.yaml (a = 0.1 m, Δ = 2 mm, δt = 2.5e-4 s: about 15 s on two
# threads) with the given overrides through bench_ldd run (the code of `rheosim run`).
set -euo pipefail
build=${1:-build}
out=${2:-results/ldd_water_column}
shift $(( $# > 2 ? 2 : $# )) || true
spacing=0.002 step=2.5e-4 gradient=surface_anchored pbd_velocity=none pbd_sweeps=3 dry_walls=include pbd_surface=tangential surface_detection=local probe=()
while [ $# -gt 0 ]; do
  case "$1" in
    --spacing) spacing=$2; shift 2 ;;
    --step) step=$2; shift 2 ;;
    --gradient) gradient=$2; shift 2 ;;
    --pbd-velocity) pbd_velocity=$2; shift 2 ;;
    --pbd-sweeps) pbd_sweeps=$2; shift 2 ;;
    --dry-walls) dry_walls=$2; shift 2 ;;
    --pbd-surface) pbd_surface=$2; shift 2 ;;
    --surface-detection) surface_detection=$2; shift 2 ;;
    --divergence-probe) probe=(--divergence-probe); shift ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
here=$(cd "$(dirname "$0")/.." && pwd)
name="dx${spacing}_dt${step}_${gradient}_${pbd_velocity}_sweeps${pbd_sweeps}$([ "$dry_walls" = include ] || echo "_$dry_walls")$([ "$pbd_surface" = tangential ] || echo "_pbd_$pbd_surface")$([ "$surface_detection" = local ] || echo "_$surface_detection")"
mkdir -p "$out"
sed -e "s/spacing: 0.002/spacing: ${spacing}/" -e "s/step: 2.5e-4/step: ${step}/" \
    -e "s/gradient: surface_anchored, pbd_velocity: none, pbd_surface: tangential/gradient: ${gradient}, pbd_velocity: ${pbd_velocity}, pbd_sweeps: ${pbd_sweeps}, dry_walls: ${dry_walls}, pbd_surface: ${pbd_surface}, surface_detection: ${surface_detection}/" \
    "$here/cases/ldd_water_column.yaml" > "$out/$name.yaml"
rm -rf "${out:?}/$name"
"$build/bin/bench_ldd" run "$out/$name.yaml" "$out/$name" "${probe[@]}" > "$out/$name.log" 2>&1 || true
python3 - "$out/$name" <<'PY'
import csv, json, math, os, sys
run = sys.argv[1]
a, g = 0.1, 9.81
# Martin & Moyce (1952), Phil. Trans. R. Soc. A 244, 312, Fig. 3: n² = 2, a = 2.25 in (T, Z).
mm = [(0.832, 1.217), (1.219, 1.474), (1.997, 2.292), (2.547, 2.995), (3.345, 4.134)]
rows = list(csv.reader(open(os.path.join(run, "front.csv"))))
head, rows = rows[0], [[float(v) for v in r] for r in rows[1:]]
col = {h.split(" ")[0]: k for k, h in enumerate(head)}
t = [r[col["time"]] for r in rows]
z = [(r[col["front"]] + a) / a for r in rows]
print(f"{run}: front Z = x/a against Martin & Moyce (n² = 2)")
print("| T | Z (Martin & Moyce) | Z (LDD) | difference |")
print("| --- | --- | --- | --- |")
for T, Zmm in mm:
    tt = T / math.sqrt(2 * g / a)
    if tt > t[-1]:
        print(f"| {T:.3f} | {Zmm:.3f} | not reached | |")
        continue
    k = next(i for i in range(1, len(t)) if t[i] >= tt)
    Z = z[k - 1] + (z[k] - z[k - 1]) * (tt - t[k - 1]) / (t[k] - t[k - 1])
    print(f"| {T:.3f} | {Zmm:.3f} | {Z:.3f} | {100 * (Z / Zmm - 1):+.1f} % |")
s = json.load(open(os.path.join(run, "summary.json")))
print(f"status {s['status']} at t = {t[-1]:.4g} s; energy gain {100 * s['energy_gain']:.2f} % of the potential "
      f"energy released; max volume drift {100 * s['volume_drift']:.2f} %; {s['ms_per_step']:.1f} ms/step")
if s.get("message"):
    print(s["message"])
if "bulk_divergence" in col:
    # --divergence-probe: the bulk's mean <div u*> before and <div u> after the projection.
    print("| t [s] | bulk mean div u* [1/s] | bulk mean div u [1/s] |")
    print("| --- | --- | --- |")
    for k in range(1, len(t), max(1, len(t) // 12)):
        print(f"| {t[k]:.3f} | {rows[k][col['bulk_divergence_predicted']]:+.3g} | {rows[k][col['bulk_divergence']]:+.3g} |")
PY
