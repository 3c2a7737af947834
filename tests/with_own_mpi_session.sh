#!/bin/sh
# Runs one test process with an OpenMPI session directory of its own. OpenMPI 4 processes
# started at the same time (ctest -j2: two tests that initialise MPI) share one session directory,
# ompi.<host>.<uid> in the temporary directory, and race to create and remove it
# (open-mpi/ompi#8510); the loser stops in orte_init with "A call to mkdir was unable to create
# the desired directory".
session=$(mktemp -d -t rheosim-mpi.XXXXXX) || exit 1
OMPI_MCA_orte_tmpdir_base=$session "$@"
status=$?
rm -rf "$session"
exit $status
