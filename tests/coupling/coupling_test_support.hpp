#pragma once
// Shared set-up for the coupling tests: a LIGGGHTS box around the fluid's cylinder with given
// particles (no walls: the tests keep particles away from them), a Newtonian law, a run folder.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "rheosim/core/case.hpp"
#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"
#include "rheosim/coupling/near_field.hpp"
#include "rheosim/dem/engine.hpp"

namespace rheosim::coupling::testing {

inline std::shared_ptr<const core::Rheology> newtonian(double viscosity) {
  const auto doc =
      core::Document::from_string(fmt::format("model: newtonian\nviscosity: {:.17g}\n", viscosity), "rheology");
  return core::make_rheology(doc.root());
}

// The near field of the predictive model: pair lubrication and the isolated-sphere terms.
inline NearFieldSettings lubrication_and_stresslet() {
  NearFieldSettings h;
  h.terms.lubrication = true;
  h.terms.single_particle = true;
  return h;
}

// A run folder per test, removed afterwards unless the test failed (then it is kept, with
// LIGGGHTS' logs, for inspection).
class RunFolder {
 public:
  RunFolder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() / fmt::format("rheosim_test_coupling_{}", ::getpid()) /
            fmt::format("{}_{}", info->test_suite_name(), info->name());
    std::filesystem::remove_all(path_);
  }
  ~RunFolder() {
    if (!::testing::Test::HasFailure()) std::filesystem::remove_all(path_);
    std::error_code not_empty;
    std::filesystem::remove(path_.parent_path(), not_empty);  // the process's folder, once empty
  }
  RunFolder(const RunFolder&) = delete;
  RunFolder& operator=(const RunFolder&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

struct BoxParticle {
  double x, y, z, diameter, density;
  double vx = 0.0, vy = 0.0, vz = 0.0;
};

// LIGGGHTS box [−R, R]² × [0, H], soft Hertz material (no contacts expected), nve/sphere,
// optional gravity along −z.
inline void make_box(dem::Engine& engine, double radius, double gap, double time_step, double gravity,
                     const std::vector<BoxParticle>& particles) {
  engine.commands({
      "atom_style granular",
      "atom_modify map array",
      "boundary f f f",
      "newton off",
      "communicate single vel yes",
      "units si",
  });
  engine.command(fmt::format("region box block {:.17g} {:.17g} {:.17g} {:.17g} 0 {:.17g} units box", -radius, radius,
                             -radius, radius, gap));
  engine.commands({
      "create_box 1 box",
      "neighbor 1e-4 bin",
      "neigh_modify delay 0",
      "fix m1 all property/global youngsModulus peratomtype 1e7",
      "fix m2 all property/global poissonsRatio peratomtype 0.3",
      "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.9",
      "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
      "pair_style gran model hertz tangential history",
      "pair_coeff * *",
      "fix integrate all nve/sphere",
  });
  engine.command(fmt::format("timestep {:.17g}", time_step));
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const BoxParticle& b = particles[p];
    engine.command(fmt::format("create_atoms 1 single {:.17g} {:.17g} {:.17g} units box", b.x, b.y, b.z));
    engine.command(fmt::format("set atom {} diameter {:.17g} density {:.17g} vx {:.17g} vy {:.17g} vz {:.17g}", p + 1,
                               b.diameter, b.density, b.vx, b.vy, b.vz));
  }
  if (gravity != 0.0) engine.command(fmt::format("fix gravity all gravity {:.17g} vector 0.0 0.0 -1.0", gravity));
}

}  // namespace rheosim::coupling::testing
