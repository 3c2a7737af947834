#pragma once
// The preconditioner of an LDD linear system (a solver setting): 1/diagonal, a sparse LU, or one
// AMG V-cycle (rheosim/numerics/amg.hpp).
#include <string_view>

namespace rheosim::ldd {

enum class Preconditioner { jacobi, sparse_lu, amg };

// "jacobi" | "lu" | "amg" as in case files (the case reader admits only these and "auto");
// "auto" gives `fallback`, the solver's own choice.
[[nodiscard]] constexpr Preconditioner preconditioner_named(std::string_view name, Preconditioner fallback) {
  if (name == "jacobi") return Preconditioner::jacobi;
  if (name == "lu") return Preconditioner::sparse_lu;
  if (name == "amg") return Preconditioner::amg;
  return fallback;
}

}  // namespace rheosim::ldd
