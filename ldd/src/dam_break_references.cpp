#include "dam_break_references.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rheosim/core/output.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd::detail {

namespace {

using core::finite_or_empty;

// The seed's LDD column for this Δ and δt, if it ran one (Table 1).
const double* table1_column(double spacing, double dt) {
  const auto close = [](double a, double b) { return std::abs(a / b - 1) < 1e-6; };
  if (close(spacing, 1e-3) && close(dt, 1e-3)) return DamBreakReference::ldd_1mm_dt1e3;
  if (close(spacing, 1e-3) && close(dt, 1e-4)) return DamBreakReference::ldd_1mm_dt1e4;
  if (close(spacing, 2e-3) && close(dt, 1e-3)) return DamBreakReference::ldd_2mm_dt1e3;
  if (close(spacing, 2e-3) && close(dt, 1e-4)) return DamBreakReference::ldd_2mm_dt1e4;
  return nullptr;
}

void compare_with_table1(const CaseSettings& l, const std::vector<double>& front_time, const std::vector<double>& front,
                         const std::filesystem::path& out_dir, RunSummary& summary, const core::Log& log) {
  // LDD Table 1 layout: time, experiment, this run, the seed's LDD for the same Δ and δt.
  const double* paper = table1_column(l.spacing, l.time_step);
  core::CsvTable table({{"time", "s"}, {"experiment", "m"}, {"front", "m"}, {"error", "m"}, {"ldd_seed", "m"}});
  Table1Comparison comparison;
  std::string text = fmt::format(
      "Mass front position, LDD Table 1 layout (Δ = {} mm, δt = {:g} s; seed LDD column for the same Δ, δt)\n"
      "{:>8} {:>10} {:>12} {:>10} {:>10}\n",
      l.spacing * 1e3, l.time_step, "Time (s)", "Exp. (m)", "this run (m)", "error (m)", "seed (m)");
  double sum2 = 0, worst = 0;
  int counted = 0;
  for (std::size_t q = 0; q < 6; ++q) {
    const double time = DamBreakReference::times[q], exp = DamBreakReference::experiment[q];
    const double x = interpolate(front_time, front, time);
    const double seed = paper ? paper[q] : std::numeric_limits<double>::quiet_NaN();
    table.add_row({time, exp, x, x - exp, seed});
    comparison.rows.push_back(
        {time, exp, finite_or_empty(x), finite_or_empty(x - exp), paper ? MaybeNumber(seed) : std::nullopt});
    text += fmt::format("{:>8.2f} {:>10.3f} {:>12.3f} {:>+10.3f} {:>10}\n", time, exp, x, x - exp,
                        paper ? fmt::format("{:.3f}", seed) : std::string("-"));
    if (std::isfinite(x)) {
      sum2 += (x - exp) * (x - exp);
      worst = std::max(worst, std::abs(x - exp));
      ++counted;
    }
  }
  const double rms = counted > 0 ? std::sqrt(sum2 / counted) : std::numeric_limits<double>::quiet_NaN();
  text += fmt::format("RMS error vs experiment {:.4f} m, max {:.4f} m ({} of 6 times reached)\n", rms, worst, counted);
  core::write_csv(out_dir / "table1.csv", table);
  core::write_atomically(out_dir / "table1.txt", [&](std::ostream& os) { os << text; });
  comparison.rms_error = finite_or_empty(rms);
  comparison.max_error = worst;
  summary.table1 = std::move(comparison);
  log.info("{}", text);
}

// The front from the gate, x, is the water column's Z = (x + a)/a; T = t√(2g/a).
void compare_with_martin_moyce(const CaseSettings& l, const DamBreakScene& scene, const std::vector<double>& front_time,
                               const std::vector<double>& front, const std::filesystem::path& out_dir,
                               RunSummary& summary, const core::Log& log) {
  const double a = scene.reservoir[0];
  const double time_scale = std::sqrt(a / (2.0 * l.gravity_magnitude()));  // t = T·√(a/2g)
  core::CsvTable table({{"time", "s"},
                        {"experiment", "m"},
                        {"front", "m"},
                        {"T", ""},
                        {"Z_experiment", ""},
                        {"Z", ""},
                        {"relative_error", ""}});
  MartinMoyceComparison comparison;
  std::string text = fmt::format(
      "Front Z = x/a against Martin & Moyce (1952), n² = 2, a = {:g} m (x from the back wall)\n{:>7} {:>8} {:>8} "
      "{:>10}\n",
      a, "T", "Z (M&M)", "Z (LDD)", "difference");
  double worst = 0;
  int counted = 0;
  for (std::size_t q = 0; q < std::size(WaterColumnReference::times); ++q) {
    const double T = WaterColumnReference::times[q], z_exp = WaterColumnReference::fronts[q];
    const double t = T * time_scale;
    const double x = interpolate(front_time, front, t);
    const double z = (x + a) / a, error = z / z_exp - 1.0;
    table.add_row({t, (z_exp - 1.0) * a, x, T, z_exp, z, error});
    comparison.rows.push_back({T, z_exp, finite_or_empty(z), finite_or_empty(error)});
    text += std::isfinite(z) ? fmt::format("{:>7.3f} {:>8.3f} {:>8.3f} {:>+9.1f} %\n", T, z_exp, z, 100 * error)
                             : fmt::format("{:>7.3f} {:>8.3f} {:>8} {:>10}\n", T, z_exp, "-", "not reached");
    if (std::isfinite(error)) {
      worst = std::max(worst, std::abs(error));
      ++counted;
    }
  }
  text += fmt::format("largest difference {:.1f} % ({} of {} times reached)\n", 100 * worst, counted,
                      std::size(WaterColumnReference::times));
  core::write_csv(out_dir / "martin_moyce.csv", table);
  if (counted > 0) comparison.max_relative_error = worst;
  summary.martin_moyce = std::move(comparison);
  log.info("{}", text);
}

// LDD §4.3's release, the only one Table 1's experiment is for: the 2 m × 0.1 m reservoir of a
// Bingham material with ρ = 1200 kg/m³, μ_B = 25 Pa·s, τ_B = 25 Pa (any regularisation).
bool is_table1_release(const CaseSettings& l, const DamBreakScene& scene) {
  const auto close = [](double a, double b) { return std::abs(a / b - 1) < 1e-6; };
  if (l.fluid.rheology->name() != "bingham" || !close(scene.reservoir[0], 2.0) || !close(scene.reservoir[1], 0.1) ||
      !close(l.fluid.density, 1200.0))
    return false;
  bool plastic = false, yield = false;
  for (const auto& p : l.fluid.rheology->parameters()) {
    if (p.name == "plastic_viscosity") plastic = close(p.value, 25.0);
    if (p.name == "yield_stress") yield = close(p.value, 25.0);
  }
  return plastic && yield;
}

// The front at the end of the run against the shallow yield-stress arrest (ThinFilmArrest), and
// the yield stress and runout the final surface implies as one (fit_thin_film_deposit).
void compare_with_thin_film_arrest(const CaseSettings& l, const ThinFilmArrest& arrest, const DamBreakScene& scene,
                                   const std::vector<double>& front, const FinalProfile& final_surface,
                                   RunSummary& summary, const core::Log& log) {
  const double length = scene.reservoir[0];
  ThinFilmArrestComparison entry;
  entry.length = arrest.length;
  entry.front = arrest.length - length;
  entry.wall_height = arrest.wall_height;
  if (!front.empty()) {
    const double runout = front.back() + length;  // from the back wall
    entry.relative_error = runout / arrest.length - 1.0;
    log.info(
        "thin-film arrest (shallow yield-stress limit): length {:.4g} m from the back wall (front {:.4g} m), wall "
        "height {:.4g} m; this run ends at {:.4g} m ({:+.1f} %)",
        arrest.length, arrest.length - length, arrest.wall_height, runout, 1e2 * (runout / arrest.length - 1.0));
  }
  std::vector<double> distance(final_surface.x.size());
  for (std::size_t k = 0; k < distance.size(); ++k) distance[k] = final_surface.x[k] + length;
  const double yield_stress = l.fluid.rheology->yield_stress();
  if (const auto fit =
          fit_thin_film_deposit(distance, final_surface.height, l.spacing, l.fluid.density, l.gravity_magnitude())) {
    entry.fitted_yield_stress = fit->yield_stress;
    entry.fitted_length = fit->length;
    entry.fitted_rms_height_error = fit->rms_height_error;
    log.info(
        "final free surface read as a shallow arrest ({} columns, rms height error {:.3g} m): yield stress {:.4g} Pa "
        "(the law's {:.4g} Pa, {:+.1f} %), runout {:.4g} m from the back wall",
        fit->columns, fit->rms_height_error, fit->yield_stress, yield_stress,
        1e2 * (fit->yield_stress / yield_stress - 1.0), fit->length);
  } else {
    log.info("final free surface: fewer than three columns two spacings high, no shallow-arrest fit");
  }
  summary.thin_film_arrest = entry;
}

}  // namespace

bool floor_is_horizontal(const CaseSettings& l) {
  return l.gravity.size() == 2 && l.gravity[1] < 0 && std::abs(l.gravity[0]) <= 1e-12 * l.gravity_magnitude();
}

std::optional<ThinFilmArrest> dam_break_thin_film_arrest(const CaseSettings& l) {
  const double yield_stress = l.fluid.rheology->yield_stress();
  if (!(yield_stress > 0) || !floor_is_horizontal(l)) return std::nullopt;
  const auto& scene = std::get<DamBreakScene>(l.scene);
  return thin_film_arrest(scene.reservoir[0] * scene.reservoir[1], yield_stress, l.fluid.density,
                          l.gravity_magnitude());
}

void compare_dam_break_front(const CaseSettings& l, const std::vector<double>& front_time,
                             const std::vector<double>& front, const FinalProfile& final_surface,
                             const std::filesystem::path& out_dir, RunSummary& summary, const core::Log& log) {
  const auto& scene = std::get<DamBreakScene>(l.scene);
  const std::string law(l.fluid.rheology->name());
  const double aspect = scene.reservoir[1] / scene.reservoir[0];
  if (!floor_is_horizontal(l)) {
    log.info(
        "no reference for this dam break: gravity [{:g}, {:g}] m/s² is not vertical, and the shallow arrest, "
        "LDD Table 1 and Martin & Moyce are for a horizontal floor",
        l.gravity[0], l.gravity[1]);
    return;
  }
  if (const auto arrest = dam_break_thin_film_arrest(l))
    compare_with_thin_film_arrest(l, *arrest, scene, front, final_surface, summary, log);
  if (is_table1_release(l, scene)) {
    compare_with_table1(l, front_time, front, out_dir, summary, log);
  } else if (law == "newtonian" && std::abs(aspect / WaterColumnReference::height_over_width - 1.0) < 1e-6) {
    compare_with_martin_moyce(l, scene, front_time, front, out_dir, summary, log);
  } else {
    log.info(
        "no experiment for this dam break: LDD Table 1 is for §4.3's release (a 2 m × 0.1 m reservoir of a Bingham "
        "material, ρ 1200 kg/m³, μ_B 25 Pa s, τ_B 25 Pa), Martin & Moyce for a Newtonian liquid in a reservoir twice "
        "as high as long ({} here, height/length {:.3g})",
        law, aspect);
  }
}

}  // namespace rheosim::ldd::detail

namespace rheosim::ldd {

ThinFilmArrest thin_film_arrest(double area, double yield_stress, double density, double gravity) {
  if (!(area > 0 && yield_stress > 0 && density > 0 && gravity > 0))
    throw std::invalid_argument("thin_film_arrest: area, yield stress, density and gravity must be > 0");
  ThinFilmArrest a;
  a.stress_scale = 2.0 * yield_stress / (density * gravity);
  // A = ∫₀^ℓ √(c(ℓ − s)) ds = (2/3)√c ℓ^{3/2}
  a.length = std::pow(1.5 * area / std::sqrt(a.stress_scale), 2.0 / 3.0);
  a.wall_height = std::sqrt(a.stress_scale * a.length);
  return a;
}

double ThinFilmArrest::height_at(double s) const {
  return s < length ? std::sqrt(stress_scale * (length - std::max(s, 0.0))) : 0.0;
}

std::optional<ThinFilmFit> fit_thin_film_deposit(std::span<const double> distance_from_back_wall,
                                                 std::span<const double> height, double spacing, double density,
                                                 double gravity) {
  if (distance_from_back_wall.size() != height.size())
    throw std::invalid_argument("fit_thin_film_deposit: distances and heights differ in size");
  if (!(spacing > 0 && density > 0 && gravity > 0))
    throw std::invalid_argument("fit_thin_film_deposit: spacing, density and gravity must be > 0");
  // The columns resolved by two nodes or more, away from the back wall's.
  std::vector<std::pair<double, double>> columns;  // (s, h)
  for (std::size_t k = 0; k < height.size(); ++k)
    if (distance_from_back_wall[k] >= 2.0 * spacing && height[k] >= 2.0 * spacing)
      columns.emplace_back(distance_from_back_wall[k], height[k]);
  // h² = a + b s by least squares; then 2τ/(ρg) = −b and ℓ = −a/b.
  const auto n = static_cast<double>(columns.size());
  double sum_s = 0, sum_q = 0, sum_ss = 0, sum_sq = 0;
  for (const auto& [s, h] : columns) {
    const double q = h * h;
    sum_s += s;
    sum_q += q;
    sum_ss += s * s;
    sum_sq += s * q;
  }
  const double spread = n * sum_ss - sum_s * sum_s;
  if (columns.size() < 3 || !(spread > 0)) return std::nullopt;
  const double slope = (n * sum_sq - sum_s * sum_q) / spread;
  const double intercept = (sum_q - slope * sum_s) / n;
  // A surface that does not fall towards the front (beyond rounding of h² over the columns' span):
  // no arrest shape to read.
  const double span = 2.0 * std::sqrt(spread) / n;  // twice the columns' standard deviation in s
  if (!(-slope * span > 1e-9 * sum_q / n)) return std::nullopt;
  ThinFilmFit fit{-0.5 * slope * density * gravity, -intercept / slope, columns.size(), 0.0};
  double squares = 0;
  for (const auto& [s, h] : columns) {
    const double error = h - std::sqrt(std::max(0.0, -slope * (fit.length - s)));
    squares += error * error;
  }
  fit.rms_height_error = std::sqrt(squares / n);
  return fit;
}

}  // namespace rheosim::ldd
