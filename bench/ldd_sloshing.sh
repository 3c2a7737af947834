#!/usr/bin/env bash
# First sloshing mode in a 2D tank against linear theory, ω² = g k tanh(kH), k = π/W: the surface
# height at the left wall over time, the run's status, volume drift and its own comparison with the
# theory (summary.json "sloshing": the period from the zero crossings about H while the run is
# still the linear wave) (docs/ldd.md, "Water at rest and sloshing").
#
#   bench/ldd_sloshing.sh [BUILD_DIR] [OUT_DIR] [--viscosity PA_S] [--amplitude M] [--step S]
#                         [--stability-probe N] [--solver "KEY: VALUE, ..."]
#
# Runs cases/ldd_sloshing_water.yaml (W = 0.1 m, H = 0.05 m, Δ = 1 mm: 5 000 nodes, seconds) with
# the given overrides through bench_ldd run (the code of `rheosim run`). --amplitude 0 is the
# resting column.
set -euo pipefail
build=${1:-build}
out=${2:-results/ldd_sloshing}
shift $(( $# > 2 ? 2 : $# )) || true
viscosity=1.0e-3 amplitude=0.001 step=1.0e-3 probe=() solver=""
while [ $# -gt 0 ]; do
  case "$1" in
    --viscosity) viscosity=$2; shift 2 ;;
    --amplitude) amplitude=$2; shift 2 ;;
    --step) step=$2; shift 2 ;;
    --stability-probe) probe=(--stability-probe "$2"); shift 2 ;;
    --solver) solver=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
here=$(cd "$(dirname "$0")/.." && pwd)
name="mu${viscosity}_a${amplitude}_dt${step}$(echo "${solver:+_$solver}" | tr -d ' ,:' )"
mkdir -p "$out"
# --solver replaces the case's solver keys after velocity_tolerance.
sed -e "s/viscosity: 1.0e-3/viscosity: ${viscosity}/" -e "s/wave_amplitude: [0-9.e-]*/wave_amplitude: ${amplitude}/" \
    -e "s/step: 1.0e-3/step: ${step}/" \
    ${solver:+-e "s/^solver: {velocity_tolerance: 1.0e-6[^}]*}/solver: {velocity_tolerance: 1.0e-6, $solver}/"} \
    "$here/cases/ldd_sloshing_water.yaml" > "$out/$name.yaml"
rm -rf "${out:?}/$name"
"$build/bin/bench_ldd" run "$out/$name.yaml" "$out/$name" "${probe[@]}" > "$out/$name.log" 2>&1 || true
python3 - "$out/$name" <<'PY'
import csv, json, os, sys
run = sys.argv[1]
H = 0.05
rows = list(csv.reader(open(os.path.join(run, "column.csv"))))
col = {h.split(" ")[0]: k for k, h in enumerate(rows[0])}
rows = [[float(v) for v in r] for r in rows[1:]]
t = [r[col["time"]] for r in rows]
h = [r[col["left_wall_height"]] for r in rows]
s = json.load(open(os.path.join(run, "summary.json")))
print(f"{run}: status {s['status']} at t = {t[-1]:.4g} s; max volume drift {100 * s['volume_drift']:.2f} %; "
      f"{s['ms_per_step']:.1f} ms/step")
if s.get("message"):
    print(s["message"])
growth = col.get("step_map_growth")
for i in range(0, len(t), max(1, len(t) // 16)):
    line = f"  t = {t[i]:.3f} s  left-wall height − H = {1e3 * (h[i] - H):+.3f} mm  KE {rows[i][col['kinetic_energy']]:.3g} J/m"
    if growth is not None and rows[i][growth] > 0:
        line += f"  step-map growth {rows[i][growth]:.4f} at ({rows[i][col['step_map_node_x']]:.4f}, {rows[i][col['step_map_node_y']]:.4f})"
    print(line)
# The period is the run's own comparison (summary.json "sloshing", ldd/src/column_references.cpp):
# zero crossings of the left-wall elevation about H up to the first time the kinetic energy
# exceeds 1.5 E, E = rho g A^2 W / 4 the linear wave's energy.
kinetic = [r[col["kinetic_energy"]] for r in rows]
c = s.get("sloshing")
if c is None:
    print(f"resting column: kinetic energy {kinetic[-1]:.3g} J/m at the end, {max(kinetic):.3g} J/m at most")
else:
    span = f"up to t = {c['compared_until']:.3f} s" + (" (kinetic energy above 1.5 E after)"
                                                      if c["compared_until"] < t[-1] else "")
    if c["measured_period"] is not None:
        print(f"period {c['measured_period']:.4f} s from {c['crossings']} zero crossings {span}; linear theory "
              f"{c['period']:.4f} s ({100 * c['relative_error']:+.1f} %); first crossing {c['first_crossing']:.4f} s "
              f"(theory {c['period'] / 4:.4f} s)")
    else:
        first = f", first {c['first_crossing']:.4f} s" if c["first_crossing"] is not None else ""
        print(f"no period measured ({c['crossings']} zero crossings {span}{first}); linear theory {c['period']:.4f} s")
PY
