#pragma once
// Shared set-up for the near-field validations: a LIGGGHTS box with optional
// periodic directions, soft Hertz spheres, nve/sphere, no gravity.
#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "rheosim/dem/engine.hpp"

namespace rheosim::coupling::testing {

struct Sphere {
  double x, y, z, radius, density;
  double vx = 0.0, vy = 0.0, vz = 0.0;
};

struct BoxSpec {
  std::array<double, 3> low{}, high{};
  std::array<bool, 3> periodic{false, false, false};
  double time_step = 1e-6;      // [s]
  double youngs_modulus = 1e7;  // [Pa] (soft: the validations resolve contacts with a large δt)
  double friction = 0.3;
  double restitution = 0.5;
};

inline void make_sphere_box(dem::Engine& engine, const BoxSpec& box, const std::vector<Sphere>& spheres) {
  const auto b = [](bool p) { return p ? "p" : "f"; };
  engine.commands({"atom_style granular", "atom_modify map array"});
  engine.command(fmt::format("boundary {} {} {}", b(box.periodic[0]), b(box.periodic[1]), b(box.periodic[2])));
  engine.commands({"newton off", "communicate single vel yes", "units si"});
  engine.command(fmt::format("region box block {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} units box", box.low[0],
                             box.high[0], box.low[1], box.high[1], box.low[2], box.high[2]));
  double max_radius = 0.0;
  for (const auto& s : spheres) max_radius = std::max(max_radius, s.radius);
  engine.command("create_box 1 box");
  engine.command(fmt::format("neighbor {:.17g} bin", 0.5 * max_radius));
  engine.commands({"neigh_modify delay 0"});
  engine.command(fmt::format("fix m1 all property/global youngsModulus peratomtype {:.17g}", box.youngs_modulus));
  engine.command("fix m2 all property/global poissonsRatio peratomtype 0.3");
  engine.command(
      fmt::format("fix m3 all property/global coefficientRestitution peratomtypepair 1 {:.17g}", box.restitution));
  engine.command(fmt::format("fix m4 all property/global coefficientFriction peratomtypepair 1 {:.17g}", box.friction));
  engine.commands({"pair_style gran model hertz tangential history", "pair_coeff * *", "fix integrate all nve/sphere"});
  engine.command(fmt::format("timestep {:.17g}", box.time_step));
  for (std::size_t p = 0; p < spheres.size(); ++p) {
    const Sphere& s = spheres[p];
    engine.command(fmt::format("create_atoms 1 single {:.17g} {:.17g} {:.17g} units box", s.x, s.y, s.z));
    engine.command(fmt::format("set atom {} diameter {:.17g} density {:.17g} vx {:.17g} vy {:.17g} vz {:.17g}", p + 1,
                               2.0 * s.radius, s.density, s.vx, s.vy, s.vz));
  }
}

}  // namespace rheosim::coupling::testing
