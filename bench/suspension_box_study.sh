#!/usr/bin/env bash
# The Lees–Edwards box's accuracy and cost study behind docs/suspension-box.md: η_r(φ), N1, N2
# with the defaults, and each numerical choice varied one at a time. About 10 min on one core.
# Usage: bench/suspension_box_study.sh [BUILD_DIR] [--only default|friction|cutoff|stokes|size|stiffness|step|tolerance|walls]
# (walls: the walled box against the bulk from H/d = 2 to 20, about 5 min more)
set -euo pipefail
build=${1:-build}
only=${3:-}
[ "${2:-}" = "--only" ] || only=""
box="$build/bin/bench_suspension_box"
[ -x "$box" ] || cmake --build "$build" -j2 --target bench_suspension_box
run() { [ -z "$only" ] || [ "$only" = "$1" ] || return 0; shift; echo; echo "\$ $(basename "$box") $*"; "$box" "$@"; }
run default   --phi 0.05,0.1,0.2,0.3,0.4,0.45,0.5
run friction  --phi 0.3,0.4,0.5 --friction 0
run cutoff    --phi 0.1,0.3,0.4 --cutoff 0.5
run stokes    --phi 0.3 --stokes 0.02
run stokes    --phi 0.3 --stokes 0.2
run stokes    --phi 0.3 --stokes 1
run size      --phi 0.3,0.5 --particles 1000
run stiffness --phi 0.3,0.5 --stiffness 6000
run step      --phi 0.3,0.5 --strain-step 0.0025
run tolerance --phi 0.3 --solver-tolerance 1e-6
run walls     --phi 0.1,0.3,0.4 --wall-gap 0,2,2.5,3,5,10,20
run walls     --phi 0.3 --wall-gap 2.5,5,10,20 --linear-flow
