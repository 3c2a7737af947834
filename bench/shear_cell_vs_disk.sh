#!/bin/sh
# Issue 10 item 5: shear-cell torque against the full disk (R = 5 mm, φ = 0.1, 50 and 100 1/s, N_z = 4,
# E = 5 MPa in both; see tests/rheometer/validate_shear_cell_vs_disk.cpp). Each model runs three
# placements (RHEOSIM_SEEDS=1,2,3) and their means are compared: 6–9 minutes on a loaded machine.
# Usage: bench/shear_cell_vs_disk.sh [BUILD_DIR]   (environment overrides: RHEOSIM_PHI,
#        RHEOSIM_DISK_RADIUS, RHEOSIM_CELL_LENGTH, RHEOSIM_YOUNGS_MODULUS, RHEOSIM_MAX_STRAIN,
#        RHEOSIM_AXIAL_CELLS, RHEOSIM_FLUID_STEP, RHEOSIM_SEEDS, RHEOSIM_RATES and the study knobs
#        listed in the test's header)
set -eu
build=${1:-build}
cmake --build "$build" -j1 --target rheometer_validate_shear_cell_vs_disk
time "$build/tests/rheometer_validate_shear_cell_vs_disk" --gtest_also_run_disabled_tests \
  --gtest_filter='*TorqueWithinThreePercentOfTheDisk*'
