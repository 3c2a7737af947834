// Near-field hydrodynamics: term registry, neighbour search, assembly of F_H = −R V + F₀ and
// the implicit (backward-Euler) update (see near_field.hpp, lubrication.hpp, stresslet.hpp).
#include "rheosim/coupling/near_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "rheosim/numerics/conjugate_gradient.hpp"

#include "block_cholesky.hpp"
#include "lubrication.hpp"
#include "stresslet.hpp"

namespace rheosim::coupling {

void NearFieldResult::reset(std::size_t particles, std::size_t plates) {
  forces.assign(3 * particles, 0.0);
  torques.assign(3 * particles, 0.0);
  particle_stress = {};
  lubrication_virial = {};
  plate_virial = {};
  stresslet_sum = {};
  stresslet_axial_moment = 0.0;
  rotation_torque_sum = {};
  lubrication_virial_full = {};
  rotation_torque_radial_moment = 0.0;
  plate_forces.assign(plates, Vector3{});
  plate_moments.assign(plates, Vector3{});
  lubricated_pairs = 0;
  lubricated_walls = 0;
  smallest_gap_ratio = 0.0;
  solver_iterations = 0;
}

namespace {

constexpr double pi = std::numbers::pi;
constexpr double infinity = std::numeric_limits<double>::infinity();

void check_settings(const NearFieldSettings& s) {
  if (!(s.roughness >= 1e-6 && s.roughness <= 0.1))
    throw std::invalid_argument(
        fmt::format("hydrodynamics.roughness = {}, expected 1e-6 <= roughness <= 0.1 (δ/ā, about 1e-3)", s.roughness));
  if (!(s.lubrication_cutoff > s.roughness && s.lubrication_cutoff <= 1.0))
    throw std::invalid_argument(fmt::format(
        "hydrodynamics.lubrication_cutoff = {}, expected roughness ({}) < cutoff <= 1 (h_c/ā; ln(1/ξ) < 0 beyond 1)",
        s.lubrication_cutoff, s.roughness));
  if (!(s.solver_tolerance > 0.0 && s.solver_tolerance <= 1e-3))
    throw std::invalid_argument(
        fmt::format("hydrodynamics.solver_tolerance = {}, expected 0 < tolerance <= 1e-3", s.solver_tolerance));
  if (s.max_solver_iterations < 1)
    throw std::invalid_argument(
        fmt::format("hydrodynamics.max_solver_iterations = {}, expected >= 1", s.max_solver_iterations));
}

Vector3 position(const ParticleSnapshot& p, std::size_t i) {
  return {p.positions[3 * i], p.positions[3 * i + 1], p.positions[3 * i + 2]};
}

void add_outer(SymmetricTensor& t, const Vector3& r, const Vector3& f, double sign) {
  // Symmetric part of r ⊗ f.
  t[0] += sign * r[0] * f[0];
  t[1] += sign * r[1] * f[1];
  t[2] += sign * r[2] * f[2];
  t[3] += sign * 0.5 * (r[0] * f[1] + r[1] * f[0]);
  t[4] += sign * 0.5 * (r[0] * f[2] + r[2] * f[0]);
  t[5] += sign * 0.5 * (r[1] * f[2] + r[2] * f[1]);
}

// Pairs of particles closer than their interaction range: a cell list over the particles
// (wrapped into the periodic box), minimum image in periodic directions.
class PairFinder {
 public:
  PairFinder(const ParticleSnapshot& p, const NearFieldScene& scene, double cutoff_ratio)
      : p_(p), scene_(scene), cutoff_ratio_(cutoff_ratio) {
    const std::size_t n = p.size();
    max_radius_ = 0.0;
    for (std::size_t i = 0; i < n; ++i) max_radius_ = std::max(max_radius_, p.radii[i]);
    // Largest centre distance with h < h_c = cutoff · ā: 2 a_max (1 + cutoff/2).
    range_ = 2.0 * max_radius_ + cutoff_ratio_ * max_radius_;
    for (int d = 0; d < 3; ++d) {
      if (scene.periodic[d]) {
        length_[d] = scene.box_high[d] - scene.box_low[d];
        if (!(length_[d] > 0.0))
          throw std::invalid_argument(
              fmt::format("NearFieldScene: periodic direction {} has box length {}", d, length_[d]));
        low_[d] = scene.box_low[d];
      } else {
        double lo = infinity, hi = -infinity;
        for (std::size_t i = 0; i < n; ++i) {
          lo = std::min(lo, p.positions[3 * i + d]);
          hi = std::max(hi, p.positions[3 * i + d]);
        }
        low_[d] = n > 0 ? lo : 0.0;
        length_[d] = n > 0 ? std::max(hi - lo, range_) * (1.0 + 1e-12) + 1e-300 : range_;
      }
      cells_[d] = std::max(1, static_cast<int>(std::floor(length_[d] / range_)));
      cells_[d] = std::min(cells_[d], 1 << 10);
    }
  }

  // Minimum-image separation x_j − x_i.
  [[nodiscard]] Vector3 separation(std::size_t i, std::size_t j) const {
    Vector3 r{};
    for (int d = 0; d < 3; ++d) {
      r[d] = p_.positions[3 * j + d] - p_.positions[3 * i + d];
      if (scene_.periodic[d]) r[d] -= length_[d] * std::round(r[d] / length_[d]);
    }
    return r;
  }

  // Calls visit(i, j, r) once per pair (i < j or by cell order) with |r| < range.
  template <class Visit>
  void for_each_pair(Visit&& visit) const {
    const std::size_t n = p_.size();
    const bool small_grid = cells_[0] < 3 || cells_[1] < 3 || cells_[2] < 3;
    if (n < 64 || small_grid) {
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) check_pair(i, j, visit);
      return;
    }
    const std::size_t cell_count = static_cast<std::size_t>(cells_[0]) * cells_[1] * cells_[2];
    std::vector<std::size_t> head(cell_count, lubrication::no_partner), next(n, lubrication::no_partner);
    std::vector<std::array<int, 3>> cell_of(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::array<int, 3> c{};
      for (int d = 0; d < 3; ++d) {
        double u = (p_.positions[3 * i + d] - low_[d]) / length_[d];
        if (scene_.periodic[d]) u -= std::floor(u);
        c[d] = std::clamp(static_cast<int>(u * cells_[d]), 0, cells_[d] - 1);
      }
      cell_of[i] = c;
      const std::size_t id = index(c);
      next[i] = head[id];
      head[id] = i;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const auto c = cell_of[i];
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            std::array<int, 3> nc{c[0] + dx, c[1] + dy, c[2] + dz};
            bool outside = false;
            for (int d = 0; d < 3; ++d) {
              if (nc[d] < 0 || nc[d] >= cells_[d]) {
                if (!scene_.periodic[d]) {
                  outside = true;
                  break;
                }
                nc[d] = (nc[d] + cells_[d]) % cells_[d];
              }
            }
            if (outside) continue;
            for (std::size_t j = head[index(nc)]; j != lubrication::no_partner; j = next[j])
              if (j > i) check_pair(i, j, visit);
          }
    }
  }

 private:
  [[nodiscard]] std::size_t index(const std::array<int, 3>& c) const {
    return (static_cast<std::size_t>(c[0]) * cells_[1] + c[1]) * cells_[2] + c[2];
  }
  template <class Visit>
  void check_pair(std::size_t i, std::size_t j, Visit& visit) const {
    const Vector3 r = separation(i, j);
    const double mean_radius = 0.5 * (p_.radii[i] + p_.radii[j]);
    const double distance = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    const double gap = distance - p_.radii[i] - p_.radii[j];
    if (gap < cutoff_ratio_ * mean_radius && distance > 0.0) visit(i, j, r, distance, gap);
  }

  const ParticleSnapshot& p_;
  const NearFieldScene& scene_;
  double cutoff_ratio_;
  double max_radius_ = 0.0, range_ = 0.0;
  std::array<double, 3> low_{}, length_{};
  std::array<int, 3> cells_{1, 1, 1};
};

// All enabled terms in one resistance system F_H = −R V + F₀ (V: 6 per particle).
class CombinedNearField final : public NearFieldModel {
 public:
  CombinedNearField(NearFieldSettings settings, std::shared_ptr<const core::Rheology> matrix)
      : settings_(std::move(settings)), matrix_(std::move(matrix)), name_(settings_.terms.name()) {}

  [[nodiscard]] std::string_view name() const override { return name_; }

  void evaluate(const ParticleSnapshot& p, const NearFieldScene& scene, const AmbientFlow& ambient,
                NearFieldResult& result) const override;

  [[nodiscard]] double stable_time_step(const ParticleSnapshot& p, double particle_density) const override;

 private:
  struct System {
    std::vector<lubrication::Gap> gaps;
    std::vector<double> drag;          // 6πμa per particle (stokes_drag)
    std::vector<double> rotation;      // 8πμa³ per particle (single_particle)
    std::vector<double> ambient_spin;  // ω∞ = ½∇×u∞, 3 per particle (single_particle)
    std::vector<double> drive;         // F₀, 6 per particle
    std::vector<double> blocks;        // the particles' own 6×6 blocks of R, 36 per particle
    std::vector<Vector3> repulsion;    // repulsive force on i of each gap (repulsion; else empty)
  };
  [[nodiscard]] System assemble(const ParticleSnapshot& p, const NearFieldScene& scene, const AmbientFlow& ambient,
                                std::span<const double> velocities, NearFieldResult* result) const;
  void apply_resistance(const System& s, std::span<const double> v, std::span<double> out) const;  // out = R v
  // μ_S of the stresslet at the ambient shear rate, μ = μ(γ̇) (NearFieldSettings::stresslet_viscosity).
  // Chateau, Ovarlez & Trung's homogenisation evaluates the matrix at the liquid's mean square
  // local rate γ̇_loc = γ̇ √(η_r/(1 − φ)); to first order in φ that gives
  // τ(γ̇)(1 + (0.75 + 1.75 n)φ) with n = 1 + d ln μ/d ln γ̇, i.e. Einstein's 2.5φ with
  // μ_S = 0.3 μ + 0.7 dτ/dγ̇ = μ + 0.7 γ̇ dμ/dγ̇ (a plastic matrix, n → 0: 0.75φ).
  [[nodiscard]] double stresslet_viscosity(double mu, double shear_rate) const {
    if (settings_.stresslet_viscosity == StressletViscosity::secant || !(shear_rate > 0.0)) return mu;
    const double tangent = mu + shear_rate * matrix_->viscosity_derivative(shear_rate);
    return std::isfinite(tangent) ? 0.3 * mu + 0.7 * std::max(tangent, 0.0) : mu;
  }

  NearFieldSettings settings_;
  std::shared_ptr<const core::Rheology> matrix_;
  std::string name_;
};

std::vector<double> generalized_velocities(const ParticleSnapshot& p) {
  const std::size_t n = p.size();
  std::vector<double> v(6 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      v[6 * i + k] = p.velocities[3 * i + k];
      v[6 * i + 3 + k] = p.angular_velocities.empty() ? 0.0 : p.angular_velocities[3 * i + k];
    }
  return v;
}

CombinedNearField::System CombinedNearField::assemble(const ParticleSnapshot& p, const NearFieldScene& scene,
                                                      const AmbientFlow& ambient, std::span<const double> v,
                                                      NearFieldResult* result) const {
  const std::size_t n = p.size();
  System s;
  s.drive.assign(6 * n, 0.0);
  s.blocks.assign(36 * n, 0.0);
  const bool need_ambient =
      settings_.terms.single_particle || settings_.terms.stokes_drag || settings_.terms.lubrication;
  std::vector<single_particle::AmbientAtParticle> flow(need_ambient && ambient ? n : 0);
  for (std::size_t i = 0; i < flow.size(); ++i) flow[i] = single_particle::decompose(ambient(position(p, i)));
  const auto ambient_shear_rate = [&](std::size_t i) { return flow.empty() ? 0.0 : flow[i].shear_rate; };

  if (settings_.terms.stokes_drag || settings_.terms.single_particle) {
    s.drag.assign(settings_.terms.stokes_drag ? n : 0, 0.0);
    s.rotation.assign(settings_.terms.single_particle ? n : 0, 0.0);
    s.ambient_spin.assign(settings_.terms.single_particle ? 3 * n : 0, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double a = p.radii[i];
      const double mu = matrix_->viscosity(ambient_shear_rate(i));
      const single_particle::AmbientAtParticle f = flow.empty() ? single_particle::AmbientAtParticle{} : flow[i];
      if (settings_.terms.stokes_drag) {
        s.drag[i] = 6.0 * pi * mu * a;
        for (std::size_t k = 0; k < 3; ++k) {
          s.drive[6 * i + k] += s.drag[i] * f.velocity[k];
          s.blocks[36 * i + 7 * k] += s.drag[i];
        }
      }
      if (settings_.terms.single_particle) {
        s.rotation[i] = 8.0 * pi * mu * a * a * a;
        for (std::size_t k = 0; k < 3; ++k) {
          s.drive[6 * i + 3 + k] += s.rotation[i] * f.vorticity_half[k];
          s.ambient_spin[3 * i + k] = f.vorticity_half[k];
          s.blocks[36 * i + 7 * (3 + k)] += s.rotation[i];
        }
        if (result != nullptr) {
          const double stresslet = 20.0 / 3.0 * pi * stresslet_viscosity(mu, ambient_shear_rate(i)) * a * a * a;
          for (std::size_t c = 0; c < 6; ++c) result->stresslet_sum[c] += stresslet * f.strain_rate[c];
          const Vector3 x = position(p, i);
          result->stresslet_axial_moment += stresslet * (x[0] * f.strain_rate[5] - x[1] * f.strain_rate[4]);
        }
      }
    }
  }

  if (settings_.terms.lubrication) {
    const double roughness = settings_.roughness;
    double smallest = infinity;
    const auto finish_gap = [&](lubrication::Gap& gap, double ai, double aj, double width, double ambient_rate) {
      // γ̇_gap = |v_s|/h_eff, not below the ambient shear rate (lubrication.hpp).
      const double mean = gap.j == lubrication::no_partner ? ai : 0.5 * (ai + aj);
      const double h_eff = std::max(width, 0.0) + roughness * mean;
      const double slip = lubrication::surface_slip_speed(gap, ai, aj, v);
      const double mu = matrix_->viscosity(std::max(slip / h_eff, ambient_rate));
      if (gap.j == lubrication::no_partner)
        lubrication::set_plate_coefficients(gap, ai, width, mu, roughness);
      else
        lubrication::set_pair_coefficients(gap, ai, aj, width, mu, roughness);
      lubrication::add_gap_self_blocks(gap, s.blocks);
      smallest = std::min(smallest, gap.gap_ratio);
      s.gaps.push_back(gap);
    };
    PairFinder finder(p, scene, settings_.lubrication_cutoff);
    finder.for_each_pair([&](std::size_t i, std::size_t j, const Vector3& r, double distance, double width) {
      lubrication::Gap gap;
      gap.i = i;
      gap.j = j;
      gap.separation = r;
      gap.n = {r[0] / distance, r[1] / distance, r[2] / distance};
      finish_gap(gap, p.radii[i], p.radii[j], width, 0.5 * (ambient_shear_rate(i) + ambient_shear_rate(j)));
      if (result != nullptr) ++result->lubricated_pairs;
    });
    for (std::size_t w = 0; w < scene.plates.size(); ++w) {
      const PlateWall& plate = scene.plates[w];
      for (std::size_t i = 0; i < n; ++i) {
        const double a = p.radii[i];
        const Vector3 x = position(p, i);
        const double width = plate.faces_up ? x[2] - plate.z - a : plate.z - x[2] - a;
        if (!(width < settings_.lubrication_cutoff * a)) continue;
        lubrication::Gap gap;
        gap.i = i;
        gap.plate = w;
        gap.n = {0.0, 0.0, plate.faces_up ? -1.0 : 1.0};
        gap.separation = {0.0, 0.0, plate.z - x[2]};
        const Vector3 point{x[0], x[1], plate.z};
        if (plate.velocity_at) gap.plate_velocity = plate.velocity_at(point);
        gap.plate_velocity[2] = 0.0;
        finish_gap(gap, a, 0.0, width, ambient_shear_rate(i));
        if (result != nullptr) ++result->lubricated_walls;
      }
    }
    // F₀ of the plates: the gap forces at V = 0 with the plate moving.
    const std::vector<double> zero(6 * n, 0.0);
    for (const auto& gap : s.gaps)
      if (gap.j == lubrication::no_partner) lubrication::add_gap_forces(gap, zero, s.drive, true);
    // Repulsion: a known force, part of F₀ (it does not depend on V).
    if (settings_.terms.repulsion) {
      s.repulsion.reserve(s.gaps.size());
      for (const auto& gap : s.gaps) {
        const double h = std::max(gap.gap_ratio, 0.0);  // h/ā (h/a at a plate)
        const double magnitude = settings_.repulsion_force * std::exp(-h / settings_.repulsion_length);
        const Vector3 f{-magnitude * gap.n[0], -magnitude * gap.n[1], -magnitude * gap.n[2]};
        s.repulsion.push_back(f);
        for (std::size_t k = 0; k < 3; ++k) {
          s.drive[6 * gap.i + k] += f[k];
          if (gap.j != lubrication::no_partner) s.drive[6 * gap.j + k] -= f[k];
        }
      }
    }
    if (result != nullptr) result->smallest_gap_ratio = s.gaps.empty() ? 0.0 : smallest;
  }
  return s;
}

void CombinedNearField::apply_resistance(const System& s, std::span<const double> v, std::span<double> out) const {
  std::fill(out.begin(), out.end(), 0.0);
  for (const auto& gap : s.gaps) lubrication::add_gap_forces(gap, v, out, false);  // adds −R_gap v
  for (double& x : out) x = -x;
  for (std::size_t i = 0; i < s.drag.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k) out[6 * i + k] += s.drag[i] * v[6 * i + k];
  for (std::size_t i = 0; i < s.rotation.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k) out[6 * i + 3 + k] += s.rotation[i] * v[6 * i + 3 + k];
}

void CombinedNearField::evaluate(const ParticleSnapshot& p, const NearFieldScene& scene, const AmbientFlow& ambient,
                                 NearFieldResult& result) const {
  const std::size_t n = p.size();
  if (p.positions.size() != 3 * n || p.velocities.size() != 3 * n ||
      (!p.angular_velocities.empty() && p.angular_velocities.size() != 3 * n))
    throw std::invalid_argument(
        fmt::format("NearFieldModel::evaluate: {} radii but {} positions, {} velocities, {} "
                    "angular velocities (expected 3 per particle)",
                    n, p.positions.size(), p.velocities.size(), p.angular_velocities.size()));
  if (result.forces.size() != 3 * n || result.torques.size() != 3 * n ||
      result.plate_forces.size() != scene.plates.size())
    throw std::invalid_argument(
        "NearFieldModel::evaluate: result not sized by NearFieldResult::reset(particles, plates)");
  if (!settings_.terms.lubrication && !settings_.terms.single_particle && !settings_.terms.stokes_drag) return;
  const bool implicit = p.time_step > 0.0;
  if (implicit && (p.masses.size() != n || p.other_forces.size() != 3 * n || p.other_torques.size() != 3 * n))
    throw std::invalid_argument(fmt::format(
        "NearFieldModel::evaluate: implicit update (time_step = {}) needs masses (n = {}), other_forces and "
        "other_torques (3n); got {}, {}, {}",
        p.time_step, n, p.masses.size(), p.other_forces.size(), p.other_torques.size()));

  const std::vector<double> v = generalized_velocities(p);
  NearFieldResult& r = result;
  const System s = assemble(p, scene, ambient, v, &r);

  // Velocities at which the hydrodynamic force is evaluated: V (explicit) or V⁺ (implicit).
  std::vector<double> v_new = v;
  if (implicit) {
    // (M/δt + R) V⁺ = M/δt V + F_other + F₀, Jacobi-preconditioned conjugate gradients.
    const double dt = p.time_step;
    std::vector<double> inertia(6 * n), rhs(6 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const double m = p.masses[i];
      const double moment = 0.4 * m * p.radii[i] * p.radii[i];
      for (std::size_t k = 0; k < 3; ++k) {
        inertia[6 * i + k] = m / dt;
        inertia[6 * i + 3 + k] = moment / dt;
        rhs[6 * i + k] = m / dt * v[6 * i + k] + p.other_forces[3 * i + k] + s.drive[6 * i + k];
        rhs[6 * i + 3 + k] = moment / dt * v[6 * i + 3 + k] + p.other_torques[3 * i + k] + s.drive[6 * i + 3 + k];
      }
    }
    // Block-Jacobi preconditioner: each particle's 6×6 block of M/δt + R, Cholesky-factored.
    std::vector<double> factor = s.blocks;
    for (std::size_t i = 0; i < n; ++i) {
      double* b = factor.data() + 36 * i;
      for (std::size_t k = 0; k < 6; ++k) b[7 * k] += inertia[6 * i + k];
      cholesky_6(b);
    }
    const auto apply_a = [&](std::span<const double> x, std::span<double> out) {
      apply_resistance(s, x, out);
      for (std::size_t k = 0; k < x.size(); ++k) out[k] += inertia[k] * x[k];
    };
    const auto precondition = [&](std::span<const double> in, std::span<double> out) {
      for (std::size_t i = 0; i < n; ++i)
        cholesky_6_solve(factor.data() + 36 * i, in.data() + 6 * i, out.data() + 6 * i);
    };
    // Initial guess: the current velocities V (the previous step's V⁺): in a lubrication-
    // dominated flow the velocities change little per step, while V* carries the full kick of
    // the contact forces that the lubrication mostly cancels.
    numerics::ConjugateGradientSettings cg;
    cg.relative_tolerance = settings_.solver_tolerance;
    cg.max_iterations = settings_.max_solver_iterations;
    numerics::ConjugateGradientWorkspace work;
    r.solver_iterations = numerics::conjugate_gradient(apply_a, precondition, rhs, v_new, cg, work).iterations;
  }

  // F_H = −R V⁺ + F₀.
  std::vector<double> rv(6 * n);
  apply_resistance(s, v_new, rv);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      r.forces[3 * i + k] += s.drive[6 * i + k] - rv[6 * i + k];
      r.torques[3 * i + k] += s.drive[6 * i + 3 + k] - rv[6 * i + 3 + k];
    }

  // The rotation torques −8πμa³(Ω⁺ − ω∞): their reaction is a couple on the liquid, which the
  // fluid solvers do not carry; the scenes add the antisymmetric stress it makes (near_field.hpp).
  for (std::size_t i = 0; i < s.rotation.size(); ++i) {
    const Vector3 x = position(p, i);
    Vector3 torque{};
    for (std::size_t k = 0; k < 3; ++k) {
      torque[k] = s.rotation[i] * (s.ambient_spin[3 * i + k] - v_new[6 * i + 3 + k]);
      r.rotation_torque_sum[k] += torque[k];
    }
    r.rotation_torque_radial_moment += x[0] * torque[0] + x[1] * torque[1];
  }

  // Stress and plate loads from the gap forces at V⁺.
  for (std::size_t g = 0; g < s.gaps.size(); ++g) {
    const auto& gap = s.gaps[g];
    Vector3 f_i = lubrication::gap_force_on_i(gap, v_new);
    if (!s.repulsion.empty())
      for (std::size_t k = 0; k < 3; ++k) f_i[k] += s.repulsion[g][k];
    // Unsymmetrised: F_i ⊗ (separation) = −F_j ⊗ (x_j − x_i) resp. −F_p ⊗ (x_p − x_w).
    for (std::size_t a = 0; a < 3; ++a)
      for (std::size_t b = 0; b < 3; ++b) r.lubrication_virial_full[3 * a + b] += f_i[a] * gap.separation[b];
    if (gap.j != lubrication::no_partner) {
      // −(x_j − x_i) ⊗ F_j with F_j = −F_i.
      add_outer(r.lubrication_virial, gap.separation, f_i, 1.0);
    } else {
      // The plate is body "i" of the pair: −(x_p − x_w) ⊗ F_p, x_p − x_w = −separation.
      add_outer(r.lubrication_virial, gap.separation, f_i, 1.0);
      add_outer(r.plate_virial, gap.separation, f_i, 1.0);
      const Vector3 x = position(p, gap.i);
      const Vector3 point{x[0], x[1], x[2] + gap.separation[2]};
      Vector3& force = r.plate_forces[gap.plate];
      Vector3& moment = r.plate_moments[gap.plate];
      const Vector3 on_plate{-f_i[0], -f_i[1], -f_i[2]};
      for (std::size_t k = 0; k < 3; ++k) force[k] += on_plate[k];
      moment[0] += point[1] * on_plate[2] - point[2] * on_plate[1];
      moment[1] += point[2] * on_plate[0] - point[0] * on_plate[2];
      moment[2] += point[0] * on_plate[1] - point[1] * on_plate[0];
    }
  }
  for (std::size_t c = 0; c < 6; ++c) r.particle_stress[c] = r.lubrication_virial[c] + r.stresslet_sum[c];
}

double CombinedNearField::stable_time_step(const ParticleSnapshot& p, double particle_density) const {
  if (!(particle_density > 0.0))
    throw std::invalid_argument(fmt::format("stable_time_step: particle_density = {}, expected > 0", particle_density));
  const std::size_t n = p.size();
  if (n == 0) return infinity;
  // Explicit damping is stable for δt < 2 m / (row sum of R) (Gershgorin); the row sum is
  // bounded by twice the diagonal for the pair blocks, so δt < m / diag(R) is used.
  const NearFieldScene no_scene{};
  const std::vector<double> v = generalized_velocities(p);
  const System s = assemble(p, no_scene, AmbientFlow{}, v, nullptr);
  double limit = infinity;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = p.radii[i];
    const double m = 4.0 / 3.0 * pi * a * a * a * particle_density;
    const double moment = 0.4 * m * a * a;
    for (std::size_t k = 0; k < 3; ++k) {
      const double translation = s.blocks[36 * i + 7 * k], rotation = s.blocks[36 * i + 7 * (3 + k)];
      if (translation > 0.0) limit = std::min(limit, m / translation);
      if (rotation > 0.0) limit = std::min(limit, moment / rotation);
    }
  }
  return limit;
}

}  // namespace

std::string NearFieldTerms::name() const {
  std::string out;
  const auto add = [&](bool on, std::string_view term) {
    if (!on) return;
    if (!out.empty()) out += '+';
    out += term;
  };
  add(lubrication, "lubrication");
  add(single_particle, "stresslet");
  add(stokes_drag, "stokes_drag");
  add(repulsion, "repulsion");
  return out.empty() ? "none" : out;
}

std::unique_ptr<const NearFieldModel> make_near_field_model(const NearFieldSettings& settings,
                                                            std::shared_ptr<const core::Rheology> matrix) {
  check_settings(settings);
  if (!matrix) throw std::invalid_argument("make_near_field_model: no matrix rheology given");
  const NearFieldTerms& terms = settings.terms;
  // The repulsion settings only bind when the term is on (its length is bounded by the cutoff).
  if (terms.repulsion) {
    if (!terms.lubrication)
      throw std::invalid_argument(
          "hydrodynamics: 'repulsion' needs 'lubrication' (it acts on the lubrication gap list)");
    if (!(settings.repulsion_force > 0.0 && std::isfinite(settings.repulsion_force)))
      throw std::invalid_argument(
          fmt::format("hydrodynamics.repulsion_force = {}, expected > 0 (F_R0 in N)", settings.repulsion_force));
    if (!(settings.repulsion_length >= 1e-3 && settings.repulsion_length <= settings.lubrication_cutoff / 5.0))
      throw std::invalid_argument(fmt::format(
          "hydrodynamics.repulsion_length = {}, expected 1e-3 <= λ/ā <= lubrication_cutoff/5 = {} (the force is "
          "evaluated on the lubrication gap list, so it must have decayed to e⁻⁵ by the cutoff)",
          settings.repulsion_length, settings.lubrication_cutoff / 5.0));
  }
  return std::make_unique<CombinedNearField>(settings, std::move(matrix));
}

}  // namespace rheosim::coupling
