#!/usr/bin/env bash
# First sloshing mode in a 2D tank against linear theory, ω² = g k tanh(kH), k = π/W: the surface
# height at the left wall over time, its period from the zero crossings while the run is still
# the linear wave, the run's status, energy and volume drift (docs/ldd.md, "Water column").
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
import csv, json, math, os, sys
run = sys.argv[1]
W, H, g = 0.1, 0.05, 9.81
rows = list(csv.reader(open(os.path.join(run, "column.csv"))))
col = {h.split(" ")[0]: k for k, h in enumerate(rows[0])}
rows = [[float(v) for v in r] for r in rows[1:]]
t = [r[col["time"]] for r in rows]
h = [r[col["left_wall_height"]] for r in rows]
k = math.pi / W
period = 2 * math.pi / math.sqrt(g * k * math.tanh(k * H))
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
# Zero crossings of the left-wall elevation about its mean, up to the first time the kinetic
# energy exceeds 1.5 E, E = ρgA²W/4 the linear wave's energy (past that the run is no longer the
# linear wave: a diverging run's last crossings are noise).
case = open(run + ".yaml").read()
amplitude = float(case.split("wave_amplitude: ")[1].split("}")[0].split(",")[0])
density = float(case.split("density: ")[1].split("\n")[0])
wave_energy = density * g * amplitude ** 2 * W / 4
kinetic = [r[col["kinetic_energy"]] for r in rows]
valid = next((q for q, e in enumerate(kinetic) if amplitude > 0 and e > 1.5 * wave_energy), len(t))
mean = sum(h[valid // 2:valid]) / max(1, valid - valid // 2) if s["status"] == "end_time" else H
cross = [t[i - 1] + (t[i] - t[i - 1]) * (mean - h[i - 1]) / (h[i] - h[i - 1])
         for i in range(1, valid) if (h[i - 1] - mean) * (h[i] - mean) < 0]
span = f"up to t = {t[valid - 1]:.3f} s" + (" (kinetic energy above 1.5 E after)" if valid < len(t) else "")
if amplitude == 0:
    print(f"resting column: kinetic energy {kinetic[-1]:.3g} J/m at the end, {max(kinetic):.3g} J/m at most")
elif len(cross) >= 3:
    measured = 2 * (cross[-1] - cross[0]) / (len(cross) - 1)
    print(f"period {measured:.4f} s from {len(cross)} zero crossings {span}; linear theory {period:.4f} s "
          f"({100 * (measured / period - 1):+.1f} %); first crossing {cross[0]:.4f} s (theory {period / 4:.4f} s)")
else:
    print(f"no period measured ({len(cross)} zero crossings {span}); linear theory {period:.4f} s")
PY
