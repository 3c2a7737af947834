#!/bin/sh
# DEM throughput of the rheometer scene on 1 and 2 MPI ranks, and the strain to a steady
# dry-shear torque (docs/performance.md, DEM). Usage: bench/dem_scaling.sh [build dir] [steps]
# Short runs (a few thousand steps per row): the machine is shared.
set -eu
build=${1:-build}
steps=${2:-2000}
bin="$build/bin/bench_dem"
[ -x "$bin" ] || { echo "dem_scaling.sh: $bin not found; build the bench_dem target first" >&2; exit 2; }
# OpenMPI refuses to run as root without these; --oversubscribe in case other jobs hold cores.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "## 1 rank"
"$bin" --steps="$steps"
echo "## 2 ranks"
mpirun -np 2 --oversubscribe "$bin" --steps="$steps"
echo "## steady torque (1 rank)"
"$bin" --steady --strain=40
