#include "rheosim/rheometer/run.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "rheosim/core/error.hpp"
#include "rheosim/core/output.hpp"
#include "rheosim/core/progress.hpp"
#include "rheosim/core/run_summary.hpp"
#include "rheosim/fluid/swirl.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/report.hpp"
#include "rheosim/rheometer/run_analysis.hpp"
#include "rheosim/rheometer/sweep.hpp"
#include "swirl_params.hpp"

namespace rheosim::rheometer {

namespace {

core::Hdf5Dataset dataset(const std::string& path, std::vector<std::size_t> shape, const std::vector<double>& data,
                          const std::string& unit) {
  core::Hdf5Dataset d;
  d.path = path;
  d.shape = std::move(shape);
  d.data = data;
  d.unit = unit;
  return d;
}

}  // namespace

RunOutcome run_single_phase(const Case& c, const std::filesystem::path& out_dir, const core::Log& log) {
  const auto& r = std::get<RheometerCase>(c.spec);
  const auto start = std::chrono::steady_clock::now();
  std::filesystem::create_directories(out_dir);
  core::write_atomically(out_dir / "case.yaml", [&](std::ostream& os) { os << c.text; });
  const ParallelPlate plate = ParallelPlate::from(r.geometry);

  nlohmann::ordered_json points = nlohmann::ordered_json::array();
  core::CsvTable table({{"shear_rate", "1/s"},
                        {"torque", "N m"},
                        {"torque_creeping", "N m"},
                        {"torque_quadrature", "N m"},
                        {"torque_analytic", "N m"},
                        {"rel_error", ""},
                        {"gap_reynolds_number", ""},
                        {"iterations", ""},
                        {"wall_time", "s"}},
                       core::CsvTable::Column{"fluid", ""});
  core::Hdf5Content fields;
  RunOutcome outcome;
  std::map<std::string, int> warning_counts;
  core::Progress progress = core::Progress::for_stderr("rheometer", r.fluids.size() * r.shear_rates.size());
  int done = 0;

  // Each point is the sweep's φ = 0 point (make_swirl_point_runner): the same solves, so a point
  // gives the same numbers in `kind: rheometer` and in `kind: sweep`.
  const PointRunner run_point = make_swirl_point_runner(r);
  for (const auto& named : r.fluids) {
    const auto& fluid = named.properties;
    for (double rate : r.shear_rates) {
      SweepPoint point;
      point.fluid = named.name;
      point.rim_shear_rate = rate;
      const PointResult res = run_point(point, {});
      const double omega = plate.angular_velocity(rate);
      const double quadrature = creeping_torque(plate, *fluid.rheology, rate);
      const double reynolds = plate.gap_reynolds_number(fluid.density, rate, fluid.rheology->viscosity(rate));
      const bool analytic = std::isfinite(res.torque_analytic);
      const double rel_error = analytic ? (res.torque - res.torque_analytic) / res.torque_analytic : std::nan("");

      nlohmann::ordered_json p;
      p["fluid"] = named.name;
      p["shear_rate"] = rate;
      p["angular_velocity"] = omega;
      p["torque"] = res.torque;
      p["torque_fluid"] = res.torque_fluid;
      if (std::isfinite(res.torque_grid)) {
        p["torque_grid"] = res.torque_grid;            // this grid's own torque
        p["torque_half_grid"] = res.torque_half_grid;  // half the cells in r and z
      }
      p["torque_contact"] = 0.0;
      p["torque_creeping"] = res.torque_creeping;
      p["torque_quadrature"] = quadrature;
      if (analytic) {
        p["torque_analytic"] = res.torque_analytic;
        p["rel_error"] = rel_error;
        p["creeping_rel_error"] = (res.torque_creeping - res.torque_analytic) / res.torque_analytic;
      }
      p["inertia_effect"] = res.torque / res.torque_creeping - 1.0;
      p["gap_reynolds_number"] = reynolds;
      p["iterations"] = res.iterations;
      p["converged"] = res.converged;
      if (!res.converged) p["failure"] = res.failure;
      if (!res.warnings.empty()) {
        p["warnings"] = res.warnings;
        for (const auto& w : res.warnings) log.warn("{} at {} 1/s: {}", named.name, rate, w);
        for (const auto& w : res.warnings) ++warning_counts[w];
      }
      p["wall_time"] = res.wall_time;
      points.push_back(p);

      table.add_row({rate, res.torque, res.torque_creeping, quadrature, res.torque_analytic, rel_error, reynolds,
                     static_cast<double>(res.iterations), res.wall_time},
                    named.name);

      // Fields of this point (the last iterate if it failed, so nothing computed is lost).
      const std::string group = fmt::format("/{}/shear_rate_{:g}", named.name, rate);
      fields.groups.push_back(
          {group, {{"shear_rate", rate}, {"torque", res.torque}, {"converged", res.converged ? 1.0 : 0.0}}});
      for (core::Hdf5Dataset d : res.fields) {
        // "fields/shear_rate" → "<group>/shear_rate_field": the group's attribute is the rim rate
        std::string name = d.path.substr(d.path.find('/') + 1);
        if (name == "shear_rate") name = "shear_rate_field";
        d.path = group + "/" + name;
        fields.datasets.push_back(std::move(d));
      }

      ++outcome.points;
      if (!res.converged) {
        ++outcome.failed_points;
        log.error("{} at {} 1/s did not converge: {}; its last iterate is saved in fields.h5", named.name, rate,
                  res.failure);
      } else {
        log.debug("{} at {} 1/s: torque {:.6e} N m, {} iterations", named.name, rate, res.torque, res.iterations);
      }
      progress.update(++done, fmt::format("{} at {} 1/s", named.name, rate));
    }
  }
  progress.finish();

  const auto& g = r.geometry;
  std::vector<double> radial_centres, axial_centres;
  {
    const fluid::CylindricalGrid grid({g.radius, g.gap, r.solver.radial_cells, 1, r.solver.axial_cells,
                                       r.solver.radial_grading, r.solver.axial_stretching});
    radial_centres.assign(grid.radial_centres().begin(), grid.radial_centres().end());
    axial_centres.assign(grid.axial_centres().begin(), grid.axial_centres().end());
  }
  fields.datasets.push_back(dataset("/grid/radial_centres", {radial_centres.size()}, radial_centres, "m"));
  fields.datasets.push_back(dataset("/grid/axial_centres", {axial_centres.size()}, axial_centres, "m"));
  fields.attributes = {{"case", c.name}, {"input_sha256", c.sha256}};
  core::write_hdf5(out_dir / "fields.h5", fields);
  core::write_csv(out_dir / "torque.csv", table);

  nlohmann::ordered_json summary = core::summary_head(c, "rheometer");
  add_plates_and_grid(summary, r);
  summary["points_failed"] = outcome.failed_points;
  summary["wall_time"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary["points"] = points;
  {  // every rule a point bent, with how many points bent it (as a sweep's summary)
    nlohmann::ordered_json warnings = nlohmann::ordered_json::array();
    for (const auto& [text, count] : warning_counts) warnings.push_back({{"warning", text}, {"points", count}});
    summary["warnings"] = warnings;
  }
  // The same analysis and report as a sweep, with one flow curve per fluid (φ = 0).
  add_flow_analysis(summary, {plate, r.fluids, r.particles});
  core::write_json(out_dir / "summary.json", summary);

  const ReportFiles report = write_report(out_dir);
  if (!report.missing_plots.empty())
    log.warn("gnuplot failed or is missing: {} plot(s) not drawn; the .gp scripts are kept in {} to plot by hand",
             report.missing_plots.size(), out_dir.string());
  outcome.summary = out_dir / "summary.json";
  return outcome;
}

}  // namespace rheosim::rheometer
