// A column's first sloshing mode against linear theory (column_references.hpp, run.hpp).
#include "column_references.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <variant>
#include <vector>

#include "rheosim/ldd/run.hpp"
#include "rheosim/ldd/scenes.hpp"

namespace rheosim::ldd {

LinearSloshing linear_sloshing(double width, double depth, double amplitude, double density, double gravity) {
  if (!(width > 0 && depth > 0 && density > 0 && gravity > 0 && amplitude >= 0))
    throw std::invalid_argument("linear_sloshing: width, depth, density and gravity must be > 0, amplitude >= 0");
  const double k = std::numbers::pi / width;
  return {2 * std::numbers::pi / std::sqrt(gravity * k * std::tanh(k * depth)),
          density * gravity * amplitude * amplitude * width / 4};
}

std::vector<double> level_crossings(std::span<const double> t, std::span<const double> h, double level,
                                    std::size_t until) {
  std::vector<double> crossings;
  const std::size_t end = std::min({until, t.size(), h.size()});
  std::size_t last = end;  // the last sample off the level
  for (std::size_t i = 0; i < end; ++i) {
    if (h[i] == level) continue;  // a sample on the level: the crossing is counted where the sign changes
    if (last < end && (h[last] - level) * (h[i] - level) < 0)
      crossings.push_back(t[last] + (t[i] - t[last]) * (level - h[last]) / (h[i] - h[last]));
    last = i;
  }
  return crossings;
}

}  // namespace rheosim::ldd

namespace rheosim::ldd::detail {

void compare_with_linear_sloshing(const CaseSettings& l, const core::CsvTable& history,
                                  const std::filesystem::path& out_dir, RunSummary& summary, const core::Log& log) {
  const auto& scene = std::get<ColumnScene>(l.scene);
  const auto [width, depth] = column_extent(scene, l.spacing);
  const LinearSloshing theory =
      linear_sloshing(width, depth, scene.wave_amplitude, l.fluid.density, l.gravity_magnitude());
  const std::vector<double> t = history.column("time"), h = history.column("left_wall_height"),
                            kinetic = history.column("kinetic_energy");
  const auto past =
      std::find_if(kinetic.begin(), kinetic.end(), [&](double e) { return e > 1.5 * theory.wave_energy; });
  const auto until = static_cast<std::size_t>(past - kinetic.begin());
  const std::vector<double> crossings = level_crossings(t, h, depth, until);

  SloshingComparison c;
  c.period = theory.period;
  c.wave_energy = theory.wave_energy;
  c.compared_until = until > 0 ? t[until - 1] : 0.0;
  c.crossings = crossings.size();
  if (!crossings.empty()) c.first_crossing = crossings.front();
  if (crossings.size() >= 3) {
    c.measured_period = 2 * (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
    c.relative_error = *c.measured_period / theory.period - 1;
  }
  summary.sloshing = c;

  core::CsvTable table({{"time", "s"}, {"left_wall_height", "m"}, {"linear_theory", "m"}});
  const double omega = 2 * std::numbers::pi / theory.period;
  for (std::size_t i = 0; i < t.size(); ++i)
    table.add_row({t[i], h[i], depth + scene.wave_amplitude * std::cos(omega * t[i])});
  core::write_csv(out_dir / "sloshing.csv", table);
  if (c.measured_period)
    log.info(
        "first sloshing mode: period {:.4g} s from {} zero crossings up to t = {:.3g} s, linear theory {:.4g} s "
        "({:+.2f} %)",
        *c.measured_period, c.crossings, c.compared_until, c.period, 1e2 * *c.relative_error);
  else
    log.info("first sloshing mode: {} zero crossings up to t = {:.3g} s, too few for a period (linear theory {:.4g} s)",
             c.crossings, c.compared_until, c.period);
}

}  // namespace rheosim::ldd::detail
