// The settings every LDD step reads (step.hpp).
#include "rheosim/ldd/step.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace rheosim::ldd {

SolverParams SolverParams::for_cavity() {
  SolverParams p;
  p.velocity_tolerance = 1e-8;
  p.neighbour_skin = 0.2;
  p.velocity_preconditioner = Preconditioner::jacobi;
  return p;
}

void SolverParams::check() const {
  const auto require = [&](bool ok, const char* field, double value, const char* range) {
    if (!ok)
      throw std::invalid_argument(fmt::format("LDD solver: {} = {} is out of range, expected {}", field, value, range));
  };
  require(dimension == 2 || dimension == 3, "dimension", dimension, "2 or 3");
  require(density > 0, "density", density, "> 0 kg/m³");
  if (!rheology) throw std::invalid_argument("LDD solver: no rheology law");
  require(gravity.size() == static_cast<std::size_t>(dimension), "gravity entries", static_cast<double>(gravity.size()),
          "one per dimension");
  require(spacing > 0, "spacing", spacing, "> 0 m");
  require(smoothing_ratio >= 1.2 && smoothing_ratio <= 3.0, "smoothing_ratio", smoothing_ratio, "[1.2, 3]");
  require(time_step > 0, "time_step", time_step, "> 0 s");
  require(pressure_tolerance > 0 && pressure_tolerance < 1, "pressure_tolerance", pressure_tolerance, "(0, 1)");
  require(velocity_tolerance > 0 && velocity_tolerance < 1, "velocity_tolerance", velocity_tolerance, "(0, 1)");
  require(max_iterations >= 1, "max_iterations", max_iterations, ">= 1");
  require(max_courant > 0, "max_courant", max_courant, "> 0");
  require(neighbour_skin >= 0 && neighbour_skin <= 1, "neighbour_skin", neighbour_skin, "[0, 1]");
  require(velocity_scale > 0, "velocity_scale", velocity_scale, "> 0 m/s");
  require(length_scale > 0, "length_scale", length_scale, "> 0 m");
  require(pbd_iterations >= 0, "pbd_iterations", pbd_iterations, ">= 0");
  require(pbd_stiffness > 0 && pbd_stiffness <= 1, "pbd_stiffness", pbd_stiffness, "(0, 1]");
  require(pbd_max_shift > 0 && pbd_max_shift <= 0.5, "pbd_max_shift", pbd_max_shift, "(0, 0.5]");
  require(wall_clearance > 0 && wall_clearance < 1, "wall_clearance", wall_clearance, "(0, 1)");
  require(surface_offset > 0 && surface_offset < 1, "surface_offset", surface_offset, "(0, 1)");
  require(surface_count > 0 && surface_count < 1, "surface_count", surface_count, "(0, 1)");
  require(min_moment_rcond > 0 && min_moment_rcond < 1, "min_moment_rcond", min_moment_rcond, "(0, 1)");
  require(surface_moment_rcond > 0 && surface_moment_rcond < 1, "surface_moment_rcond", surface_moment_rcond, "(0, 1)");
  require(surface_fluid_weight >= 0 && surface_fluid_weight < 1, "surface_fluid_weight", surface_fluid_weight,
          "[0, 1)");
  require(surface_cone_angle > 0 && surface_cone_angle < 90, "surface_cone_angle", surface_cone_angle,
          "(0, 90) degrees");
  require(neighbour_reuse_skin >= 0 && neighbour_reuse_skin <= 2, "neighbour_reuse_skin", neighbour_reuse_skin,
          "[0, 2]");
  require(stability_probe_iterations >= 0, "stability_probe_iterations", stability_probe_iterations, ">= 0");
}

void check_step(const StepCheck& c, const SolverParams& params, StepStats& stats) {
  stats.max_speed = c.max_speed;
  stats.courant = stats.max_speed * params.time_step / params.spacing;
  if (!c.finite)
    throw DivergenceError(
        fmt::format("NaN or infinite velocity/pressure at t = {:.6g} s (step {})", c.next_time, c.step));
  if (stats.courant > params.max_courant)
    throw DivergenceError(fmt::format(
        "Courant number max|u|·δt/Δ = {:.3g} exceeds {:.3g} at t = {:.6g} s (step {}, max |u| = {:.4g} m/s{}): reduce "
        "time.step",
        stats.courant, params.max_courant, c.next_time, c.step, stats.max_speed,
        c.where_fastest ? c.where_fastest() : std::string()));
  if (!c.pressure.converged && !(c.pressure.relative_residual < 1e3 * params.pressure_tolerance))
    throw DivergenceError(
        fmt::format("pressure solve failed at t = {:.6g} s (step {}): relative residual {:.3g} after "
                    "{} iterations {}",
                    c.next_time, c.step, c.pressure.relative_residual, c.pressure.iterations,
                    c.pressure_failure ? c.pressure_failure() : std::string()));
  if (!c.velocity_converged && !(stats.velocity_residual < 1e3 * params.velocity_tolerance))
    throw DivergenceError(fmt::format("velocity solve failed at t = {:.6g} s (step {}): relative residual {:.3g}",
                                      c.next_time, c.step, stats.velocity_residual));
  stats.pressure_accepted_unconverged = !c.pressure.converged;
  stats.velocity_accepted_unconverged = !c.velocity_converged;
}

}  // namespace rheosim::ldd
