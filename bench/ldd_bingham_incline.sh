#!/usr/bin/env bash
# A Bingham layer sliding down an incline against its analytic solution (docs/ldd.md, "The
# deposit's shape"): under gravity with a slope component g_x the basal stress of a layer h thick
# is ρ g_x h; above h_c = τ₀/(ρ g_x) the part below h − h_c shears (no slip at the floor) under a
# rigid plug that moves at u_p = ρ g_x (h − h_c)²/(2 μ_p). The script releases layers
# LAYER·Δ thicker than h_c (the dam-break scene under a tilted gravity, gravity [2.0, -9.6]:
# h_c = 10 mm for the 2D arrest's material, ρ 1000 kg/m³, μ_p 10 Pa·s, τ₀ 20 Pa, m = 1000 s)
# and prints the plug velocity (the mean x velocity of the top row of fluid nodes between
# x = −0.22 and −0.12 m, away from the back wall and the front) at 0.1, 0.2 and 0.3 s against
# u_p, and the yield stress the last one implies, τ = ρ g_x (h − √(2 μ_p u/(ρ g_x))).
#
#   bench/ldd_bingham_incline.sh [BUILD_DIR] [OUT_DIR] [--spacing M] [--layers "1 2 3 4"]
#                                [--solver "KEY: VALUE, ..."]
#
# One thread, through bench_ldd run (the code of `rheosim run`); Δ = 2.5 mm: seconds a layer.
set -euo pipefail
build=${1:-build}
out=${2:-results/ldd_bingham_incline}
shift $(( $# > 2 ? 2 : $# )) || true
spacing=0.0025 layers="1 2 3 4" solver=""
while [ $# -gt 0 ]; do
  case "$1" in
    --spacing) spacing=$2; shift 2 ;;
    --layers) layers=$2; shift 2 ;;
    --solver) solver=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
runs=()
for layer in $layers; do
  height=$(python3 -c "print(repr(0.01 + $layer * $spacing))")
  name="dx${spacing}_layer${layer}$(echo "${solver:+_$solver}" | tr -d ' ,:')"
  cat > "$out/$name.yaml" <<EOF
kind: ldd
dimension: 2
scene: {type: dam_break, reservoir: [0.3, $height], channel_length: 0.4}
fluid:
  density: 1000
  rheology: {model: bingham, plastic_viscosity: 10.0, yield_stress: 20.0, regularization: 1000}
gravity: [2.0, -9.6]
resolution: {spacing: $spacing}
time: {step: 1.0e-3, end: 0.3}
solver: {velocity_tolerance: 1.0e-6, threads: 1${solver:+, $solver}}
output: {probe_interval: 0.01, frame_interval: 0.1}
EOF
  rm -rf "${out:?}/$name"
  "$build/bin/bench_ldd" run "$out/$name.yaml" "$out/$name" > "$out/$name.log" 2>&1 || true
  runs+=("$out/$name")
done
python3 - "$here/bench" "$spacing" "${runs[@]}" <<'PY'
import glob, math, os, re, sys
sys.path.insert(0, sys.argv[1])
from ldd_bulk_density import read_vtk_fields
spacing = float(sys.argv[2])
rho, mu_p, tau0, g_x = 1000.0, 10.0, 20.0, 2.0
h_c = tau0 / (rho * g_x)
print(f"Δ = {spacing} m, h_c = {h_c} m; plug velocity in mm/s at 0.1 / 0.2 / 0.3 s against u_p")
print(f"{'h (m)':>8} {'(h − h_c)/Δ':>11} {'u_p':>8} {'LDD 0.1 s':>10} {'0.2 s':>8} {'0.3 s':>8} {'vs u_p':>8} "
      f"{'implied τ':>14}   bottom row's stress (exact) at 0.3 s")
for run in sys.argv[3:]:
    case = open(run + ".yaml").read()
    height = float(re.search(r"reservoir: \[0.3, ([0-9.e-]+)\]", case).group(1))
    u_p = rho * g_x * (height - h_c) ** 2 / (2 * mu_p)
    if not os.path.exists(os.path.join(run, "summary.json")):  # refused or failed: say why
        print(f"{height:8.4f} {(height - h_c) / spacing:11.2f} no run: {open(run + '.log').read().strip().splitlines()[-1]}")
        continue
    plug = []
    for frame in sorted(glob.glob(os.path.join(run, "frames", "nodes_*.vtk")))[1:]:
        fields, n = read_vtk_fields(frame)
        points, velocity, kind = fields["points"], fields["velocity"], fields["kind"]
        middle = [i for i in range(n) if kind[i] in (0, 1) and -0.22 < points[3 * i] < -0.12]
        top = max(points[3 * i + 1] for i in middle)
        row = [velocity[3 * i] for i in middle if points[3 * i + 1] > top - 0.5 * spacing]
        plug.append(sum(row) / len(row))
    # The last frame's bottom row: its stress μ(γ̇)γ̇ against the exact ρ g_x (h − y) at its mean height.
    bottom = [i for i in middle if points[3 * i + 1] < spacing]
    y = sum(points[3 * i + 1] for i in bottom) / len(bottom)
    stress = sum(fields["viscosity"][i] * fields["shear_rate"][i] for i in bottom) / len(bottom)
    exact = rho * g_x * (height - y)
    u = plug[-1]
    implied = rho * g_x * (height - math.sqrt(2 * mu_p * max(u, 0.0) / (rho * g_x)))
    print(f"{height:8.4f} {(height - h_c) / spacing:11.2f} {1e3 * u_p:8.3f} "
          + " ".join(f"{1e3 * v:8.3f}" for v in plug)
          + f" {100 * (u / u_p - 1):+7.1f}% {implied:7.2f} Pa ({100 * (implied / tau0 - 1):+.1f} %)"
          + f"   {stress:.2f} Pa ({exact:.2f})")
PY
