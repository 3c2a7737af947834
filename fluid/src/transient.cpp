#include "rheosim/fluid/transient.hpp"

#include <cmath>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "transient_impl.hpp"

namespace rheosim::fluid {

namespace {

void check_params(const TransientParams& p) {
  const auto bad = [](const std::string& what) { throw std::invalid_argument("TransientSolver: " + what); };
  if (p.grid.radial_cells < 2)
    bad(fmt::format("grid.radial_cells = {} is out of range, expected >= 2", p.grid.radial_cells));
  if (p.grid.axial_cells < 2)
    bad(fmt::format("grid.axial_cells = {} is out of range, expected >= 2", p.grid.axial_cells));
  // The plate stencils here assume equal wall cells; only the steady swirl solver stretches z.
  if (p.grid.axial_stretching != 0.0)
    bad(fmt::format("grid.axial_stretching = {} is not supported, expected 0 (uniform axial cells)",
                    p.grid.axial_stretching));
  if (!(p.density > 0) || !std::isfinite(p.density))
    bad(fmt::format("density = {} kg/m³ is out of range, expected > 0", p.density));
  if (!p.rheology) bad("rheology must be set");
  if (!std::isfinite(p.top_angular_velocity)) bad("top_angular_velocity must be finite");
  if (!std::isfinite(p.bottom_angular_velocity)) bad("bottom_angular_velocity must be finite");
  if (!std::isfinite(p.axial_gravity)) bad("axial_gravity must be finite");
  if (!(p.max_courant > 0)) bad(fmt::format("max_courant = {} is out of range, expected > 0", p.max_courant));
  if (!(p.pressure_tolerance > 0))
    bad(fmt::format("pressure_tolerance = {} is out of range, expected > 0", p.pressure_tolerance));
  if (p.pressure_max_iterations < 1)
    bad(fmt::format("pressure_max_iterations = {} is out of range, expected >= 1", p.pressure_max_iterations));
  if (p.direct_solver_limit < 0)
    bad(fmt::format("direct_solver_limit = {} is out of range, expected >= 0", p.direct_solver_limit));
  if (!(p.viscous_tolerance > 0))
    bad(fmt::format("viscous_tolerance = {} is out of range, expected > 0", p.viscous_tolerance));
  if (p.viscous_max_iterations < 1)
    bad(fmt::format("viscous_max_iterations = {} is out of range, expected >= 1", p.viscous_max_iterations));
  if (!(p.blow_up_factor > 1)) bad(fmt::format("blow_up_factor = {} is out of range, expected > 1", p.blow_up_factor));
}

TransientParams checked(TransientParams p) {
  check_params(p);
  return p;
}

void check_size(std::string_view name, std::size_t got, std::size_t expected) {
  if (got != expected)
    throw std::invalid_argument(fmt::format("TransientSolver: {} has {} values, expected {}", name, got, expected));
}

}  // namespace

TransientSolver::TransientSolver(TransientParams params) : impl_(std::make_unique<Impl>(checked(std::move(params)))) {}
TransientSolver::~TransientSolver() = default;
TransientSolver::TransientSolver(TransientSolver&&) noexcept = default;
TransientSolver& TransientSolver::operator=(TransientSolver&&) noexcept = default;

StepReport TransientSolver::advance(double dt) { return impl_->advance(dt); }

namespace {
void check_void_fraction(std::span<const double> void_fraction, std::size_t cells) {
  check_size("void_fraction", void_fraction.size(), cells);
  for (std::size_t c = 0; c < void_fraction.size(); ++c)
    if (!(void_fraction[c] > 0 && void_fraction[c] <= 1))
      throw std::invalid_argument(fmt::format(
          "TransientSolver: void_fraction[{}] = {} is out of range, expected 0 < ε <= 1", c, void_fraction[c]));
}
}  // namespace

void TransientSolver::set_void_fraction(std::span<const double> void_fraction) {
  Impl& m = *impl_;
  check_void_fraction(void_fraction, m.g.nc);
  m.eps_next.assign(void_fraction.begin(), void_fraction.end());
}

void TransientSolver::reset_void_fraction(std::span<const double> void_fraction) {
  Impl& m = *impl_;
  check_void_fraction(void_fraction, m.g.nc);
  m.eps_next.assign(void_fraction.begin(), void_fraction.end());
  m.eps_now = m.eps_old = m.eps_next;
}

void TransientSolver::set_pressure(std::span<const double> pressure) {
  Impl& m = *impl_;
  check_size("pressure", pressure.size(), m.g.nc);
  if (!std::all_of(pressure.begin(), pressure.end(), [](double x) { return std::isfinite(x); }))
    throw std::invalid_argument("TransientSolver: pressure contains a non-finite value");
  m.p.assign(pressure.begin(), pressure.end());
  m.remove_volume_mean(m.p);
}

void TransientSolver::set_momentum_source(const MomentumSource& source) {
  Impl& m = *impl_;
  const auto copy = [&](std::string_view name, std::span<const double> in, std::vector<double>& out) {
    if (in.empty()) {
      out.clear();
      return;
    }
    check_size(name, in.size(), m.g.nc);
    for (double x : in)
      if (!std::isfinite(x))
        throw std::invalid_argument(fmt::format("TransientSolver: {} contains a non-finite value", name));
    out.assign(in.begin(), in.end());
  };
  copy("momentum source radial", source.radial, m.source_r);
  copy("momentum source azimuthal", source.azimuthal, m.source_t);
  copy("momentum source axial", source.axial, m.source_z);
  copy("drag_coefficient", source.drag_coefficient, m.drag);
  for (double b : m.drag)
    if (b < 0) throw std::invalid_argument("TransientSolver: drag_coefficient must be >= 0 kg/(m³·s)");
}

void TransientSolver::set_top_angular_velocity(double angular_velocity) {
  if (!std::isfinite(angular_velocity))
    throw std::invalid_argument("TransientSolver: top angular velocity must be finite");
  impl_->params.top_angular_velocity = angular_velocity;
}

void TransientSolver::set_velocity(std::span<const double> radial, std::span<const double> azimuthal,
                                   std::span<const double> axial) {
  Impl& m = *impl_;
  check_size("radial velocity", radial.size(), m.g.n_ur());
  check_size("azimuthal velocity", azimuthal.size(), m.g.nc);
  check_size("axial velocity", axial.size(), m.g.n_uz());
  m.u.ur.assign(radial.begin(), radial.end());
  m.u.ut.assign(azimuthal.begin(), azimuthal.end());
  m.u.uz.assign(axial.begin(), axial.end());
  impose_boundary_values(m.g, m.u);
  m.u_old = m.u;
  m.have_old = false;
  m.update_diagnostics();
}

int TransientSolver::project_velocity() {
  Impl& m = *impl_;
  m.pressure_solver.set_void_fraction(m.eps_now);
  const std::vector<double> flux = m.flux_divergence(m.u, m.eps_now);
  const std::vector<double> magnitude = m.flux_divergence(m.u, m.eps_now, true);
  Eigen::VectorXd b(static_cast<Eigen::Index>(m.g.nc));
  double reference = 0;
  for (std::size_t c = 0; c < m.g.nc; ++c) {
    b[static_cast<Eigen::Index>(c)] = -flux[c];
    reference += magnitude[c] * magnitude[c];
  }
  Eigen::VectorXd phi;
  const auto result = m.pressure_solver.solve(b, phi, m.params.pressure_tolerance, m.params.pressure_max_iterations,
                                              std::sqrt(reference));
  if (!result.converged)
    throw StepError(
        StepFailure::linear_solver,
        fmt::format("TransientSolver::project_velocity: PCG did not converge ({} iterations, residual {:.3g})",
                    result.iterations, result.relative_residual),
        StepReport{});
  m.correct(m.u, phi, 1.0);
  m.u_old = m.u;
  m.have_old = false;
  m.update_diagnostics();
  return result.iterations;
}

std::span<const double> TransientSolver::radial_velocity() const { return impl_->u.ur; }
std::span<const double> TransientSolver::azimuthal_velocity() const { return impl_->u.ut; }
std::span<const double> TransientSolver::axial_velocity() const { return impl_->u.uz; }
std::span<const double> TransientSolver::pressure() const { return impl_->p; }
std::span<const double> TransientSolver::viscosity() const { return impl_->mu_now.centre; }
std::span<const double> TransientSolver::shear_rate() const { return impl_->mu_now.shear_rate; }
std::span<const double> TransientSolver::void_fraction() const { return impl_->eps_now; }

std::vector<double> TransientSolver::divergence() const {
  const Impl& m = *impl_;
  std::vector<double> d = m.flux_divergence(m.u, m.eps_now);
  for (std::size_t i = 0; i < m.g.nr; ++i)
    for (std::size_t j = 0; j < m.g.nt; ++j)
      for (std::size_t k = 0; k < m.g.nz; ++k) d[m.g.cell(i, j, k)] /= m.g.volume(i, k);
  return d;
}

std::vector<CylindricalVelocity> TransientSolver::sample_velocity(std::span<const CylindricalPoint> points) const {
  return impl_->sample(points);
}

double TransientSolver::torque() const { return impl_->torque_top; }
double TransientSolver::bottom_torque() const { return impl_->torque_bottom; }
double TransientSolver::time() const { return impl_->time; }
long TransientSolver::step_count() const { return impl_->steps; }
double TransientSolver::courant_number(double dt) const { return impl_->courant(impl_->u, dt).value; }
const CylindricalGrid& TransientSolver::grid() const { return impl_->grid; }
const TransientParams& TransientSolver::params() const { return impl_->params; }

}  // namespace rheosim::fluid
