// Pair and plate lubrication (see lubrication.hpp for the formulas and sources).
#include "lubrication.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

namespace rheosim::coupling {

namespace {

constexpr double pi = std::numbers::pi;

void check_xi(double xi, const char* where) {
  if (!(xi > 0.0 && std::isfinite(xi)))
    throw std::invalid_argument(fmt::format("{}: dimensionless gap ξ = {}, expected a finite value > 0", where, xi));
}

}  // namespace

NearContactResistance sphere_sphere_resistance(double size_ratio, double xi) {
  check_xi(xi, "sphere_sphere_resistance");
  if (!(size_ratio > 0.0 && std::isfinite(size_ratio)))
    throw std::invalid_argument(fmt::format("sphere_sphere_resistance: λ = {}, expected > 0", size_ratio));
  const double l = size_ratio;
  const double lp1 = 1.0 + l;
  const double log_term = std::log(1.0 / xi);
  // Jeffrey & Onishi (1984) eqs. for X^A_11, Y^A_11, Y^B_11, Y^C_11, Y^C_12 (singular parts).
  const double g1 = 2.0 * l * l / (lp1 * lp1 * lp1);
  const double g2 = l * (1.0 + 7.0 * l + l * l) / (5.0 * lp1 * lp1 * lp1);
  const double g4 = 4.0 * l * (2.0 + l + 2.0 * l * l) / (15.0 * lp1 * lp1 * lp1);
  return {.squeeze = g1 / xi + g2 * log_term,
          .shear = g4 * log_term,
          .rotation_coupling_self = l * (4.0 + l) / (5.0 * lp1 * lp1) * log_term,
          .rotation_coupling_other = l * l * (1.0 + 4.0 * l) / (5.0 * lp1 * lp1) * log_term,
          .rotation_self = 2.0 * l / (5.0 * lp1) * log_term,
          .rotation_other = l * l / (10.0 * lp1) * log_term};
}

NearContactResistance sphere_plate_resistance(double xi) {
  check_xi(xi, "sphere_plate_resistance");
  // λ → ∞ with ξ = h/a (Cox & Brenner 1967; Goldman, Cox & Brenner 1967).
  const double log_term = std::log(1.0 / xi);
  return {.squeeze = 1.0 / xi + 0.2 * log_term,
          .shear = 8.0 / 15.0 * log_term,
          .rotation_coupling_self = 0.2 * log_term,
          .rotation_coupling_other = 0.0,
          .rotation_self = 0.4 * log_term,
          .rotation_other = 0.0};
}

namespace lubrication {

namespace {

Vector3 cross(const Vector3& a, const Vector3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vector3& a, const Vector3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vector3 tangential(const Vector3& v, const Vector3& n) {
  const double vn = dot(v, n);
  return {v[0] - vn * n[0], v[1] - vn * n[1], v[2] - vn * n[2]};
}
Vector3 get(std::span<const double> v, std::size_t particle, std::size_t offset) {
  return {v[6 * particle + offset], v[6 * particle + offset + 1], v[6 * particle + offset + 2]};
}
void add(std::span<double> out, std::size_t particle, std::size_t offset, const Vector3& value, double sign = 1.0) {
  for (std::size_t k = 0; k < 3; ++k) out[6 * particle + offset + k] += sign * value[k];
}

struct GapLoads {
  Vector3 force_i{}, torque_i{}, torque_j{};
};

GapLoads loads(const Gap& gap, std::span<const double> v, bool include_plate_drive) {
  const bool plate = gap.j == no_partner;
  const Vector3 ui = get(v, gap.i, 0), wi = get(v, gap.i, 3);
  Vector3 uj{}, wj{};
  if (!plate) {
    uj = get(v, gap.j, 0);
    wj = get(v, gap.j, 3);
  } else if (include_plate_drive) {
    uj = gap.plate_velocity;
  }
  const Vector3 du{ui[0] - uj[0], ui[1] - uj[1], ui[2] - uj[2]};
  const Vector3& n = gap.n;
  const double dun = dot(du, n);
  const Vector3 dut = tangential(du, n);
  const Vector3 wi_x_n = cross(wi, n), wj_x_n = cross(wj, n);
  GapLoads out;
  for (std::size_t k = 0; k < 3; ++k)
    out.force_i[k] = -gap.k_squeeze * dun * n[k] - gap.k_shear * dut[k] - gap.b_i * wi_x_n[k] - gap.b_j * wj_x_n[k];
  const Vector3 n_x_du = cross(n, du);
  const Vector3 wit = tangential(wi, n), wjt = tangential(wj, n);
  for (std::size_t k = 0; k < 3; ++k) {
    out.torque_i[k] = -gap.b_i * n_x_du[k] - gap.c_ii * wit[k] - gap.c_ij * wjt[k];
    // Sphere j: n → −n, ΔU → −ΔU, so n×ΔU is unchanged; its self coupling is b_j.
    out.torque_j[k] = -gap.b_j * n_x_du[k] - gap.c_jj * wjt[k] - gap.c_ij * wit[k];
  }
  return out;
}

}  // namespace

void set_pair_coefficients(Gap& gap, double radius_i, double radius_j, double gap_width, double viscosity,
                           double roughness) {
  const double mean_radius = 0.5 * (radius_i + radius_j);
  const double xi = (std::max(gap_width, 0.0) + roughness * mean_radius) / mean_radius;
  const double lambda = radius_j / radius_i;
  const NearContactResistance r = sphere_sphere_resistance(lambda, xi);
  const double ai = radius_i, aj = radius_j, mu = viscosity;
  gap.gap_ratio = gap_width / mean_radius;
  gap.k_squeeze = 6.0 * pi * mu * ai * r.squeeze;
  gap.k_shear = 6.0 * pi * mu * ai * r.shear;
  gap.b_i = 4.0 * pi * mu * ai * ai * r.rotation_coupling_self;
  gap.b_j = 4.0 * pi * mu * ai * ai * r.rotation_coupling_other;
  gap.c_ii = 8.0 * pi * mu * ai * ai * ai * r.rotation_self;
  gap.c_ij = 8.0 * pi * mu * ai * ai * ai * r.rotation_other;
  gap.c_jj = 8.0 * pi * mu * aj * aj * aj * (2.0 / (5.0 * (1.0 + lambda))) * std::log(1.0 / xi);
}

void set_plate_coefficients(Gap& gap, double radius, double gap_width, double viscosity, double roughness) {
  const double xi = (std::max(gap_width, 0.0) + roughness * radius) / radius;
  const NearContactResistance r = sphere_plate_resistance(xi);
  const double a = radius, mu = viscosity;
  gap.gap_ratio = gap_width / radius;
  gap.k_squeeze = 6.0 * pi * mu * a * r.squeeze;
  gap.k_shear = 6.0 * pi * mu * a * r.shear;
  gap.b_i = 4.0 * pi * mu * a * a * r.rotation_coupling_self;
  gap.b_j = 0.0;
  gap.c_ii = 8.0 * pi * mu * a * a * a * r.rotation_self;
  gap.c_ij = 0.0;
  gap.c_jj = 0.0;
}

void add_gap_forces(const Gap& gap, std::span<const double> velocities, std::span<double> out,
                    bool include_plate_drive) {
  const GapLoads l = loads(gap, velocities, include_plate_drive);
  add(out, gap.i, 0, l.force_i);
  add(out, gap.i, 3, l.torque_i);
  if (gap.j != no_partner) {
    add(out, gap.j, 0, l.force_i, -1.0);
    add(out, gap.j, 3, l.torque_j);
  }
}

Vector3 gap_force_on_i(const Gap& gap, std::span<const double> velocities) {
  return loads(gap, velocities, true).force_i;
}

void add_gap_self_blocks(const Gap& gap, std::span<double> blocks) {
  const Vector3& n = gap.n;
  // N v = n × v as a matrix.
  const std::array<std::array<double, 3>, 3> cross_n{{{0.0, -n[2], n[1]}, {n[2], 0.0, -n[0]}, {-n[1], n[0], 0.0}}};
  const auto add_block = [&](std::size_t particle, double coupling, double rotation) {
    double* b = blocks.data() + 36 * particle;
    for (std::size_t r = 0; r < 3; ++r)
      for (std::size_t c = 0; c < 3; ++c) {
        const double nn = n[r] * n[c];
        const double identity = r == c ? 1.0 : 0.0;
        b[6 * r + c] += gap.k_squeeze * nn + gap.k_shear * (identity - nn);  // R_UU
        b[6 * r + 3 + c] += -coupling * cross_n[r][c];                       // R_UΩ = −b N
        b[6 * (3 + r) + c] += coupling * cross_n[r][c];                      // R_ΩU = b N
        b[6 * (3 + r) + 3 + c] += rotation * (identity - nn);                // R_ΩΩ = c P
      }
  };
  add_block(gap.i, gap.b_i, gap.c_ii);
  // Sphere j sees n → −n: its R_UΩ is +b_j N in terms of this n.
  if (gap.j != no_partner) add_block(gap.j, -gap.b_j, gap.c_jj);
}

double surface_slip_speed(const Gap& gap, double radius_i, double radius_j, std::span<const double> velocities) {
  const bool plate = gap.j == no_partner;
  const Vector3 ui = get(velocities, gap.i, 0), wi = get(velocities, gap.i, 3);
  const Vector3 uj = plate ? gap.plate_velocity : get(velocities, gap.j, 0);
  const Vector3 wj = plate ? Vector3{} : get(velocities, gap.j, 3);
  const Vector3 wi_x_n = cross(wi, gap.n), wj_x_n = cross(wj, gap.n);
  // Surface of i at x_i + a_i n, of j at x_j − a_j n.
  double sum = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const double s = ui[k] - uj[k] + radius_i * wi_x_n[k] + radius_j * wj_x_n[k];
    sum += s * s;
  }
  return std::sqrt(sum);
}

}  // namespace lubrication
}  // namespace rheosim::coupling
