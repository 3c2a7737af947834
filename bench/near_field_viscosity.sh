#!/bin/sh
# Relative viscosity η_r(φ) of the near-field shear cell (issue 9 item 4; docs/hydrodynamics.md):
# φ = 0.1 … 0.45 at γ̇ = 100 and 300 1/s, Krieger–Dougherty fit of φ_m, and the drag-only model
# for comparison. About 15 min on one core. Usage: bench/near_field_viscosity.sh [build dir]
set -eu
build=${1:-build}
cmake --build "$build" -j1 --target coupling_validate_near_field_shear_cell
RHEOSIM_NF_PHIS=${RHEOSIM_NF_PHIS:-0.1,0.2,0.3,0.4,0.45} \
RHEOSIM_NF_RATES=${RHEOSIM_NF_RATES:-100,300} \
RHEOSIM_NF_STRAIN=${RHEOSIM_NF_STRAIN:-5} \
RHEOSIM_NF_DRAG_ONLY=${RHEOSIM_NF_DRAG_ONLY:-1} \
  "$build"/tests/coupling_validate_near_field_shear_cell --gtest_also_run_disabled_tests \
  --gtest_filter='*ViscosityCurveStudy*'
