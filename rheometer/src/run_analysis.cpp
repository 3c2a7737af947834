// The analysis of a run's points into summary.json (rheometer/run_analysis.hpp).
#include "rheosim/rheometer/run_analysis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <utility>

#include "rheosim/rheometer/analysis.hpp"

namespace rheosim::rheometer {

namespace {

using core::finite_or_empty;

Interval95 interval(const Interval& i) { return {finite_or_empty(i.lower), finite_or_empty(i.upper)}; }

// A label without the characters that would need quoting in gnuplot filters or CSV cells.
std::string clean_label(std::string s) {
  for (char& ch : s)
    if (ch == ',' || ch == '\'' || ch == '"') ch = ' ';
  return s;
}

struct Series {
  std::string fluid;
  double volume_fraction = 0;
  std::string label;
  std::vector<std::size_t> point_indices;  // converged, positive torque, by rate
};

const NamedFluid& find_fluid(const RunAnalysisInputs& in, const std::string& name) {
  for (const auto& f : in.fluids)
    if (f.name == name) return f;
  return in.fluids.front();
}

FitRecord fit_record(const FitResult& f, const Series& s) {
  FitRecord r;
  r.label = s.label;
  r.fluid = s.fluid;
  r.volume_fraction = s.volume_fraction;
  r.model = f.model_name;
  r.equation = std::string(f.model->equation());
  r.converged = f.converged;
  r.iterations = f.iterations;
  r.stop_reason = f.stop_reason;
  r.points = f.points;
  r.degrees_of_freedom = f.degrees_of_freedom;
  r.residual_std = finite_or_empty(f.residual_std);
  r.sum_of_squares = finite_or_empty(f.sum_of_squares);
  r.aic = finite_or_empty(f.aic);
  r.aicc = finite_or_empty(f.aicc);
  r.min_shear_rate = f.min_shear_rate;
  r.max_shear_rate = f.max_shear_rate;
  const auto info = f.model->parameters();
  for (std::size_t k = 0; k < f.params.size(); ++k)
    r.parameters.push_back({f.parameter_names[k], std::string(info[k].symbol), f.units[k], finite_or_empty(f.params[k]),
                            finite_or_empty(f.std_errors[k]), interval(f.ci95[k])});
  for (Eigen::Index row = 0; row < f.correlation.rows(); ++row) {
    std::vector<MaybeNumber> values;
    for (Eigen::Index c = 0; c < f.correlation.cols(); ++c) values.push_back(finite_or_empty(f.correlation(row, c)));
    r.correlation.push_back(std::move(values));
  }
  r.shear_rate = f.shear_rate;
  for (double x : f.residuals) r.residuals.push_back(finite_or_empty(x));
  for (const auto& w : f.warnings) r.warnings.push_back({std::string(to_string(w.kind)), w.parameter, w.message});
  return r;
}

YieldRecord yield_record(const YieldStressEstimate& e, const Series& s) {
  return {s.label,
          s.fluid,
          s.volume_fraction,
          e.method,
          finite_or_empty(e.value),
          finite_or_empty(e.std_error),
          interval(e.ci95),
          e.is_significant,
          e.converged,
          e.warnings,
          std::nullopt};
}

CorrelationRecord correlation_record(const CorrelationComparison& c) {
  CorrelationRecord r;
  r.name = c.name;
  for (double x : c.predicted) r.predicted.push_back(finite_or_empty(x));
  r.sum_of_squares = finite_or_empty(c.sum_of_squares);
  r.max_packing = finite_or_empty(c.max_packing);
  r.max_packing_std_error = finite_or_empty(c.max_packing_std_error);
  r.max_packing_ci95 = interval(c.max_packing_ci95);
  r.intrinsic_viscosity = finite_or_empty(c.intrinsic_viscosity);
  r.degrees_of_freedom = c.degrees_of_freedom;
  r.aic = finite_or_empty(c.aic);
  r.converged = c.converged;
  r.warnings = c.warnings;
  return r;
}

// The points grouped into flow curves (fluid, φ), in order of first appearance; each keeps its
// converged points with a positive torque.
std::vector<Series> group_into_series(std::span<const SweepPointRecord> points,
                                      const std::vector<std::string>& fluid_names, bool has_suspension) {
  std::vector<Series> series;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    auto it = std::find_if(series.begin(), series.end(), [&](const Series& s) {
      return s.fluid == p.fluid && s.volume_fraction == p.volume_fraction;
    });
    if (it == series.end()) {
      std::string label = fluid_names.size() > 1 ? p.fluid : std::string();
      if (has_suspension) label += fmt::format("{}φ = {:g}", label.empty() ? "" : " ", p.volume_fraction);
      if (label.empty()) label = p.fluid;
      series.push_back({p.fluid, p.volume_fraction, clean_label(label), {}});
      it = std::prev(series.end());
    }
    if (p.converged && p.torque > 0 && std::isfinite(p.torque)) it->point_indices.push_back(i);
  }
  return series;
}

// The flow analysis so far, and each fluid's best fit per φ for η_r(φ).
struct SeriesAnalysis {
  FlowAnalysis records;
  std::map<std::string, std::vector<std::pair<double, FitResult>>> best_fits;
};

// The measured points of one flow curve, by rate.
struct FlowCurveData {
  std::vector<double> rates, torques, relative_errors;  // relative_errors: empty unless every point has one
};

// A point's torque standard error, NaN when it has none.
double torque_std_error(const SweepPointRecord& p) {
  return p.torque_std_error.value_or(std::numeric_limits<double>::quiet_NaN());
}

FlowCurveData flow_curve_data(const Series& s, std::span<const SweepPointRecord> points) {
  FlowCurveData d;
  bool all_errors = true;
  for (std::size_t i : s.point_indices) {
    d.rates.push_back(points[i].shear_rate);
    d.torques.push_back(points[i].torque);
    const double se = torque_std_error(points[i]);
    all_errors = all_errors && se > 0;
    d.relative_errors.push_back(se / d.torques.back());
  }
  if (!all_errors) d.relative_errors.clear();
  return d;
}

PointChecks checks_record(const PointValidity& v, bool has_particles) {
  PointChecks c;
  c.gap_reynolds = v.gap_reynolds;
  if (has_particles) {
    c.particle_reynolds = v.particle_reynolds;
    c.stokes = v.stokes;
  }
  c.gap_to_diameter = finite_or_empty(v.gap_to_diameter);
  c.gap_reynolds_ok = v.gap_reynolds_ok;
  c.particle_reynolds_ok = v.particle_reynolds_ok;
  c.stokes_ok = v.stokes_ok;
  c.gap_to_diameter_ok = v.gap_to_diameter_ok;
  c.valid = v.is_valid();
  c.messages = v.messages;
  return c;
}

// The rim stress of each point and its validity checks, written into the points; returns which
// points pass the checks.
std::vector<bool> add_rim_stress_and_validity(const Series& s, const FlowCurveData& d, const RimStressCurve& curve,
                                              std::span<SweepPointRecord> points, const RunAnalysisInputs& in) {
  const auto& fluid = find_fluid(in, s.fluid).properties;
  std::vector<bool> valid(d.rates.size(), true);
  const double particle_density = in.particles ? in.particles->density : 0.0;
  for (std::size_t k = 0; k < d.rates.size(); ++k) {
    auto& p = points[s.point_indices[k]];
    p.log_slope = finite_or_empty(curve.log_slope[k]);
    p.log_slope_std_error = finite_or_empty(curve.log_slope_std_error[k]);
    p.apparent_stress = curve.apparent_stress[k];
    p.rim_stress = finite_or_empty(curve.corrected_stress[k]);
    p.apparent_viscosity = finite_or_empty(curve.apparent_viscosity[k]);
    p.viscosity = finite_or_empty(curve.corrected_viscosity[k]);
    // Validity at this point: the sample's density is the mixture's, its viscosity the measured one.
    PointConditions cond;
    cond.rim_shear_rate = d.rates[k];
    cond.density = (1.0 - s.volume_fraction) * fluid.density + s.volume_fraction * particle_density;
    cond.viscosity = curve.corrected_viscosity[k] > 0 ? curve.corrected_viscosity[k] : curve.apparent_viscosity[k];
    cond.fluid_density = fluid.density;
    cond.fluid_viscosity = fluid.rheology->viscosity(d.rates[k]);
    if (s.volume_fraction > 0 && in.particles) {
      cond.particle_diameter = in.particles->diameter;
      cond.particle_density = in.particles->density;
    }
    if (cond.viscosity > 0) {
      const PointValidity v = check_validity(in.plate, cond);
      p.validity = checks_record(v, cond.particle_diameter > 0);
      valid[k] = v.is_valid();
    }
  }
  return valid;
}

// The points the fits use (each marked used_in_fits): only those that pass the validity checks,
// since a torque raised by secondary flow or particle inertia is not the material's flow curve
// (it reads as shear thickening or a yield stress); with fewer than 3 valid points every point,
// with a warning.
struct FitPoints {
  std::vector<double> rates, stress, torques;
};
FitPoints choose_fit_points(const Series& s, const FlowCurveData& d, const RimStressCurve& curve,
                            const std::vector<bool>& valid, std::span<SweepPointRecord> points,
                            std::vector<std::string>& warnings) {
  const auto valid_count = static_cast<std::size_t>(std::count(valid.begin(), valid.end(), true));
  const bool fit_valid_only = valid_count >= 3 && valid_count < d.rates.size();
  FitPoints f;
  for (std::size_t k = 0; k < d.rates.size(); ++k) {
    const bool used = !fit_valid_only || valid[k];
    points[s.point_indices[k]].used_in_fits = used;
    if (!used) continue;
    f.rates.push_back(d.rates[k]);
    f.stress.push_back(curve.corrected_stress[k]);
    f.torques.push_back(d.torques[k]);
  }
  if (fit_valid_only)
    warnings.push_back(
        fmt::format("{}: {} of {} points fail the validity checks (see the point table) and are left "
                    "out of the fits and yield-stress estimates",
                    s.label, d.rates.size() - valid_count, d.rates.size()));
  else if (valid_count < d.rates.size())
    warnings.push_back(
        fmt::format("{}: {} of {} points fail the validity checks; too few valid points remain, so all "
                    "are fitted: read the fits and yield stresses with that in mind",
                    s.label, d.rates.size() - valid_count, d.rates.size()));
  return f;
}

// Every flow model on (γ̇_R, τ_R), ranked by AICc, into out's fits; the best one into the series
// record and out.best_fits. Returns the fits and their ranking.
std::pair<std::vector<FitResult>, std::vector<ModelRanking>> fit_and_rank(const Series& s, const FitPoints& f,
                                                                          SeriesRecord& record, SeriesAnalysis& out) {
  std::vector<FitResult> fits;
  for (const auto& name : builtin_flow_models().names()) {
    try {
      fits.push_back(fit_flow_curve(name, f.rates, f.stress));
    } catch (const std::exception& e) {
      record.warnings.push_back(fmt::format("{}: the {} fit failed: {}", s.label, name, e.what()));
    }
  }
  auto ranking = rank_by_aic(fits);
  std::vector<FitRecord> fit_records;
  for (const auto& fit : fits) fit_records.push_back(fit_record(fit, s));
  for (std::size_t r = 0; r < ranking.size(); ++r) {
    auto& fr = fit_records[ranking[r].fit_index];
    fr.rank = r + 1;
    fr.delta = finite_or_empty(ranking[r].delta);
    fr.akaike_weight = finite_or_empty(ranking[r].weight);
  }
  for (auto& fr : fit_records) out.records.fits.push_back(std::move(fr));
  if (!ranking.empty()) {
    const FitResult& best = fits[ranking.front().fit_index];
    record.best_model = best.model_name;
    out.best_fits[s.fluid].emplace_back(s.volume_fraction, best);
  }
  return {std::move(fits), std::move(ranking)};
}

// Yield stress, four ways kept apart (analysis.hpp §3): three fits' intercepts with the Akaike
// weight of their model, and the seed's straight torque line (kept in the series record).
void add_yield_stresses(const Series& s, const FitPoints& f, const std::vector<FitResult>& fits,
                        const std::vector<ModelRanking>& ranking, const RunAnalysisInputs& in, SeriesRecord& record,
                        SeriesAnalysis& out) {
  for (const auto& [model, method] :
       {std::pair{"bingham", "bingham_intercept"}, std::pair{"casson", "casson_intercept"},
        std::pair{"herschel_bulkley", "herschel_bulkley"}}) {
    const auto it = std::find_if(fits.begin(), fits.end(), [&](const FitResult& x) { return x.model_name == model; });
    if (it == fits.end()) continue;
    auto yield = yield_record(yield_stress_from_fit(*it, method), s);
    // How much the data support the model the estimate comes from (an intercept of a model
    // with weight ~0 is a fitting artefact, not a material property).
    const auto index = static_cast<std::size_t>(it - fits.begin());
    for (const auto& r : ranking)
      if (r.fit_index == index) yield.akaike_weight = finite_or_empty(r.weight);
    out.records.yield_stress.push_back(std::move(yield));
  }
  const TorqueLineFit line = fit_torque_line(in.plate, f.rates, f.torques);
  out.records.yield_stress.push_back(yield_record(line.yield_stress, s));
  record.torque_line = TorqueLine{line.intercept,
                                  line.slope,
                                  finite_or_empty(line.intercept_std_error),
                                  finite_or_empty(line.slope_std_error),
                                  line.plastic_viscosity,
                                  interval(line.plastic_viscosity_ci95),
                                  line.residuals};
}

// One flow curve: the rim stress and validity of its points (written into them), the fits ranked
// by AICc, the yield stresses, into `out`.
void analyse_series(Series& s, std::span<SweepPointRecord> points, const RunAnalysisInputs& in, SeriesAnalysis& out) {
  std::sort(s.point_indices.begin(), s.point_indices.end(),
            [&](std::size_t a, std::size_t b) { return points[a].shear_rate < points[b].shear_rate; });
  SeriesRecord record;
  record.label = s.label;
  record.fluid = s.fluid;
  record.volume_fraction = s.volume_fraction;
  record.points = s.point_indices.size();
  const FlowCurveData d = flow_curve_data(s, points);
  if (d.rates.size() < 2) {
    record.warnings.push_back(fmt::format("{}: {} finished point(s): the plate correction and the fits need at least 2",
                                          s.label, d.rates.size()));
    out.records.series.push_back(std::move(record));
    return;
  }
  const RimStressCurve curve = rim_stress_curve(in.plate, d.rates, d.torques, d.relative_errors);
  const std::vector<bool> valid = add_rim_stress_and_validity(s, d, curve, points, in);
  const FitPoints f = choose_fit_points(s, d, curve, valid, points, record.warnings);
  record.fitted_points = f.rates.size();
  const auto [fits, ranking] = fit_and_rank(s, f, record, out);
  add_yield_stresses(s, f, fits, ranking, in, record, out);
  out.records.series.push_back(std::move(record));
}

// η_r(φ) of one fluid at the largest shear rate every φ of that fluid reached, against the
// correlations.
RelativeViscosityRecord relative_viscosity_of(const std::string& name, const SeriesAnalysis& analysis,
                                              const std::vector<Series>& series,
                                              std::span<const SweepPointRecord> points, const RunAnalysisInputs& in) {
  RelativeViscosityRecord out;
  out.fluid = name;
  const auto found = analysis.best_fits.find(name);
  if (found == analysis.best_fits.end()) {
    out.warnings.push_back(name + ": no flow curve could be fitted, so there is no relative viscosity");
    return out;
  }
  const auto& by_phi = found->second;
  double reference_rate = std::numeric_limits<double>::infinity();
  for (const auto& [phi, fit] : by_phi) reference_rate = std::min(reference_rate, fit.max_shear_rate);
  out.reference_shear_rate = reference_rate;

  // The liquid's viscosity: its measured flow curve (φ = 0) when there is one, so plate and
  // inertia effects cancel in the ratio; else its rheology law.
  const auto liquid_fit = std::find_if(by_phi.begin(), by_phi.end(), [](const auto& e) { return e.first == 0.0; });
  FlowPrediction liquid;
  if (liquid_fit != by_phi.end()) {
    liquid = predict(liquid_fit->second, reference_rate);
    out.liquid_viscosity_source = "measured flow curve at φ = 0 (" + liquid_fit->second.model_name + " fit)";
  } else {
    liquid.shear_rate = reference_rate;
    liquid.viscosity = find_fluid(in, name).properties.rheology->viscosity(reference_rate);
    liquid.viscosity_std_error = 0;
    out.liquid_viscosity_source = "the liquid's rheology law (no φ = 0 points)";
  }
  out.liquid_viscosity = finite_or_empty(liquid.viscosity);
  out.liquid_viscosity_std_error = finite_or_empty(liquid.viscosity_std_error);

  std::vector<RelativeViscosityPoint> rv;
  for (const auto& [phi, fit] : by_phi) {
    FlowPrediction suspension = predict(fit, reference_rate);
    // The fit sees only the scatter between the points; an error they share (one suspension
    // box serving every rate of a φ, so its statistical error moves every torque together)
    // it cannot see. The smallest relative torque error of the φ's points bounds it from below.
    double shared = std::numeric_limits<double>::infinity();
    for (const auto& s : series)
      if (s.fluid == name && s.volume_fraction == phi)
        for (const std::size_t i : s.point_indices)
          shared = std::min(shared, torque_std_error(points[i]) / points[i].torque);
    const bool floored = std::isfinite(shared) && shared * suspension.viscosity > suspension.viscosity_std_error;
    if (floored) suspension.viscosity_std_error = shared * suspension.viscosity;
    RelativeViscosityPoint p = relative_viscosity(phi, suspension, liquid);
    if (phi == 0.0 && liquid_fit != by_phi.end()) p = {0.0, 1.0, 0.0};  // the liquid against itself
    rv.push_back(p);
    out.points.push_back({phi, finite_or_empty(p.relative_viscosity), finite_or_empty(p.std_error),
                          finite_or_empty(suspension.viscosity), finite_or_empty(suspension.viscosity_std_error),
                          floored ? "the points' shared statistical error" : "the flow-curve fit", fit.model_name});
  }
  try {
    const RelativeViscosityAnalysis a = analyze_relative_viscosity(rv);
    for (const auto* c : {&a.einstein, &a.batchelor, &a.krieger_dougherty, &a.maron_pierce})
      out.correlations.push_back(correlation_record(*c));
  } catch (const std::exception& e) {
    out.warnings.push_back(fmt::format("{}: correlations not compared: {}", name, e.what()));
  }
  if (std::none_of(rv.begin(), rv.end(), [](const auto& p) { return p.volume_fraction > 0; }))
    out.warnings.push_back(name + ": no finished point with φ > 0: η_r(φ) is the liquid alone and φ_m is not fitted");
  return out;
}

}  // namespace

FlowAnalysis analyse_flow_curves(std::span<SweepPointRecord> points, const RunAnalysisInputs& in) {
  if (in.fluids.empty()) throw std::invalid_argument("analyse_flow_curves: no fluids");
  // Flow curves carry φ in their label when the run has suspension points.
  const bool has_suspension =
      std::any_of(points.begin(), points.end(), [](const SweepPointRecord& p) { return p.volume_fraction > 0; });
  std::vector<std::string> fluid_names;
  for (const auto& p : points)
    if (std::find(fluid_names.begin(), fluid_names.end(), p.fluid) == fluid_names.end()) fluid_names.push_back(p.fluid);

  std::vector<Series> series = group_into_series(points, fluid_names, has_suspension);
  SeriesAnalysis analysis;
  for (auto& s : series) analyse_series(s, points, in, analysis);
  // η_r(φ) per fluid at the largest shear rate every φ of that fluid reached.
  for (const auto& name : fluid_names)
    analysis.records.relative_viscosity.push_back(relative_viscosity_of(name, analysis, series, points, in));
  return std::move(analysis.records);
}

}  // namespace rheosim::rheometer
