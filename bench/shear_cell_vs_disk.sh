#!/bin/sh
# The drag-only shear cell's plate torque against CFD-DEM of the whole disk (R = 5 mm, φ = 0.1,
# 50 and 100 1/s, N_z = 4, E = 5 MPa in both; three placements each, their means compared; see
# tests/rheometer/validate_shear_cell_vs_disk.cpp): 6–9 minutes on a loaded machine.
# Usage: bench/shear_cell_vs_disk.sh [BUILD_DIR]
set -eu
build=${1:-build}
cmake --build "$build" -j1 --target rheometer_validate_shear_cell_vs_disk
time "$build/tests/rheometer_validate_shear_cell_vs_disk" --gtest_filter='*TorqueWithinThreePercentOfTheDisk*'
