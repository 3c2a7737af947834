// Plate torque from the periodic shear cell, model choice, similarity and stiffness scaling
// (see shear_cell.hpp).
#include "rheosim/rheometer/shear_cell.hpp"

#include "rheosim/rheometer/box_point.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "rheosim/core/units.hpp"
#include "rheosim/coupling/shear_cell_point.hpp"
#include "rheosim/dem/contact.hpp"
#include "rheosim/dem/shear_cell_scene.hpp"
#include "rheosim/fluid/swirl.hpp"
#include "rheosim/numerics/quadrature.hpp"
#include "rheosim/rheometer/plate.hpp"

namespace rheosim::rheometer {
namespace {

namespace fs = std::filesystem;
using Model = RheometerCase::SuspensionModel;

constexpr double regime_limit = 1.0;  // Re_p, St, Re_gap at most this: Stokes regime

// Expected cell cost [s]: particles × DEM steps to max_strain at the rate the cell runs (measured
// on this machine: about 3e6 particle-steps/s including the coupling, docs/shear-cell.md).
double cell_cost_seconds(const RheometerCase& r, double phi, double rate, double max_strain, double softening) {
  const auto& p = *r.particles;
  const double length = std::max(8.0 * p.diameter, 3.0 * r.geometry.gap);
  const auto n = static_cast<double>(dem::shear_cell_particle_count(r.geometry.gap, length, length, p.diameter, phi));
  const double dt =
      0.3 * dem::rayleigh_time({0.5 * p.diameter, p.density, p.youngs_modulus / softening, p.poisson_ratio});
  // Near field: ×10–25 the DEM time per step with soft particles (docs/performance.md).
  const double near_field = p.hydrodynamics.terms.any() ? 20.0 : 1.0;
  return std::max(n, 1.0) * max_strain / (rate * dt) / 3e6 * near_field;
}

double inertia_effect(const RheometerCase& r, const core::FluidProperties& fluid, double rate) {
  if (!r.solver.inertia) return 0.0;
  fluid::SwirlParams p;
  p.grid = {r.geometry.radius,    r.geometry.gap,          r.solver.radial_cells,    1,
            r.solver.axial_cells, r.solver.radial_grading, r.solver.axial_stretching};
  p.density = fluid.density;
  p.rheology = fluid.rheology;
  p.tolerance = r.solver.tolerance;
  p.max_iterations = r.solver.max_iterations;
  const double omega = ParallelPlate::from(r.geometry).angular_velocity(rate);
  p.inertia = false;
  const auto creeping = fluid::SwirlSolver(p).solve(omega);
  p.inertia = true;
  const auto full = fluid::SwirlSolver(p).solve(omega);
  if (!creeping.converged || !full.converged) return std::numeric_limits<double>::quiet_NaN();
  return std::abs(full.torque / creeping.torque - 1.0);
}

// One cell run's top-plate stress and its parts [Pa].
struct Measured {
  double rate = 0;
  double stress = 0, error = 0;
  double fluid = 0, contact = 0, lubrication = 0, stresslet = 0, couple = 0, bulk = 0;
  bool converged = false;
};

// Everything the cell learnt about one φ.
struct PhiStudy {
  std::map<double, Measured> measured;  // the runs at the study's stiffness and size, by rate
  [[nodiscard]] const Measured& nearest(double rate) const {
    auto best = measured.begin();
    for (auto it = measured.begin(); it != measured.end(); ++it)
      if (std::abs(std::log(it->first / rate)) < std::abs(std::log(best->first / rate))) best = it;
    return best->second;
  }
  LocalFlowCurve curve;
  double softening = 1.0;         // E used = E / softening
  double stiffness_change = 0.0;  // |τ(E/s) − τ(E/(s/10))| / τ, measured
  double cell_length = 0.0;
  double size_change = 0.0;  // |τ(L) − τ(2L)| / τ, measured (0 when not checked)
  double grid_change = 0.0;  // |τ(2 N_z) − τ(N_z)| / τ: fluid layers doubled, measured
  double linearity_deviation = 0.0;
  double statistical_error = 0.0;  // largest relative standard error of the points used
  bool all_converged = true;
  int cell_runs = 0;
  double wall_time = 0.0;
  std::string summary;                // the choices, for model_reason
  std::vector<std::string> warnings;  // rules the study bent (checks passed on noise)
  // Cost of the whole study, for PointResult's cost split.
  coupling::CostSplit cost;
};

class ShearCellRunner {
 public:
  ShearCellRunner(RheometerCase rheometer, fs::path work_dir, ShearCellOptions options)
      : r_(std::move(rheometer)), work_(std::move(work_dir)), options_(std::move(options)) {}

  PointResult run(const SweepPoint& point, const PointProgressCallback& progress) {
    PointResult out;
    out.model = "shear_cell";
    out.method =
        "periodic shear cell (CFD-DEM: LIGGGHTS box + horizontally averaged fluid column), torque from the "
        "local flow curve";
    if (!r_.particles) {
      out.failure = fmt::format("φ = {:g} needs a particles: section", point.volume_fraction);
      return out;
    }
    if (r_.particles->hydrodynamics.terms.stokes_drag) {
      out.failure =
          "particles.hydrodynamics: stokes_drag is the drag on an imposed flow; the shear cell solves its "
          "fluid column and applies coupling.drag — use lubrication and/or stresslet";
      return out;
    }
    const auto start = std::chrono::steady_clock::now();
    bool fresh = false;
    const PhiStudy& study = study_for(point.volume_fraction, progress, fresh);
    const double rate = point.rim_shear_rate;
    const auto& fluid = r_.fluid;
    const double inertia = inertia_effect(r_, fluid, rate);
    const double linear = study.curve.linear ? study.linearity_deviation : 0.0;
    out.estimated_error =
        std::sqrt(study.statistical_error * study.statistical_error + study.size_change * study.size_change +
                  study.stiffness_change * study.stiffness_change + study.grid_change * study.grid_change +
                  linear * linear + (std::isfinite(inertia) ? inertia * inertia : 0.0));
    out.torque = plate_torque(study.curve, r_.geometry.radius, rate);
    out.torque_creeping = out.torque;
    // Parts of the torque: the stress fractions of the simulated rate nearest to this one.
    const Measured& nearest = study.nearest(rate);
    if (std::isfinite(out.torque) && nearest.stress != 0.0) {
      out.torque_fluid = out.torque * nearest.fluid / nearest.stress;
      out.torque_contact = out.torque * nearest.contact / nearest.stress;
      out.torque_lubrication = out.torque * nearest.lubrication / nearest.stress;
      out.torque_stresslet = out.torque * nearest.stresslet / nearest.stress;
      out.torque_couple = out.torque * nearest.couple / nearest.stress;
    }
    // A cell run that did not meet the steady-state tolerance within its maximum strain still has
    // a last-window mean ± standard error, which the estimated error carries; the point keeps it.
    out.converged = std::isfinite(out.torque) && std::isfinite(out.estimated_error);
    if (!out.converged) out.failure = "the shear cell gave no finite stress";
    out.warnings = study.warnings;
    if (!study.all_converged)
      out.warnings.push_back(
          "shear cell: not every cell run met the steady-state tolerance within its maximum strain; "
          "their last-window means (± standard error, in the estimated error) are used");
    const auto groups = dimensionless_groups(r_, fluid, *r_.particles, rate);
    out.model_reason = fmt::format(
        "{}; this rate: Re_gap {:.3g}, Re_p {:.3g}, St {:.3g}, Bn {:.3g}, μγ̇/E* {:.2g} (softened: {:.2g}){}, liquid "
        "inertia effect {:.2g} %; cell at {:g} 1/s: wall stress {:.4g} Pa = fluid {:.3g} + contact {:.3g} + "
        "lubrication {:.3g} + stresslet {:.3g} + couple {:.3g}, bulk stress from the particle virial {:.4g} Pa "
        "({:+.2g} %)",
        study.all_converged ? study.summary
                            : study.summary +
                                  " (not every cell run met the steady-state tolerance within its "
                                  "maximum strain: last-window means used)",
        groups.gap_reynolds, groups.particle_reynolds, groups.stokes, groups.bingham, groups.stiffness,
        groups.stiffness * study.softening,
        study.curve.linear && std::find(study.curve.shear_rate.begin(), study.curve.shear_rate.end(), rate) ==
                                  study.curve.shear_rate.end()
            ? " (from the linear shortcut, not simulated)"
            : "",
        100.0 * inertia, nearest.rate, nearest.stress, nearest.fluid, nearest.contact, nearest.lubrication,
        nearest.stresslet, nearest.couple, nearest.bulk, 100.0 * (nearest.bulk / nearest.stress - 1.0));
    out.iterations = fresh ? study.cell_runs : 0;
    out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (fresh) {
      out.cost_dem = study.cost.dem;
      out.cost_void_fraction = study.cost.void_fraction;
      out.cost_forces = study.cost.forces;
      out.cost_fluid = study.cost.fluid;
      out.cost_near_field = study.cost.near_field;
    }
    return out;
  }

 private:
  Measured cell(double phi, double rate, double softening, double length, const std::string& tag, PhiStudy& study,
                const PointProgressCallback& progress, int axial_cells = 0) {
    coupling::ShearCellPointSettings s;
    s.gap = r_.geometry.gap;
    s.cell_length = s.cell_width = length;
    s.fluid = r_.fluid;
    s.particles = *r_.particles;  // the solid; its drag and near field follow
    s.particles.volume_fraction = phi;
    s.drag = r_.particles->drag;
    s.particles.youngs_modulus /= softening;
    s.shear_rate = rate;
    s.axial_cells = axial_cells > 0 ? axial_cells : options_.axial_cells;
    const double dt = 0.3 * dem::rayleigh_time({0.5 * s.particles.diameter, s.particles.density,
                                                s.particles.youngs_modulus, s.particles.poisson_ratio});
    s.coupling_interval = std::max(1, static_cast<int>(std::lround(options_.fluid_time_step / dt)));
    s.steady = options_.steady;
    s.run_directory = work_ / fmt::format("cell_phi{:g}", phi) / tag;
    if (const auto& hydrodynamics = r_.particles->hydrodynamics; hydrodynamics.terms.any()) {
      s.near_field = coupling::make_near_field_model(hydrodynamics, s.fluid.rheology);
      // Lubricated suspensions wander over several strain units (φ = 0.3: ±20 % per unit, measured
      // with coupling_validate_near_field_coupled's seed-cell study), so two 2-unit windows can
      // agree by chance: longer windows and a later first decision.
      s.steady.strain_window = std::max(s.steady.strain_window, 4.0);
      s.steady.min_strain = std::max(s.steady.min_strain, 12.0);
      s.steady.max_strain = std::max(s.steady.max_strain, 30.0);
    }
    fs::create_directories(s.run_directory);
    const auto p = coupling::run_shear_cell_point(s);
    {  // One line per cell run, for whoever wants to see what the study measured.
      const fs::path table = work_ / fmt::format("cell_phi{:g}", phi) / "cell_runs.csv";
      const bool header = !fs::exists(table);
      std::ofstream out(table, std::ios::app);
      if (header)
        out << "run,shear_rate,softening,cell_length,axial_cells,particles,stress,stress_error,converged,strain,"
               "fluid,contact,lubrication,stresslet,couple,bulk,wall_time\n";
      out << fmt::format(
          "{},{:g},{:g},{:g},{},{},{:.9g},{:.3g},{},{:.4g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.4g}\n", tag,
          rate, softening, length, s.axial_cells, p.particles, p.stress, p.stress_error, p.converged ? 1 : 0, p.strain,
          p.stress_fluid, p.stress_contact, p.stress_lubrication, p.stress_stresslet, p.stress_couple, p.bulk_stress,
          p.wall_time);
    }
    ++study.cell_runs;
    if (const int cap = coupling::NearFieldSettings{}.max_solver_iterations; p.max_near_field_iterations >= cap)
      study.warnings.push_back(
          fmt::format("near field: implicit solves stopped at their iteration cap ({}) in the cell "
                      "run {}; their forces are the last iterate's",
                      cap, tag));
    if (p.cost.void_fraction_clamped_steps > 0)
      study.warnings.push_back(fmt::format(
          "void fraction: in the cell run {} the layer ε fell below the floor {:g} on {} of {} steps (down to {:.3g}) "
          "and was clamped there: the fluid column carries less solid than the particles",
          tag, s.void_fraction_floor, p.cost.void_fraction_clamped_steps, p.cost.steps, p.cost.min_raw_void_fraction));
    study.wall_time += p.wall_time;
    study.cost.dem += p.cost.dem;
    study.cost.void_fraction += p.cost.void_fraction;
    study.cost.forces += p.cost.forces;
    study.cost.fluid += p.cost.fluid;
    study.cost.near_field += p.cost.near_field;
    if (progress) progress({p.strain, std::numeric_limits<double>::quiet_NaN()});
    return {.rate = rate,
            .stress = p.stress,
            .error = p.stress_error,
            .fluid = p.stress_fluid,
            .contact = p.stress_contact,
            .lubrication = p.stress_lubrication,
            .stresslet = p.stress_stresslet,
            .couple = p.stress_couple,
            .bulk = p.bulk_stress,
            .converged = p.converged};
  }

  // The change between two measurements, and whether it passes: within the tolerance, or within
  // two combined standard errors (what one pair of runs can resolve; then the study says so).
  [[nodiscard]] std::pair<double, bool> compare(const Measured& a, const Measured& b, PhiStudy& study,
                                                const char* check) const {
    const double change = std::abs(a.stress - b.stress) / std::abs(b.stress);
    const double noise = 2.0 * std::hypot(a.error, b.error) / std::abs(b.stress);
    const bool ok = change <= std::max(options_.tolerance, noise);
    if (ok && change > options_.tolerance)
      study.warnings.push_back(fmt::format(
          "shear cell: the {} check passed on noise: stress change {:.2g} % above the {:g} % tolerance but within two "
          "standard errors ({:.2g} %)",
          check, 100.0 * change, 100.0 * options_.tolerance, 100.0 * noise));
    return {change, ok};
  }

  const PhiStudy& study_for(double phi, const PointProgressCallback& progress, bool& fresh) {
    const std::lock_guard lock(mutex_);
    if (const auto it = studies_.find(phi); it != studies_.end()) return it->second;
    fresh = true;
    PhiStudy study;
    const auto& q = *r_.particles;
    const auto& rates = r_.shear_rates;
    const double top_rate = rates.back();
    const double length0 = std::max(8.0 * q.diameter, 3.0 * r_.geometry.gap);
    const auto tag = [](double s, double l, double rate) { return fmt::format("E{:g}_L{:g}_rate{:g}", s, l, rate); };

    // 3. Contact stiffness: the softest E·10⁻ᵏ whose stress matches E·10⁻⁽ᵏ⁻¹⁾.
    std::map<double, Measured> by_softening;
    const auto at = [&](double softening) -> const Measured& {
      auto it = by_softening.find(softening);
      if (it == by_softening.end())
        it = by_softening
                 .emplace(softening,
                          cell(phi, top_rate, softening, length0, tag(softening, length0, top_rate), study, progress))
                 .first;
      return it->second;
    };
    study.softening = 1.0;
    for (int k = options_.softening_decades; k >= 1; --k) {
      const double soft = std::pow(10.0, k);
      const auto [change, ok] = compare(at(soft), at(soft / 10.0), study, "contact stiffness");
      if (ok) {
        study.softening = soft;
        study.stiffness_change = change;
        break;
      }
    }
    // 4. Cell size at that stiffness.
    Measured base = at(study.softening);
    double length = length0;
    for (int doubling = 0; doubling < options_.max_cell_doublings; ++doubling) {
      const Measured bigger = cell(phi, top_rate, study.softening, 2.0 * length,
                                   tag(study.softening, 2.0 * length, top_rate), study, progress);
      const auto [change, ok] = compare(base, bigger, study, "cell size");
      study.size_change = change;
      if (ok) break;
      length *= 2.0;
      base = bigger;
    }
    study.cell_length = length;
    // Sensitivity to the fluid's axial resolution (not a convergence: in unresolved CFD-DEM the
    // layers may not shrink far below a particle): the same run on twice the layers; the change
    // goes into the estimated error.
    {
      const Measured finer =
          cell(phi, top_rate, study.softening, length, tag(study.softening, length, top_rate) + "_finer", study,
               progress, 2 * options_.axial_cells);
      study.grid_change = std::abs(finer.stress - base.stress) / std::abs(base.stress);
    }

    // 2. Similarity: the Stokes shortcut, else every rate.
    const auto& fluid = r_.fluid;
    bool stokes = fluid.rheology->name() == "newtonian";
    for (const double rate : rates) stokes = stokes && dimensionless_groups(r_, fluid, q, rate).stokes_regime();
    std::map<double, Measured> measured{{top_rate, base}};
    const auto measure = [&](double rate) {
      if (!measured.contains(rate))
        measured.emplace(rate,
                         cell(phi, rate, study.softening, length, tag(study.softening, length, rate), study, progress));
    };
    if (stokes && rates.size() >= 3) {
      const double second = rates[rates.size() - 2];
      measure(second);
      const double eta_top = measured[top_rate].stress / top_rate, eta_second = measured[second].stress / second;
      study.linearity_deviation = std::abs(eta_top - eta_second) / eta_top;
      const double noise =
          2.0 * std::hypot(measured[top_rate].error / top_rate, measured[second].error / second) / eta_top;
      study.curve.linear = study.linearity_deviation <= std::max(options_.tolerance, noise);
      if (study.curve.linear && study.linearity_deviation > options_.tolerance)
        study.warnings.push_back(fmt::format(
            "shear cell: the linearity check passed on noise: η changes {:.2g} % between the two highest rates, above "
            "the {:g} % tolerance but within two standard errors ({:.2g} %)",
            100.0 * study.linearity_deviation, 100.0 * options_.tolerance, 100.0 * noise));
    }
    if (!study.curve.linear)
      for (const double rate : rates) measure(rate);
    study.measured = measured;
    for (const auto& [rate, m] : measured) {
      study.curve.shear_rate.push_back(rate);
      study.curve.stress.push_back(m.stress);
      study.statistical_error = std::max(study.statistical_error, m.error / std::abs(m.stress));
      study.all_converged = study.all_converged && m.converged;
    }
    if (study.curve.linear) {  // least squares through the origin
      double sxy = 0, sxx = 0;
      for (std::size_t i = 0; i < study.curve.shear_rate.size(); ++i) {
        sxy += study.curve.shear_rate[i] * study.curve.stress[i];
        sxx += study.curve.shear_rate[i] * study.curve.shear_rate[i];
      }
      study.curve.viscosity = sxy / sxx;
    }
    const double gain = std::sqrt(study.softening);
    study.summary = fmt::format(
        "shear cell {:.3g} mm × {:.3g} mm × H (size check: stress change {:.2g} % on doubling), {} fluid layers "
        "(stress change {:.2g} % with {}), E/{:g} (DEM step {:.3g}× larger; stress change {:.2g} % vs E/{:g}), {} ({} "
        "rates simulated{}), {} cell runs, {:.1f} s",
        1e3 * length, 1e3 * length, 100.0 * study.size_change, options_.axial_cells, 100.0 * study.grid_change,
        2 * options_.axial_cells, study.softening, gain, 100.0 * study.stiffness_change, study.softening / 10.0,
        study.curve.linear ? "Stokes regime with Newtonian matrix: linear local flow curve" : "every rate simulated",
        study.curve.shear_rate.size(),
        study.curve.linear ? fmt::format(", linearity deviation {:.2g} %", 100.0 * study.linearity_deviation) : "",
        study.cell_runs, study.wall_time);
    return studies_.emplace(phi, std::move(study)).first->second;
  }

  RheometerCase r_;
  fs::path work_;
  ShearCellOptions options_;
  std::mutex mutex_;
  std::map<double, PhiStudy> studies_;
};

}  // namespace

bool DimensionlessGroups::stokes_regime() const {
  const double limit = regime_limit * (1.0 + 1e-9);  // the seed sits at Re_p = 1.0 at 100 1/s
  return particle_reynolds <= limit && stokes <= limit && gap_reynolds <= limit;
}

DimensionlessGroups dimensionless_groups(const RheometerCase& r, const core::FluidProperties& fluid,
                                         const coupling::SuspendedParticles& p, double rate) {
  DimensionlessGroups g;
  const double mu = fluid.rheology->viscosity(rate);
  const double a = 0.5 * p.diameter;
  g.gap_reynolds = ParallelPlate::from(r.geometry).gap_reynolds_number(fluid.density, rate, mu);
  g.particle_reynolds = fluid.density * rate * a * a / mu;
  g.stokes = 2.0 / 9.0 * p.density * rate * a * a / mu;
  g.bingham = fluid.rheology->yield_stress() / (mu * rate);
  g.stiffness = mu * rate / (p.youngs_modulus / (2.0 * (1.0 - p.poisson_ratio * p.poisson_ratio)));
  g.gap_over_diameter = r.geometry.gap / p.diameter;
  return g;
}

double LocalFlowCurve::stress_at(double rate) const {
  if (linear) return viscosity * rate;
  const std::size_t n = shear_rate.size();
  if (n == 0) throw std::logic_error("LocalFlowCurve::stress_at: no points");
  if (n == 1) return stress[0] * rate / shear_rate[0];
  if (rate <= 0.0) return 0.0;
  // Segment i spans [γ̇_i, γ̇_{i+1}]; below the first and above the last, extend the end segments.
  std::size_t i = 0;
  while (i + 2 < n && rate > shear_rate[i + 1]) ++i;
  const double exponent = std::log(stress[i + 1] / stress[i]) / std::log(shear_rate[i + 1] / shear_rate[i]);
  return stress[i] * std::pow(rate / shear_rate[i], exponent);
}

double plate_torque(const LocalFlowCurve& curve, double radius, double rim_rate) {
  // T = 2π R³/γ̇_R³ ∫₀^γ̇_R τ(s) s² ds, split at the measured rates (smooth on each piece).
  std::vector<double> edges{0.0};
  for (const double s : curve.shear_rate)
    if (s > 0.0 && s < rim_rate) edges.push_back(s);
  edges.push_back(rim_rate);
  // The first piece is a power law τ = τ(e₁)(s/e₁)^m (the curve's extrapolation towards 0):
  // ∫₀^e₁ τ s² ds = τ(e₁) e₁³/(m + 3) exactly (Gauss would miss the s^(m+2) kink at 0).
  const std::size_t n = curve.shear_rate.size();
  const double exponent = curve.linear || n < 2 ? 1.0
                                                : std::log(curve.stress[1] / curve.stress[0]) /
                                                      std::log(curve.shear_rate[1] / curve.shear_rate[0]);
  double integral = curve.stress_at(edges[1]) * edges[1] * edges[1] * edges[1] / (exponent + 3.0);
  for (std::size_t i = 1; i + 1 < edges.size(); ++i)
    integral += numerics::integrate_gauss_legendre<8>(edges[i], edges[i + 1],
                                                      [&](double s) { return curve.stress_at(s) * s * s; });
  return 2.0 * core::units::pi * radius * radius * radius / (rim_rate * rim_rate * rim_rate) * integral;
}

double estimate_shear_cell_study_cost(const RheometerCase& r, double phi) {
  if (!r.particles || r.shear_rates.empty()) return 0.0;
  const double max_strain = ShearCellOptions{}.steady.max_strain;
  double total = 3.0 * cell_cost_seconds(r, phi, r.shear_rates.back(), max_strain, 1e3);
  for (const double rate : r.shear_rates) total += cell_cost_seconds(r, phi, rate, max_strain, 1e4);
  return total;
}

ModelChoice choose_suspension_model(const RheometerCase& r, double phi, double budget_seconds) {
  const double study = estimate_shear_cell_study_cost(r, phi);
  if (r.suspension_model == Model::lees_edwards)
    return {Model::lees_edwards, "model: lees_edwards in the case file", study};
  if (r.suspension_model == Model::walled_box) return {Model::walled_box, "model: walled_box in the case file", study};
  if (r.suspension_model == Model::full_disk) return {Model::full_disk, "model: full_disk in the case file", study};
  if (r.suspension_model == Model::shear_cell) return {Model::shear_cell, "model: shear_cell in the case file", study};
  if (!r.particles) return {Model::full_disk, "auto: no particles section", study};
  const auto& p = *r.particles;
  const double top_rate = r.shear_rates.back();
  if (!p.hydrodynamics_given || p.hydrodynamics.terms.lubrication) {
    // The predictive model: the near field needs the box, whose cost is fixed in strain.
    std::string limits;
    if (r.geometry.radius < 10.0 * r.geometry.gap)
      limits += fmt::format("; R/H = {:.3g} < 10: the local flow curve misses the rim region",
                            r.geometry.radius / r.geometry.gap);
    if (const auto g = dimensionless_groups(r, r.fluid, p, top_rate); g.gap_reynolds > regime_limit)
      limits += fmt::format("; gap Reynolds number {:.3g} > 1 at {:g} 1/s: the disk's secondary flow is not included",
                            g.gap_reynolds, top_rate);
    const double gap_ratio = r.geometry.gap / p.diameter;
    const bool walled = gap_ratio < walled_box_gap_limit;
    return {walled ? Model::walled_box : Model::lees_edwards,
            fmt::format("auto: {}, the predictive model ({}; `particles.hydrodynamics: {{model: none}}` selects the "
                        "seed's drag-only CFD-DEM){}",
                        walled ? fmt::format("walled box (H/d = {:.3g} < {:g}: the plates are simulated; `model: "
                                             "lees_edwards` gives the bulk stress)",
                                             gap_ratio, walled_box_gap_limit)
                               : fmt::format("Lees–Edwards box (H/d = {:.3g} >= {:g}: the bulk stress)", gap_ratio,
                                             walled_box_gap_limit),
                        p.hydrodynamics_given ? "the case's near field with lubrication" : "no hydrodynamics block",
                        limits),
            study};
  }
  const auto disk = estimate_suspension_cost(r, phi, top_rate, coupling::SteadyStateSettings{}.max_strain);
  const double cell = cell_cost_seconds(r, phi, top_rate, ShearCellOptions{}.steady.max_strain, 1e3);
  const auto costs = fmt::format(
      "full disk ≈ {:.3g} h per point (DEM alone), shear cell ≈ {:.2g} s per run and ≈ {:.2g} s for this φ's study",
      disk.wall_time / 3600.0, cell, study);
  std::string unfit;
  if (p.size_distribution.type != dem::SizeDistribution::Type::none)
    unfit = "a size distribution (the cell is monodisperse)";
  else if (r.geometry.radius < 10.0 * r.geometry.gap)
    unfit = fmt::format("R/H = {:.3g} < 10 (the rim region, which the cell lacks, is a large part of the torque)",
                        r.geometry.radius / r.geometry.gap);
  else if (const auto g = dimensionless_groups(r, r.fluid, p, top_rate); g.gap_reynolds > regime_limit)
    unfit = fmt::format("gap Reynolds number {:.3g} > 1 at {:g} 1/s (the disk's secondary flow is not in the cell)",
                        g.gap_reynolds, top_rate);
  if (!unfit.empty()) {
    if (disk.wall_time <= budget_seconds)
      return {Model::full_disk, fmt::format("auto: full disk because of {}; {}", unfit, costs), study};
    return {Model::shear_cell,
            fmt::format("auto: shear cell although {}, because the full disk is over the point budget of {:g} s; {}",
                        unfit, budget_seconds, costs),
            study};
  }
  if (disk.wall_time <= cell)
    return {Model::full_disk, fmt::format("auto: full disk, cheaper than the cell here; {}", costs), study};
  return {Model::shear_cell,
          fmt::format("auto: shear cell (R/H = {:.3g}, gap Reynolds number <= 1, monodisperse, so the gap is locally "
                      "plane Couette flow); {}",
                      r.geometry.radius / r.geometry.gap, costs),
          study};
}

PointRunner make_shear_cell_suspension_runner(const RheometerCase& rheometer, fs::path work_dir,
                                              ShearCellOptions options) {
  auto runner = std::make_shared<ShearCellRunner>(rheometer, std::move(work_dir), std::move(options));
  return
      [runner](const SweepPoint& point, const PointProgressCallback& progress) { return runner->run(point, progress); };
}

}  // namespace rheosim::rheometer
