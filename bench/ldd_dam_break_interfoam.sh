#!/usr/bin/env bash
# An LDD dam break against OpenFOAM's interFoam, the independent solver (docs/ldd.md, "Dam break
# against interFoam"): the same reservoir, channel, fluid and cell size, the mass front of each
# at the experiment's times, beside the experiment (LDD Table 1 for a Bingham material, Martin &
# Moyce for the water column).
#
#   bench/ldd_dam_break_interfoam.sh [BUILD_DIR] [OUT_DIR] [--case FILE] [--spacing M] [--step S]
#                                    [--viscous-stress laplacian|full] [--max-courant C] [--ldd-run DIR]
#                                    [--reference table1|martin_moyce|thin_film]
#
# FILE defaults to cases/ldd_dam_break_bingham.yaml; --spacing and --step replace its
# `resolution.spacing` and `time.step`, --viscous-stress sets its `solver.viscous_stress` (the
# LDD run's, `full` in the shipped Bingham case; interFoam always has the full stress)
# (OUT/case.yaml is the deck both solvers run). The interFoam case is written by
# `rheosim export-openfoam FILE OUT/interfoam` and run there (one core; the 2 mm Bingham case,
# 112 500 cells, about 15–25 min); a finished run is kept and not run again while the export
# it was made from is unchanged. The LDD run is
# `rheosim run FILE --out OUT/ldd` on one thread unless --ldd-run names a finished run folder.
# --reference picks what the fronts are set beside: LDD Table 1's experiment (the default for a
# yield-stress law), Martin & Moyce (the default otherwise) or `thin_film`, the shallow arrest of
# a yield-stress reservoir (cases/ldd_dam_break_arrest.yaml): the fronts over the whole run, their
# speed over its last tenth, and the final free surface of both solvers (interFoam's height is a
# column's sum of alpha times the cell size) beside the arrest's h(x) from the LDD run's profile.csv.
# Needs OpenFOAM v1912 (Debian's openfoam package, WM_PROJECT_DIR=/usr/share/openfoam).
set -euo pipefail
build=${1:-build}
out=${2:-results/ldd_dam_break_interfoam}
shift $(( $# > 2 ? 2 : $# )) || true
here=$(cd "$(dirname "$0")/.." && pwd)
case_file=$here/cases/ldd_dam_break_bingham.yaml courant=0.5 ldd_run= spacing= step= viscous_stress= reference=
while [ $# -gt 0 ]; do
  case "$1" in
    --case) case_file=$2; shift 2 ;;
    --spacing) spacing=$2; shift 2 ;;
    --step) step=$2; shift 2 ;;
    --viscous-stress) viscous_stress=$2; shift 2 ;;
    --max-courant) courant=$2; shift 2 ;;
    --ldd-run) ldd_run=$2; shift 2 ;;
    --reference) reference=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
case "$reference" in
  ''|table1|martin_moyce|thin_film) ;;
  *) echo "--reference must be table1, martin_moyce or thin_film, not '$reference'" >&2; exit 2 ;;
esac
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}
mkdir -p "$out"
sed -E ${spacing:+-e "s/spacing: [0-9.eE+-]+/spacing: $spacing/"} ${step:+-e "s/step: [0-9.eE+-]+/step: $step/"} \
    -e '' "$case_file" > "$out/case.yaml.new"
if [ -n "$viscous_stress" ]; then  # replace the deck's choice, or add one to its solver: line
  if grep -q "^solver:.*viscous_stress: " "$out/case.yaml.new"; then
    sed -i -E "/^solver:/ s/viscous_stress: [a-z]+/viscous_stress: $viscous_stress/" "$out/case.yaml.new"
  else
    sed -i -E "s/^solver: \{/solver: {viscous_stress: $viscous_stress, /" "$out/case.yaml.new"
  fi
  if ! grep -q "^solver:.*viscous_stress: $viscous_stress" "$out/case.yaml.new"; then
    echo "--viscous-stress needs a 'solver: {' line in $case_file" >&2; exit 2
  fi
fi
# A changed deck starts the LDD run afresh; the interFoam run only when its exported case changes
# (solver keys of the LDD deck do not reach it; its mesh, fields and dictionaries are compared, not
# rheosim.json, README and the header line, which name the deck and the revision).
# OUT/interfoam.export keeps the export as written.
if ! cmp -s "$out/case.yaml.new" "$out/case.yaml"; then rm -rf "$out/ldd"; fi
mv "$out/case.yaml.new" "$out/case.yaml"
case_file=$out/case.yaml
foam=$out/interfoam
rm -rf "$out/interfoam.new"
"$build/bin/rheosim" export-openfoam "$case_file" "$out/interfoam.new" --max-courant "$courant" --quiet
if ! grep -q '^End' "$foam/log.interFoam" 2>/dev/null || ! diff -rq -I "Written by rheosim" -x rheosim.json -x README "$out/interfoam.new" "$out/interfoam.export" > /dev/null 2>&1; then
  rm -rf "$foam" "$out/interfoam.export"
  cp -r "$out/interfoam.new" "$out/interfoam.export"
  mv "$out/interfoam.new" "$foam"
  (cd "$foam" && blockMesh > log.blockMesh && setFields > log.setFields &&
     { time interFoam > log.interFoam; } 2> time.log)
fi
rm -rf "$out/interfoam.new"
if [ -z "$ldd_run" ]; then
  ldd_run=$out/ldd
  if ! grep -qE '"status": "(end_time|diverged|settled)"' "$ldd_run/summary.json" 2>/dev/null; then
    OMP_NUM_THREADS=1 "$build/bin/rheosim" run "$case_file" --out "$ldd_run" --quiet > "$out/ldd.log" 2>&1 || true
  fi
fi
python3 - "$foam" "$ldd_run" "$case_file" "$out" "$reference" <<'PY'
import csv, glob, json, math, os, re, sys
foam, ldd, case_file, out, reference = sys.argv[1:6]
export = json.load(open(os.path.join(foam, "rheosim.json")))  # written by the export
dx = export["cell_size"]
foam_t, foam_x = [], []
for d in sorted(glob.glob(os.path.join(foam, "postProcessing/front/*")), key=lambda p: float(os.path.basename(p))):
    front = -math.inf
    for f in glob.glob(os.path.join(d, "row*_alpha.water.xy")):
        for line in open(f):
            x, alpha = (float(v) for v in line.split())
            if alpha >= 0.5:
                front = max(front, x + 0.5 * dx)  # the LDD front: largest x of fluid + Δ/2
    foam_t.append(float(os.path.basename(d)))
    foam_x.append(front)
with open(os.path.join(out, "interfoam_front.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["time [s]", "front [m]"])
    w.writerows(zip(foam_t, foam_x))
rows = list(csv.reader(open(os.path.join(ldd, "front.csv"))))
col = {h.split(" ")[0]: k for k, h in enumerate(rows[0])}
ldd_t = [float(r[col["time"]]) for r in rows[1:]]
ldd_x = [float(r[col["front"]]) for r in rows[1:]]

def at(t, v, x):
    if not t or x > t[-1] + 1e-9:
        return math.nan
    k = next((i for i in range(1, len(t)) if t[i] >= x), len(t) - 1)
    w = (x - t[k - 1]) / (t[k] - t[k - 1]) if t[k] > t[k - 1] else 1.0
    return v[k - 1] + w * (v[k] - v[k - 1])

text = open(case_file).read()
a = float(re.search(r"reservoir: \[([0-9.eE+-]+),", text).group(1))  # the reservoir's length
if not reference:
    reference = "table1" if re.search(r"model: *(bingham|herschel_bulkley)", text) else "martin_moyce"


def speed_at_end(t, x):  # mean front speed over the last tenth of the run [m/s]
    k = next(i for i in range(len(t)) if t[i] >= 0.9 * t[-1])
    return (x[-1] - x[k]) / (t[-1] - t[k]) if t[-1] > t[k] else math.nan


if reference == "thin_film":
    arrest = json.load(open(os.path.join(ldd, "summary.json")))["thin_film_arrest"]
    end = min(foam_t[-1], ldd_t[-1])
    print(f"{case_file}: mass front x from the gate [m], cells of {dx} m; the shallow arrest's "
          f"front {arrest['front']:.4f} m (runout {arrest['length']:.4f} m from the back wall)")
    print("| t (s) | interFoam | LDD | LDD vs interFoam |")
    print("| --- | --- | --- | --- |")
    for t in [x for x in (0.25, 0.5, 1.0, 2.0, 4.0, 8.0) if x < end] + [end]:
        xf, xl = at(foam_t, foam_x, t), at(ldd_t, ldd_x, t)
        print(f"| {t:g} | {xf:.4f} | {xl:.4f} | {100 * ((xl + a) / (xf + a) - 1):+.1f} % of the runout |")
    for name, t, x in (("interFoam", foam_t, foam_x), ("LDD", ldd_t, ldd_x)):
        print(f"{name}: runout {x[-1] + a:.4f} m from the back wall at {t[-1]:g} s, "
              f"{100 * ((x[-1] + a) / arrest['length'] - 1):+.1f} % of the shallow arrest's; "
              f"front speed over the last tenth {1e3 * speed_at_end(t, x):.2f} mm/s")
    # interFoam's final surface: each cell column's liquid height, the sum of alpha times the cell.
    last = max((d for d in os.listdir(foam) if re.fullmatch(r"[0-9.eE+-]+", d) and float(d) > 0), key=float)
    field = open(os.path.join(foam, last, "alpha.water")).read()
    body = field[field.index("internalField"):]
    n = int(re.search(r"nonuniform List<scalar>\s*(\d+)", body).group(1))
    alpha = [float(v) for v in body[body.index("(") + 1:].split(None, n)[:n]]
    nx, ny = export["cells"]
    foam_h = [dx * sum(alpha[j * nx + i] for j in range(ny)) for i in range(nx)]
    x0 = export["domain_x"][0]
    rows = list(csv.reader(open(os.path.join(ldd, "profile.csv"))))[1:]
    profile = [(float(r[0]), float(r[1]), float(r[2])) for r in rows]
    print(f"final free surface (interFoam at {float(last):g} s, LDD at {ldd_t[-1]:g} s), heights [m]:")
    print("| x (m) | shallow arrest | interFoam | LDD |")
    print("| --- | --- | --- | --- |")
    for x, h_ldd, h_theory in profile[::max(1, len(profile) // 12)]:
        i = min(nx - 1, max(0, int((x - x0) / dx)))
        print(f"| {x:+.4f} | {h_theory:.4f} | {foam_h[i]:.4f} | {h_ldd:.4f} |")
else:
    if reference == "table1":
        # LDD Table 1's experiment: the mass front x from the gate [m].
        label, unit, scale = "LDD Table 1 experiment", "x [m] from the gate", lambda x: x
        ref = list(zip([0.09, 0.23, 0.38, 0.56, 0.74, 1.14], [0.103, 0.198, 0.297, 0.399, 0.499, 0.596]))
    else:
        # Martin & Moyce (1952), n² = 2: Z = x/a (x from the back wall) at T = t√(2g/a).
        g = 9.81
        label, unit, scale = "Martin & Moyce", "Z = x/a from the back wall", lambda x: (x + a) / a
        ref = [(T / math.sqrt(2 * g / a), Z) for T, Z in
               [(0.832, 1.217), (1.219, 1.474), (1.997, 2.292), (2.547, 2.995), (3.345, 4.134)]]
    print(f"{case_file}: mass front, {unit}, cells of {dx} m")
    print(f"| t (s) | {label} | interFoam | LDD | LDD vs interFoam | interFoam vs {label} |")
    print("| --- | --- | --- | --- | --- | --- |")
    for t, x in ref:
        xf, xl = scale(at(foam_t, foam_x, t)), scale(at(ldd_t, ldd_x, t))
        print(f"| {t:.3f} | {x:.3f} | {xf:.3f} | {xl:.3f} | {100 * (xl / xf - 1):+.1f} % | {100 * (xf / x - 1):+.1f} % |")
wall = re.search(r"real\s+(\S+)", open(os.path.join(foam, "time.log")).read()) if os.path.exists(
    os.path.join(foam, "time.log")) else None
steps = sum(1 for line in open(os.path.join(foam, "log.interFoam")) if line.startswith("Time = "))
print(f"interFoam: {steps} steps, wall {wall.group(1) if wall else 'unknown'}; fronts in {out}/interfoam_front.csv")
PY
