#pragma once
// The experiments a dam break's front is compared with (run_free_surface.cpp writes them beside
// the run and into its RunSummary; the LDD report draws them):
//   - LDD §4.3's release (2 m × 0.1 m of a Bingham material, ρ 1200, μ_B 25, τ_B 25): LDD Table 1
//     (its experiment and the seed's LDD columns for the same Δ and δt), table1.csv and
//     table1.txt, summary "table1";
//   - a Newtonian liquid in a reservoir twice as high as long: the water column of Martin &
//     Moyce (1952, Phil. Trans. R. Soc. A 244, 312, Fig. 3, n² = 2), front Z = x/a (x from the
//     back wall, a the column's width) against T = t√(2g/a), martin_moyce.csv, summary
//     "martin_moyce";
//   - anything else: no experiment (the log says so);
//   - and for any law with a yield stress, the shallow arrest of ThinFilmArrest (run.hpp),
//     summary "thin_film_arrest".
#include <algorithm>
#include <filesystem>
#include <limits>
#include <optional>
#include <vector>

#include "rheosim/core/log.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/run.hpp"
#include "rheosim/ldd/summary.hpp"

namespace rheosim::ldd::detail {

// Martin & Moyce (1952), Fig. 3, n² = 2 (a = 2.25 in): T = t√(2g/a) and Z = x/a.
struct WaterColumnReference {
  static constexpr double height_over_width = 2.0;
  static constexpr double times[5] = {0.832, 1.219, 1.997, 2.547, 3.345};
  static constexpr double fronts[5] = {1.217, 1.474, 2.292, 2.995, 4.134};
};

// v(at) by linear interpolation in the increasing t; NaN beyond the last sample (the run did
// not get there).
[[nodiscard]] inline double interpolate(const std::vector<double>& t, const std::vector<double>& v, double at) {
  if (t.empty()) return std::numeric_limits<double>::quiet_NaN();
  if (at <= t.front()) return v.front();
  if (at > t.back() + 1e-9) return std::numeric_limits<double>::quiet_NaN();  // the run did not get there
  if (at >= t.back()) return v.back();
  const auto upper = std::lower_bound(t.begin(), t.end(), at);
  const auto k = static_cast<std::size_t>(upper - t.begin());
  const double w = (at - t[k - 1]) / (t[k] - t[k - 1]);
  return (1 - w) * v[k - 1] + w * v[k];
}

// Whether gravity points down the y axis: the references (shallow arrest, LDD Table 1, Martin &
// Moyce) are for a horizontal floor; a tilted gravity (a layer on an incline) has none.
[[nodiscard]] bool floor_is_horizontal(const CaseSettings& l);
// The shallow arrest of a dam break's reservoir (ThinFilmArrest, run.hpp); none for a law
// without a yield stress or a tilted gravity.
[[nodiscard]] std::optional<ThinFilmArrest> dam_break_thin_film_arrest(const CaseSettings& l);

// A dam break's free surface at the end of the run: the top of each Δ-wide column, at the
// columns' centres (x from the gate), ascending in x.
struct FinalProfile {
  std::vector<double> x, height;  // [m]
};

// The front over the run against the dam break's experiment, and for a yield-stress law the
// final front and final surface against the shallow arrest (summary "thin_film_arrest", with
// the fit of the final surface).
void compare_dam_break_front(const CaseSettings& l, const std::vector<double>& front_time,
                             const std::vector<double>& front, const FinalProfile& final_surface,
                             const std::filesystem::path& out_dir, RunSummary& summary, const core::Log& log);

}  // namespace rheosim::ldd::detail
