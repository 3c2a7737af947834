#pragma once
// The preconditioner of an LDD linear system (a solver setting): 1/diagonal, a sparse LU, or one
// AMG V-cycle (rheosim/numerics/amg.hpp).
namespace rheosim::ldd {

enum class Preconditioner { jacobi, sparse_lu, amg };

}  // namespace rheosim::ldd
