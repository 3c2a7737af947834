// The Lees–Edwards suspension box (see suspension_box.hpp for the physics and units).
#include "rheosim/coupling/suspension_box.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <span>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>

#include "rheosim/numerics/conjugate_gradient.hpp"

#include "block_cholesky.hpp"
#include "box_mean_flow.hpp"
#include "lubrication.hpp"
#include "sheared_cell.hpp"

namespace rheosim::coupling {
namespace {

constexpr double pi = std::numbers::pi;
// Forces are in units of 6πμa²γ̇; the lubrication functions take μ, so they get μ = 1/(6π).
constexpr double unit_viscosity = 1.0 / (6.0 * pi);
constexpr double spin_ambient = 0.5;  // Ω∞_y = γ̇/2 for u∞ = γ̇ z e_x

Vector3 operator-(const Vector3& a, const Vector3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vector3 operator+(const Vector3& a, const Vector3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vector3 operator*(double s, const Vector3& a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(const Vector3& a, const Vector3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vector3& a) { return std::sqrt(dot(a, a)); }
Vector3 cross(const Vector3& a, const Vector3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Stress accumulator: full 3×3, [3a + b] = Σ r_a F_b.
using Tensor = std::array<double, 9>;
void add_dyad(Tensor& t, const Vector3& r, const Vector3& f) {
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < 3; ++b) t[3 * a + b] += r[a] * f[b];
}

// One entry of the Verlet list: a pair within the interaction range plus a skin, with the
// tangential spring of its contact (the displacement of i's surface relative to j's, Cundall &
// Strack) carried from step to step.
struct Pair {
  std::size_t i = 0, j = 0;
  Vector3 spring{};
  bool in_contact = false;
};

class Box {
 public:
  explicit Box(const SuspensionBoxSettings& s) : s_(s) {
    place();
    stiffness_ = s_.contact_stiffness > 0.0 ? s_.contact_stiffness : default_contact_stiffness(s_.volume_fraction);
    tangential_ = stiffness_ * s_.tangential_stiffness_ratio;
    SuspensionBoxSettings with_stiffness = s_;
    with_stiffness.contact_stiffness = stiffness_;
    dt_ = s_.strain_step > 0.0 ? s_.strain_step : default_strain_step(with_stiffness);
    const std::size_t n = radius_.size();
    velocity_.assign(6 * n, 0.0);
    // Spheres start with the ambient spin, V' = 0.
    mass_.resize(n);
    inertia_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double a = radius_[i];
      mass_[i] = s_.stokes_number * a * a * a;
      inertia_[i] = 0.4 * mass_[i] * a * a;
    }
    wall_spring_.assign(2 * n, Vector3{});
    wall_contact_.assign(2 * n, false);
    if (cell_.walls && s_.mean_flow_coupling) {
      flow_.emplace(cell_.height, cell_.length * cell_.length, unit_viscosity, s_.stresslet_viscosity_ratio);
      for (std::size_t i = 0; i < n; ++i) flow_->add_sphere(position_[i][2], radius_[i], 0.0, 0.0);
      flow_->relax(1.0);  // the placement's solid fraction, no forces yet
    }
    build_pairs();
  }

  SuspensionBoxResult run() {
    const auto start = std::chrono::steady_clock::now();
    SuspensionBoxResult out;
    out.particles = static_cast<int>(radius_.size());
    out.box_length = cell_.length;
    out.box_height = cell_.height;
    const double volume = cell_.length * cell_.length * cell_.height;
    out.volume_fraction = solid_volume_ / volume;
    out.strain_step = dt_;
    out.contact_stiffness = stiffness_;
    const double stress_unit = 6.0 * pi / volume;  // virial [6πμa³γ̇] → stress [μγ̇]
    out.part_stresslet = 2.5 * out.volume_fraction * s_.stresslet_viscosity_ratio;

    // Block sums of the stress parts, over block_strain each.
    struct Block {
      Tensor lubrication{}, contact{}, repulsion{};
      double plate = 0.0;  // ∫ plate stress dγ [μγ̇] (walled box with the mean flow)
      double strain = 0.0;
    };
    std::vector<Block> blocks;
    Block current;
    double strain = 0.0;
    long solver_iterations = 0;
    double contacts = 0.0, sliding = 0.0, overlap_sum = 0.0;
    long contact_samples = 0;
    double slip_sum = 0.0;
    long slip_samples = 0;
    const auto block_virial = [&](const Block& b) {
      return 1.0 + out.part_stresslet +
             stress_unit * (sym(b.lubrication, 0, 2) + sym(b.contact, 0, 2) + sym(b.repulsion, 0, 2)) / b.strain;
    };
    const auto block_viscosity = [&](const Block& b) { return flow_ ? b.plate / b.strain : block_virial(b); };
    const auto standard_error = [&](const auto& value) {
      BoxMean m;
      const std::size_t k = blocks.size();
      if (k == 0) return m;
      double sum = 0.0, weight = 0.0;
      for (const auto& b : blocks) {
        sum += value(b) * b.strain;
        weight += b.strain;
      }
      m.mean = sum / weight;
      if (k < 2) {
        m.error = std::numeric_limits<double>::infinity();
        return m;
      }
      double var = 0.0;
      for (const auto& b : blocks) var += (value(b) - m.mean) * (value(b) - m.mean);
      m.error = std::sqrt(var / static_cast<double>(k - 1) / static_cast<double>(k));
      return m;
    };

    while (strain < s_.max_strain - 1e-12) {
      const StepLoads loads = step();
      ++out.steps;
      solver_iterations += loads.iterations;
      if (loads.iterations >= s_.max_solver_iterations) ++out.solves_at_iteration_cap;
      out.worst_solver_residual = std::max(out.worst_solver_residual, loads.residual);
      strain += dt_;
      if (strain <= s_.warmup_strain) continue;
      for (std::size_t k = 0; k < 9; ++k) {
        current.lubrication[k] += dt_ * loads.lubrication[k];
        current.contact[k] += dt_ * loads.contact[k];
        current.repulsion[k] += dt_ * loads.repulsion[k];
      }
      current.plate += dt_ * loads.plate_stress;
      current.strain += dt_;
      contacts += static_cast<double>(loads.contacts);
      sliding += static_cast<double>(loads.sliding);
      overlap_sum += loads.overlap_sum;
      out.max_overlap = std::max(out.max_overlap, loads.max_overlap);
      ++contact_samples;
      slip_sum += loads.wall_slip_sum;
      slip_samples += loads.wall_layer;
      if (current.strain >= s_.block_strain - 1e-12) {
        blocks.push_back(current);
        current = Block{};
        if (s_.on_block) s_.on_block(strain);
        const double averaged = strain - s_.warmup_strain;
        if (averaged >= s_.min_averaging_strain - 1e-9 && blocks.size() >= 4) {
          const BoxMean eta = standard_error(block_viscosity);
          if (eta.error <= s_.relative_tolerance * std::abs(eta.mean)) {
            out.converged = true;
            break;
          }
        }
      }
    }
    if (current.strain > 0.5 * s_.block_strain) blocks.push_back(current);
    out.strain = strain;
    for (const auto& b : blocks) out.averaged_strain += b.strain;
    out.relative_viscosity = standard_error(block_viscosity);
    out.n1 = standard_error([&](const Block& b) { return stress_unit * (total(b, 0, 0) - total(b, 2, 2)) / b.strain; });
    out.n2 = standard_error([&](const Block& b) { return stress_unit * (total(b, 2, 2) - total(b, 1, 1)) / b.strain; });
    out.particle_pressure = standard_error([&](const Block& b) {
      return -stress_unit * (total(b, 0, 0) + total(b, 1, 1) + total(b, 2, 2)) / (3.0 * b.strain);
    });
    Block sum;
    for (const auto& b : blocks) {
      for (std::size_t k = 0; k < 9; ++k) {
        sum.lubrication[k] += b.lubrication[k];
        sum.contact[k] += b.contact[k];
        sum.repulsion[k] += b.repulsion[k];
      }
      sum.plate += b.plate;
      sum.strain += b.strain;
    }
    if (sum.strain > 0.0) {
      out.part_lubrication = stress_unit * sym(sum.lubrication, 0, 2) / sum.strain;
      out.part_contact = stress_unit * sym(sum.contact, 0, 2) / sum.strain;
      out.part_repulsion = stress_unit * sym(sum.repulsion, 0, 2) / sum.strain;
      if (flow_) {
        // The plates read the stress; the virial's parts, scaled to it, say where it comes from.
        const double scale = (sum.plate / sum.strain) / block_virial(sum);
        out.part_fluid *= scale;
        out.part_stresslet *= scale;
        out.part_lubrication *= scale;
        out.part_contact *= scale;
        out.part_repulsion *= scale;
        out.core_shear_rate = flow_->mean_shear_rate(cell_.height / 3.0, 2.0 * cell_.height / 3.0);
        out.plate_shear_rate =
            0.5 * (flow_->mean_shear_rate(0.0, 1.0) + flow_->mean_shear_rate(cell_.height - 1.0, cell_.height));
      }
    }
    {
      const std::size_t half = blocks.size() / 2;
      double a = 0.0, wa = 0.0, b = 0.0, wb = 0.0;
      for (std::size_t k = 0; k < blocks.size(); ++k) {
        (k < half ? a : b) += block_viscosity(blocks[k]) * blocks[k].strain;
        (k < half ? wa : wb) += blocks[k].strain;
      }
      out.first_half = wa > 0.0 ? a / wa : std::nan("");
      out.second_half = wb > 0.0 ? b / wb : std::nan("");
    }
    const double n = static_cast<double>(radius_.size());
    out.mean_solver_iterations = out.steps > 0 ? static_cast<double>(solver_iterations) / out.steps : 0.0;
    out.mean_contacts_per_particle = contact_samples > 0 ? 2.0 * contacts / (n * contact_samples) : 0.0;
    out.sliding_fraction = contacts > 0.0 ? sliding / contacts : 0.0;
    out.mean_overlap = contacts > 0.0 ? overlap_sum / contacts : 0.0;
    out.wall_slip = slip_samples > 0 ? slip_sum / static_cast<double>(slip_samples) : 0.0;
    if (!out.converged)
      out.warnings.push_back(fmt::format(
          "suspension box: η_r standard error {:.2g} % after strain {:g} is above the {:g} % tolerance (max_strain); "
          "the mean over strain {:g} is used",
          100.0 * out.relative_viscosity.error / out.relative_viscosity.mean, out.strain, 100.0 * s_.relative_tolerance,
          out.averaged_strain));
    if (out.solves_at_iteration_cap > 0)
      out.warnings.push_back(fmt::format(
          "suspension box: {} of {} implicit solves stopped at the iteration cap {} (worst residual {:.2g} of the "
          "right-hand side, tolerance {:.2g})",
          out.solves_at_iteration_cap, out.steps, s_.max_solver_iterations, out.worst_solver_residual,
          s_.solver_tolerance));
    if (out.max_overlap > 0.05)
      out.warnings.push_back(fmt::format(
          "suspension box: largest contact overlap {:.3g} ā (mean {:.2g} ā) exceeds 5 % of a radius: the contacts are "
          "soft for this stress (contact_stiffness {:g})",
          out.max_overlap, out.mean_overlap, stiffness_));
    out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }

 private:
  struct StepLoads {
    Tensor lubrication{}, contact{}, repulsion{};  // Σ (x_j − x_i) ⊗ F_i [6πμa³γ̇]
    int iterations = 0;
    double residual = 0.0;
    long contacts = 0, sliding = 0;
    double overlap_sum = 0.0, max_overlap = 0.0;
    double wall_slip_sum = 0.0;  // Σ lag behind u∞ over the spheres of the plate layers [āγ̇]
    long wall_layer = 0;
    double plate_stress = 0.0;  // [μγ̇], walled box with the mean flow
  };

  static double sym(const Tensor& t, std::size_t a, std::size_t b) { return 0.5 * (t[3 * a + b] + t[3 * b + a]); }
  static double total(const auto& block, std::size_t a, std::size_t b) {
    return sym(block.lubrication, a, b) + sym(block.contact, a, b) + sym(block.repulsion, a, b);
  }

  // Radii from the classes' volume shares, then random positions with the overlaps relaxed
  // away (each overlapping pair pushed apart along its line of centres until none is left).
  void place() {
    const std::size_t classes = s_.radii.size();
    std::vector<double> per_volume(classes);
    double norm_sum = 0.0;
    for (std::size_t c = 0; c < classes; ++c) {
      per_volume[c] = s_.volume_shares[c] / std::pow(s_.radii[c], 3);
      norm_sum += per_volume[c];
    }
    const auto n_total = static_cast<std::size_t>(s_.particles);
    std::size_t assigned = 0;
    for (std::size_t c = 0; c < classes; ++c) {
      const std::size_t count =
          c + 1 == classes
              ? n_total - assigned
              : static_cast<std::size_t>(std::lround(static_cast<double>(n_total) * per_volume[c] / norm_sum));
      for (std::size_t k = 0; k < count && assigned < n_total; ++k, ++assigned) radius_.push_back(s_.radii[c]);
    }
    solid_volume_ = 0.0;
    for (const double a : radius_) solid_volume_ += 4.0 / 3.0 * pi * a * a * a;
    max_radius_ = *std::max_element(radius_.begin(), radius_.end());
    cell_.walls = s_.wall_gap > 0.0;
    if (cell_.walls) {
      cell_.height = s_.wall_gap;
      cell_.length = std::sqrt(solid_volume_ / (s_.volume_fraction * cell_.height));
    } else {
      cell_.length = cell_.height = std::cbrt(solid_volume_ / s_.volume_fraction);
    }
    const double range = 2.0 * max_radius_ * (1.0 + 0.5 * s_.lubrication_cutoff) + 0.3 * max_radius_;
    if (cell_.walls && cell_.length < 2.0 * range)
      throw std::invalid_argument(fmt::format(
          "suspension box: {} spheres at φ = {:g} between plates {:g} a apart give a side of {:.3g} a, below twice "
          "the interaction range ({:.3g} a); use more spheres",
          radius_.size(), s_.volume_fraction, cell_.height, cell_.length, 2.0 * range));
    const std::size_t n = radius_.size();
    std::mt19937_64 random(s_.seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    position_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      // Between plates the centres stay a radius clear of them.
      const double low = cell_.walls ? radius_[i] : 0.0,
                   span = cell_.walls ? cell_.height - 2.0 * radius_[i] : cell_.height;
      position_[i] = {cell_.length * uniform(random), cell_.length * uniform(random), low + span * uniform(random)};
    }
    // Relaxation, pairs pushed apart and centres kept off the plates.
    for (int sweep = 0; sweep < 20000; ++sweep) {
      double worst = 0.0;
      cell_.for_each_near_pair(position_, 2.0 * max_radius_,
                               [&](std::size_t i, std::size_t j, const Vector3& r, double d) {
                                 const double overlap = radius_[i] + radius_[j] - d;
                                 if (overlap <= 0.0) return;
                                 worst = std::max(worst, overlap);
                                 const Vector3 push = ((0.5 * overlap * 1.05 + 1e-6) / std::max(d, 1e-12)) * r;
                                 position_[i] = position_[i] - push;
                                 position_[j] = position_[j] + push;
                               });
      for (auto& x : position_) cell_.wrap(x);
      if (cell_.walls)
        for (std::size_t i = 0; i < n; ++i)
          position_[i][2] =
              std::clamp(position_[i][2], radius_[i] * (1.0 + 1e-4), cell_.height - radius_[i] * (1.0 + 1e-4));
      if (worst < 1e-4) return;
    }
    throw std::runtime_error(
        fmt::format("suspension box: could not place {} spheres without overlap at φ = {:g}", n, s_.volume_fraction));
  }

  void build_pairs() {
    skin_ = 0.3 * max_radius_;
    const double range = 2.0 * max_radius_ * (1.0 + 0.5 * s_.lubrication_cutoff) + skin_;
    std::unordered_map<std::size_t, Vector3> springs;
    for (const auto& p : pairs_)
      if (p.in_contact) springs.emplace(p.i * radius_.size() + p.j, p.spring);
    pairs_.clear();
    cell_.for_each_near_pair(position_, range, [&](std::size_t i, std::size_t j, const Vector3&, double) {
      Pair p{.i = i, .j = j};
      if (const auto it = springs.find(i * radius_.size() + j); it != springs.end()) {
        p.spring = it->second;
        p.in_contact = true;
      }
      pairs_.push_back(p);
    });
    drift_.assign(radius_.size(), Vector3{});
    strain_since_build_ = 0.0;
  }

  // Affine velocity of j's image relative to i and the ambient spin, as a local 12-vector
  // [U_i Ω_i U_j Ω_j] (plus the fluctuating velocities when given).
  [[nodiscard]] std::array<double, 12> local_velocities(const Pair& p, const Vector3& r, bool with_fluctuation) const {
    std::array<double, 12> v{};
    v[4] = v[10] = spin_ambient;
    v[6] = r[2];  // u∞(x_j) − u∞(x_i) = γ̇ (z_j − z_i) e_x
    if (with_fluctuation)
      for (std::size_t k = 0; k < 6; ++k) {
        v[k] += velocity_[6 * p.i + k];
        v[6 + k] += velocity_[6 * p.j + k];
      }
    return v;
  }

  // A contact's Cundall–Strack tangential spring this step: carried over (its normal part dropped
  // as the pair rotates: it lives in the tangent plane) and held to the Coulomb limit μ_c k_n δ.
  struct TangentialContact {
    Vector3 spring{}, force{};
    bool slides = false;
  };
  [[nodiscard]] TangentialContact tangential_contact(const Vector3& carried, const Vector3& nrm, double overlap) const {
    TangentialContact c;
    c.spring = carried - dot(carried, nrm) * nrm;
    c.force = (-tangential_) * c.spring;
    const double limit = s_.friction * stiffness_ * overlap;
    const double magnitude = norm(c.force);
    if (magnitude > limit) {
      const double scale = magnitude > 0.0 ? limit / magnitude : 0.0;
      c.spring = scale * c.spring;
      c.force = scale * c.force;
      c.slides = true;
    }
    return c;
  }

  // The springs' change over the step is implicit: Δt K has the structure of a lubrication gap
  // (normal: squeeze; tangential, on the relative surface velocity ΔU + (a_iΩ_i + a_jΩ_j)×n:
  // shear, rolling couplings a_i, a_j and a_i², a_i a_j, a_j²); a plate is a_j = 0.
  [[nodiscard]] lubrication::Gap spring_gap(const Vector3& nrm, const Vector3& r, double ai, double aj,
                                            bool slides) const {
    lubrication::Gap g;
    g.n = nrm;
    g.separation = r;
    g.k_squeeze = dt_ * stiffness_;
    if (!slides) {
      const double kt = dt_ * tangential_;
      g.k_shear = kt;
      g.b_i = kt * ai;
      g.b_j = kt * aj;
      g.c_ii = kt * ai * ai;
      g.c_ij = kt * ai * aj;
      g.c_jj = kt * aj * aj;
    }
    return g;
  }

  // Which pair (or sphere and plate) a gap of the implicit system belongs to, and for a contact
  // its explicit force.
  struct GapSource {
    std::size_t pair = 0;
    bool contact = false;
    Vector3 explicit_force{};
    int plate = -1;  // 0 bottom, 1 top; pair is then the sphere
  };

  // A plate at z = 0 (plate 0) or z = H (plate 1): its unit normal from a sphere, and the
  // sphere's velocity relative to it as a local 6-vector [U Ω] (affine, plus V' when given).
  [[nodiscard]] Vector3 plate_normal(int plate) const { return {0.0, 0.0, plate == 0 ? -1.0 : 1.0}; }
  [[nodiscard]] std::array<double, 6> plate_local_velocities(std::size_t i, int plate, bool with_fluctuation) const {
    std::array<double, 6> v{};
    v[0] = position_[i][2] - (plate == 0 ? 0.0 : cell_.height);  // u∞(z_i) − U_plate
    v[4] = spin_ambient;
    if (with_fluctuation)
      for (std::size_t k = 0; k < 6; ++k) v[k] += velocity_[6 * i + k];
    return v;
  }

  // Adds a gap to the implicit system and its drive by the affine motion, −R_gap V∞, to rhs.
  void add_gap(const lubrication::Gap& g, std::size_t pair, const Vector3& r, std::vector<double>& rhs, bool contact,
               const Vector3& explicit_force) {
    gaps_.push_back(g);
    gap_source_.push_back({pair, contact, explicit_force, -1});
    lubrication::Gap local = g;
    local.i = 0;
    local.j = 1;
    const auto v = local_velocities(pairs_[pair], r, false);
    std::array<double, 12> f{};
    lubrication::add_gap_forces(local, v, f, false);
    for (std::size_t c = 0; c < 6; ++c) {
      rhs[6 * g.i + c] += f[c];
      rhs[6 * g.j + c] += f[6 + c];
    }
  }

  void add_plate_gap(const lubrication::Gap& g, int plate, std::vector<double>& rhs, bool contact,
                     const Vector3& explicit_force) {
    gaps_.push_back(g);
    gap_source_.push_back({g.i, contact, explicit_force, plate});
    lubrication::Gap local = g;
    local.i = 0;
    const auto v = plate_local_velocities(g.i, plate, false);
    std::array<double, 6> f{};
    lubrication::add_gap_forces(local, v, f, false);
    for (std::size_t c = 0; c < 6; ++c) rhs[6 * g.i + c] += f[c];
  }

  // The two plates' contacts and lubrication for every sphere near them (walled box).
  void add_plates(std::vector<double>& rhs, StepLoads& loads) {
    for (std::size_t i = 0; i < radius_.size(); ++i)
      for (const int plate : {0, 1}) {
        const double a = radius_[i], z = position_[i][2];
        const double h = plate == 0 ? z - a : cell_.height - z - a;
        const std::size_t slot = 2 * i + static_cast<std::size_t>(plate);
        const Vector3 nrm = plate_normal(plate);
        const Vector3 r{0.0, 0.0, (plate == 0 ? 0.0 : cell_.height) - z};  // the plate point under i, minus x_i
        if (h < 2.0 * a) {                                                 // the layer whose slip is reported
          const double lag = -velocity_[6 * i];
          loads.wall_slip_sum += plate == 0 ? -lag : lag;
          ++loads.wall_layer;
        }
        if (h < 0.0) {  // contact, as between spheres (Cundall & Strack) with the plate as partner
          const double overlap = -h;
          const Vector3 normal_force = (-stiffness_ * overlap) * nrm;
          const auto [spring, tangential_force, slides] =
              tangential_contact(wall_contact_[slot] ? wall_spring_[slot] : Vector3{}, nrm, overlap);
          wall_spring_[slot] = spring;
          wall_contact_[slot] = true;
          const Vector3 force = normal_force + tangential_force;
          const Vector3 torque = cross(a * nrm, tangential_force);
          lubrication::Gap g = spring_gap(nrm, r, a, 0.0, slides);
          g.i = i;
          g.plate = static_cast<std::size_t>(plate);
          add_plate_gap(g, plate, rhs, true, force);
          for (std::size_t c = 0; c < 3; ++c) {
            rhs[6 * i + c] += force[c];
            rhs[6 * i + 3 + c] += torque[c];
          }
          ++loads.contacts;
          loads.sliding += slides ? 1 : 0;
          loads.overlap_sum += overlap / a;
          loads.max_overlap = std::max(loads.max_overlap, overlap / a);
        } else {
          wall_contact_[slot] = false;
          wall_spring_[slot] = {};
        }
        if (h < s_.lubrication_cutoff * a) {
          lubrication::Gap g;
          g.i = i;
          g.plate = static_cast<std::size_t>(plate);
          g.n = nrm;
          g.separation = r;
          double viscosity = unit_viscosity;
          if (s_.viscosity_ratio) {
            lubrication::Gap probe = g;
            probe.i = 0;
            const auto v = plate_local_velocities(i, plate, true);
            const double slip = lubrication::surface_slip_speed(probe, a, 0.0, v);
            viscosity *= s_.viscosity_ratio(std::max(slip / (std::max(h, 0.0) + s_.roughness * a), 1.0));
          }
          lubrication::set_plate_coefficients(g, a, h, viscosity, s_.roughness);
          add_plate_gap(g, plate, rhs, false, {});
        }
      }
  }

  StepLoads step() {
    const std::size_t n = radius_.size();
    StepLoads loads;
    gaps_.clear();
    gap_source_.clear();
    std::vector<double> rhs(6 * n, 0.0);
    std::vector<Vector3> separations(pairs_.size());
    // Known forces: contacts and repulsion (explicit), the lubrication of the affine motion, inertia.
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      Pair& p = pairs_[k];
      const Vector3 r = cell_.separation(position_[p.i], position_[p.j]);
      separations[k] = r;
      const double d = norm(r);
      const double ai = radius_[p.i], aj = radius_[p.j], mean = 0.5 * (ai + aj);
      const double h = d - ai - aj;
      const Vector3 nrm = (1.0 / d) * r;
      Vector3 force_i{}, torque_i{}, torque_j{};
      if (h < 0.0) {  // contact
        const double overlap = -h;
        const Vector3 normal_force = (-stiffness_ * overlap) * nrm;  // on i, away from j
        const auto [spring, tangential_force, slides] =
            tangential_contact(p.in_contact ? p.spring : Vector3{}, nrm, overlap);
        p.spring = spring;
        p.in_contact = true;
        force_i = normal_force + tangential_force;
        torque_i = cross(ai * nrm, tangential_force);
        torque_j = cross(aj * nrm, tangential_force);  // −a_j n × (−F_t)
        lubrication::Gap g = spring_gap(nrm, r, ai, aj, slides);
        g.i = p.i;
        g.j = p.j;
        add_gap(g, k, r, rhs, true, force_i);
        ++loads.contacts;
        loads.sliding += slides ? 1 : 0;
        loads.overlap_sum += overlap / mean;
        loads.max_overlap = std::max(loads.max_overlap, overlap / mean);
      } else {
        p.in_contact = false;
        p.spring = {};
      }
      if (h < s_.lubrication_cutoff * mean) {
        if (s_.repulsion_force > 0.0) {
          const double f = s_.repulsion_force * std::exp(-std::max(h, 0.0) / (s_.repulsion_length * mean));
          const Vector3 rep = (-f) * nrm;
          force_i = force_i + rep;
          add_dyad(loads.repulsion, r, rep);
        }
        lubrication::Gap g;
        g.i = p.i;
        g.j = p.j;
        g.n = nrm;
        g.separation = r;
        double viscosity = unit_viscosity;
        if (s_.viscosity_ratio) {
          // The gap's own rate |v_s|/h_eff from the last step's velocities, not below γ̇.
          lubrication::Gap probe = g;
          lubrication::set_pair_coefficients(probe, ai, aj, h, unit_viscosity, s_.roughness);
          const auto v = local_velocities(p, r, true);
          probe.i = 0;
          probe.j = 1;
          const double slip = lubrication::surface_slip_speed(probe, ai, aj, v);
          const double rate = slip / (std::max(h, 0.0) + s_.roughness * mean);
          viscosity *= s_.viscosity_ratio(std::max(rate, 1.0));
        }
        lubrication::set_pair_coefficients(g, ai, aj, h, viscosity, s_.roughness);
        add_gap(g, k, r, rhs, false, {});
      }
      for (std::size_t c = 0; c < 3; ++c) {
        rhs[6 * p.i + c] += force_i[c];
        rhs[6 * p.j + c] -= force_i[c];
        rhs[6 * p.i + 3 + c] += torque_i[c];
        rhs[6 * p.j + 3 + c] += torque_j[c];
      }
    }
    if (cell_.walls) add_plates(rhs, loads);
    if (flow_)
      for (std::size_t i = 0; i < n; ++i) {
        // Drag and rotation relative to the liquid's profile instead of u∞ (V' stays relative to u∞).
        const double a = radius_[i], z = position_[i][2];
        rhs[6 * i] += a * (flow_->velocity(z) - z);
        rhs[6 * i + 4] += 4.0 / 3.0 * a * a * a * 0.5 * (flow_->shear_rate(z) - 1.0);
      }
    if (s_.stokes_number > 0.0)
      for (std::size_t i = 0; i < n; ++i) {
        const double m = mass_[i] / dt_, rot = inertia_[i] / dt_;
        for (std::size_t c = 0; c < 3; ++c) {
          rhs[6 * i + c] += m * velocity_[6 * i + c];
          rhs[6 * i + 3 + c] += rot * velocity_[6 * i + 3 + c];
        }
        rhs[6 * i] -= mass_[i] * velocity_[6 * i + 2];  // −m u'_z e_x: the ambient flow's own acceleration
      }
    solve(rhs, loads);

    // Stress of the solved motion: lubrication, and the contacts' forces at the end of the step
    // (explicit part + implicit change); the tangential springs advance with the new velocities.
    std::array<double, 2> plate_force{};  // x force of each plate on the spheres
    for (std::size_t g = 0; g < gaps_.size(); ++g) {
      const GapSource& source = gap_source_[g];
      lubrication::Gap local = gaps_[g];
      local.i = 0;
      if (source.plate >= 0) {
        const Vector3 f = lubrication::gap_force_on_i(local, plate_local_velocities(gaps_[g].i, source.plate, true));
        const Vector3 total = source.contact ? source.explicit_force + f : f;
        add_dyad(source.contact ? loads.contact : loads.lubrication, gaps_[g].separation, total);
        plate_force[static_cast<std::size_t>(source.plate)] += total[0];
        continue;
      }
      const Pair& p = pairs_[source.pair];
      local.j = 1;
      const Vector3& r = separations[source.pair];
      const auto v = local_velocities(p, r, true);
      const Vector3 f = lubrication::gap_force_on_i(local, v);
      if (source.contact)
        add_dyad(loads.contact, r, source.explicit_force + f);
      else
        add_dyad(loads.lubrication, r, f);
    }
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      Pair& p = pairs_[k];
      if (!p.in_contact) continue;
      const auto v = local_velocities(p, separations[k], true);
      const Vector3 nrm = (1.0 / norm(separations[k])) * separations[k];
      const Vector3 du{v[0] - v[6], v[1] - v[7], v[2] - v[8]};
      const Vector3 spin = radius_[p.i] * Vector3{v[3], v[4], v[5]} + radius_[p.j] * Vector3{v[9], v[10], v[11]};
      Vector3 slip = du + cross(spin, nrm);
      slip = slip - dot(slip, nrm) * nrm;
      p.spring = p.spring + dt_ * slip;
    }
    for (std::size_t slot = 0; slot < wall_contact_.size(); ++slot) {
      if (!wall_contact_[slot]) continue;
      const std::size_t i = slot / 2;
      const int plate = static_cast<int>(slot % 2);
      const auto v = plate_local_velocities(i, plate, true);
      const Vector3 nrm = plate_normal(plate);
      Vector3 slip = Vector3{v[0], v[1], v[2]} + cross(radius_[i] * Vector3{v[3], v[4], v[5]}, nrm);
      slip = slip - dot(slip, nrm) * nrm;
      wall_spring_[slot] = wall_spring_[slot] + dt_ * slip;
    }
    if (flow_) {
      // The liquid takes the reaction of each sphere's drag and couple; the plates read τ₀ less
      // their share of the liquid's load, plus what they exert on the spheres directly.
      for (std::size_t i = 0; i < n; ++i) {
        const double a = radius_[i], z = position_[i][2];
        const double slip = z + velocity_[6 * i] - flow_->velocity(z);
        const double spin = 0.5 + velocity_[6 * i + 4] - 0.5 * flow_->shear_rate(z);
        flow_->add_sphere(z, a, a * slip, 4.0 / 3.0 * a * a * a * spin);
      }
      flow_->relax(std::min(1.0, dt_ / s_.mean_flow_relaxation));
      const double area = cell_.length * cell_.length;
      loads.plate_stress = 6.0 * pi * (flow_->liquid_stress() + 0.5 * (plate_force[1] - plate_force[0]) / area);
    }
    // Move: affine + fluctuating, then the Lees–Edwards wrap.
    double max_drift = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vector3 u{velocity_[6 * i], velocity_[6 * i + 1], velocity_[6 * i + 2]};
      if (!std::isfinite(u[0] + u[1] + u[2]))
        throw std::runtime_error(fmt::format("suspension box diverged at strain {:.4g}: non-finite velocity", strain_));
      position_[i] = position_[i] + dt_ * u;
      position_[i][0] += dt_ * position_[i][2];
      drift_[i] = drift_[i] + dt_ * u;
      max_drift = std::max(max_drift, norm(drift_[i]));
    }
    strain_ += dt_;
    strain_since_build_ += dt_;
    cell_.offset = std::fmod(cell_.offset + dt_ * cell_.length, cell_.length);
    for (auto& x : position_) cell_.wrap(x);
    if (cell_.walls)
      for (const auto& x : position_)
        if (!(x[2] > 0.0 && x[2] < cell_.height))
          throw std::runtime_error(
              fmt::format("suspension box diverged at strain {:.4g}: a sphere passed through a plate", strain_));
    if (loads.max_overlap > 1.0)
      throw std::runtime_error(fmt::format(
          "suspension box diverged at strain {:.4g}: a contact overlaps by {:.3g} radii (contact stiffness {:g})",
          strain_, loads.max_overlap, stiffness_));
    const double range = 2.0 * max_radius_ * (1.0 + 0.5 * s_.lubrication_cutoff);
    if (2.0 * max_drift + strain_since_build_ * range > skin_) build_pairs();
    return loads;
  }

  // (M/Δt + D + R_lub) V' = rhs by conjugate gradients, block-Jacobi preconditioned, from the
  // last step's V'.
  void solve(const std::vector<double>& rhs, StepLoads& loads) {
    const std::size_t n = radius_.size(), m = 6 * n;
    std::vector<double> diagonal(m);
    for (std::size_t i = 0; i < n; ++i) {
      const double a = radius_[i];
      for (std::size_t c = 0; c < 3; ++c) {
        diagonal[6 * i + c] = a + (s_.stokes_number > 0.0 ? mass_[i] / dt_ : 0.0);
        diagonal[6 * i + 3 + c] = 4.0 / 3.0 * a * a * a + (s_.stokes_number > 0.0 ? inertia_[i] / dt_ : 0.0);
      }
    }
    factor_.assign(36 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 6; ++c) factor_[36 * i + 7 * c] = diagonal[6 * i + c];
    for (const auto& g : gaps_) lubrication::add_gap_self_blocks(g, factor_);
    for (std::size_t i = 0; i < n; ++i) cholesky_6(factor_.data() + 36 * i);

    const auto apply = [&](std::span<const double> x, std::span<double> y) {
      for (std::size_t k = 0; k < m; ++k) y[k] = diagonal[k] * x[k];
      scratch_.assign(m, 0.0);
      for (const auto& g : gaps_) lubrication::add_gap_forces(g, x, scratch_, false);  // −R_gap x
      for (std::size_t k = 0; k < m; ++k) y[k] -= scratch_[k];
    };
    const auto precondition = [&](std::span<const double> x, std::span<double> y) {
      for (std::size_t i = 0; i < n; ++i) cholesky_6_solve(factor_.data() + 36 * i, x.data() + 6 * i, y.data() + 6 * i);
    };
    numerics::ConjugateGradientSettings cg;
    cg.relative_tolerance = s_.solver_tolerance;
    cg.max_iterations = s_.max_solver_iterations;
    const numerics::KrylovResult solved =
        numerics::conjugate_gradient(apply, precondition, rhs, velocity_, cg, cg_work_);
    loads.iterations = solved.iterations;
    loads.residual = solved.relative_residual;
  }

  SuspensionBoxSettings s_;
  std::vector<double> radius_, mass_, inertia_;
  std::vector<Vector3> position_, drift_;
  std::vector<double> velocity_;  // V' = V − V∞, 6 per sphere [aγ̇, γ̇]
  std::vector<Pair> pairs_;
  std::optional<BoxMeanFlow> flow_;   // walled box with mean_flow_coupling
  std::vector<Vector3> wall_spring_;  // tangential springs of the plate contacts, 2 per sphere
  std::vector<bool> wall_contact_;
  std::vector<lubrication::Gap> gaps_;
  std::vector<GapSource> gap_source_;
  std::vector<double> factor_, scratch_;
  numerics::ConjugateGradientWorkspace cg_work_;
  ShearedCell cell_;
  double solid_volume_ = 0.0, max_radius_ = 0.0, skin_ = 0.0;
  double strain_ = 0.0, strain_since_build_ = 0.0;
  double stiffness_ = 0.0, tangential_ = 0.0, dt_ = 0.0;
};

}  // namespace

SuspensionBoxResult run_suspension_box(const SuspensionBoxSettings& settings) {
  check_suspension_box_settings(settings);
  Box box(settings);
  return box.run();
}

}  // namespace rheosim::coupling
