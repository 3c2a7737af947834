// The analysis of a run's points into summary.json (rheometer/run_analysis.hpp).
#include "rheosim/rheometer/run_analysis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>

#include "rheosim/rheometer/analysis.hpp"

namespace rheosim::rheometer {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

double number(const nlohmann::ordered_json& j, const char* key) {
  if (!j.contains(key) || !j.at(key).is_number()) return nan;
  return j.at(key).get<double>();
}

// NaN and infinities are written as null by core::write_json; keep them explicit here too.
nlohmann::ordered_json finite_or_null(double x) {
  return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json interval(const Interval& i) { return {finite_or_null(i.lower), finite_or_null(i.upper)}; }

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

nlohmann::ordered_json fit_json(const FitResult& f, const Series& s) {
  nlohmann::ordered_json j;
  j["label"] = s.label;
  j["fluid"] = s.fluid;
  j["volume_fraction"] = s.volume_fraction;
  j["model"] = f.model_name;
  j["equation"] = std::string(f.model->equation());
  j["converged"] = f.converged;
  j["iterations"] = f.iterations;
  j["stop_reason"] = f.stop_reason;
  j["points"] = f.points;
  j["degrees_of_freedom"] = f.degrees_of_freedom;
  j["residual_std"] = finite_or_null(f.residual_std);
  j["sum_of_squares"] = finite_or_null(f.sum_of_squares);
  j["aic"] = finite_or_null(f.aic);
  j["aicc"] = finite_or_null(f.aicc);
  j["min_shear_rate"] = f.min_shear_rate;
  j["max_shear_rate"] = f.max_shear_rate;
  auto params = nlohmann::ordered_json::array();
  const auto info = f.model->parameters();
  for (std::size_t k = 0; k < f.params.size(); ++k) {
    nlohmann::ordered_json p;
    p["name"] = f.parameter_names[k];
    p["symbol"] = std::string(info[k].symbol);
    p["unit"] = f.units[k];
    p["value"] = finite_or_null(f.params[k]);
    p["std_error"] = finite_or_null(f.std_errors[k]);
    p["ci95"] = interval(f.ci95[k]);
    params.push_back(p);
  }
  j["parameters"] = params;
  auto corr = nlohmann::ordered_json::array();
  for (Eigen::Index r = 0; r < f.correlation.rows(); ++r) {
    auto row = nlohmann::ordered_json::array();
    for (Eigen::Index c = 0; c < f.correlation.cols(); ++c) row.push_back(finite_or_null(f.correlation(r, c)));
    corr.push_back(row);
  }
  j["correlation"] = corr;
  j["shear_rate"] = f.shear_rate;
  j["residuals"] = nlohmann::ordered_json::array();
  for (double r : f.residuals) j["residuals"].push_back(finite_or_null(r));
  auto warnings = nlohmann::ordered_json::array();
  for (const auto& w : f.warnings)
    warnings.push_back({{"kind", std::string(to_string(w.kind))}, {"parameter", w.parameter}, {"message", w.message}});
  j["warnings"] = warnings;
  return j;
}

nlohmann::ordered_json yield_json(const YieldStressEstimate& e, const Series& s) {
  nlohmann::ordered_json j;
  j["label"] = s.label;
  j["fluid"] = s.fluid;
  j["volume_fraction"] = s.volume_fraction;
  j["method"] = e.method;
  j["value"] = finite_or_null(e.value);
  j["std_error"] = finite_or_null(e.std_error);
  j["ci95"] = interval(e.ci95);
  j["significant"] = e.is_significant;
  j["converged"] = e.converged;
  j["warnings"] = e.warnings;
  return j;
}

nlohmann::ordered_json correlation_json(const CorrelationComparison& c) {
  nlohmann::ordered_json j;
  j["name"] = c.name;
  j["predicted"] = nlohmann::ordered_json::array();
  for (double p : c.predicted) j["predicted"].push_back(finite_or_null(p));
  j["sum_of_squares"] = finite_or_null(c.sum_of_squares);
  j["max_packing"] = finite_or_null(c.max_packing);
  j["max_packing_std_error"] = finite_or_null(c.max_packing_std_error);
  j["max_packing_ci95"] = interval(c.max_packing_ci95);
  j["intrinsic_viscosity"] = finite_or_null(c.intrinsic_viscosity);
  j["degrees_of_freedom"] = c.degrees_of_freedom;
  j["aic"] = finite_or_null(c.aic);
  j["converged"] = c.converged;
  j["warnings"] = c.warnings;
  return j;
}

// The points grouped into flow curves (fluid, φ), in order of first appearance; each keeps its
// converged points with a positive torque.
std::vector<Series> group_into_series(const nlohmann::ordered_json& points, const RunAnalysisInputs& in,
                                      const std::vector<std::string>& fluid_names, bool has_suspension) {
  std::vector<Series> series;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    const std::string fluid = p.value("fluid", in.fluids.front().name);
    const double phi = p.contains("volume_fraction") ? p["volume_fraction"].get<double>() : 0.0;
    auto it = std::find_if(series.begin(), series.end(),
                           [&](const Series& s) { return s.fluid == fluid && s.volume_fraction == phi; });
    if (it == series.end()) {
      std::string label = fluid_names.size() > 1 ? fluid : std::string();
      if (has_suspension) label += fmt::format("{}φ = {:g}", label.empty() ? "" : " ", phi);
      if (label.empty()) label = fluid;
      series.push_back({fluid, phi, clean_label(label), {}});
      it = std::prev(series.end());
    }
    const double torque = number(p, "torque");
    if (p.value("converged", false) && torque > 0 && std::isfinite(torque)) it->point_indices.push_back(i);
  }

  return series;
}

// What the flow curves add to summary.json, and each fluid's best fit per φ for η_r(φ).
struct SeriesAnalysis {
  nlohmann::ordered_json series = nlohmann::ordered_json::array();
  nlohmann::ordered_json fits = nlohmann::ordered_json::array();
  nlohmann::ordered_json yields = nlohmann::ordered_json::array();
  std::map<std::string, std::vector<std::pair<double, FitResult>>> best_fits;
};

// The measured points of one flow curve, by rate.
struct FlowCurveData {
  std::vector<double> rates, torques, relative_errors;  // relative_errors: empty unless every point has one
};

FlowCurveData flow_curve_data(const Series& s, const nlohmann::ordered_json& points) {
  FlowCurveData d;
  bool all_errors = true;
  for (std::size_t i : s.point_indices) {
    d.rates.push_back(number(points[i], "shear_rate"));
    d.torques.push_back(number(points[i], "torque"));
    const double se = number(points[i], "torque_std_error");
    all_errors = all_errors && se > 0;
    d.relative_errors.push_back(se / d.torques.back());
  }
  if (!all_errors) d.relative_errors.clear();
  return d;
}

// The rim stress of each point and its validity checks, written into the points; returns which
// points pass the checks.
std::vector<bool> add_rim_stress_and_validity(const Series& s, const FlowCurveData& d, const RimStressCurve& curve,
                                              nlohmann::ordered_json& points, const RunAnalysisInputs& in) {
  const auto& fluid = find_fluid(in, s.fluid).properties;
  std::vector<bool> valid(d.rates.size(), true);
  const double particle_density = in.particles ? in.particles->density : 0.0;
  for (std::size_t k = 0; k < d.rates.size(); ++k) {
    auto& p = points[s.point_indices[k]];
    p["log_slope"] = finite_or_null(curve.log_slope[k]);
    p["log_slope_std_error"] = finite_or_null(curve.log_slope_std_error[k]);
    p["apparent_stress"] = curve.apparent_stress[k];
    p["rim_stress"] = curve.corrected_stress[k];
    p["apparent_viscosity"] = curve.apparent_viscosity[k];
    p["viscosity"] = curve.corrected_viscosity[k];
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
      nlohmann::ordered_json vj;
      vj["gap_reynolds"] = v.gap_reynolds;
      vj["particle_reynolds"] = cond.particle_diameter > 0 ? nlohmann::ordered_json(v.particle_reynolds) : nullptr;
      vj["stokes"] = cond.particle_diameter > 0 ? nlohmann::ordered_json(v.stokes) : nullptr;
      vj["gap_to_diameter"] = finite_or_null(v.gap_to_diameter);
      vj["gap_reynolds_ok"] = v.gap_reynolds_ok;
      vj["particle_reynolds_ok"] = v.particle_reynolds_ok;
      vj["stokes_ok"] = v.stokes_ok;
      vj["gap_to_diameter_ok"] = v.gap_to_diameter_ok;
      vj["valid"] = v.is_valid();
      vj["messages"] = v.messages;
      p["validity"] = vj;
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
                            const std::vector<bool>& valid, nlohmann::ordered_json& points,
                            nlohmann::ordered_json& warnings) {
  const auto valid_count = static_cast<std::size_t>(std::count(valid.begin(), valid.end(), true));
  const bool fit_valid_only = valid_count >= 3 && valid_count < d.rates.size();
  FitPoints f;
  for (std::size_t k = 0; k < d.rates.size(); ++k) {
    const bool used = !fit_valid_only || valid[k];
    points[s.point_indices[k]]["used_in_fits"] = used;
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

// Every flow model on (γ̇_R, τ_R), ranked by AICc, into out.fits; the best one into sj and
// out.best_fits. Returns the fits and their ranking.
std::pair<std::vector<FitResult>, std::vector<ModelRanking>> fit_and_rank(const Series& s, const FitPoints& f,
                                                                          nlohmann::ordered_json& sj,
                                                                          nlohmann::ordered_json& warnings,
                                                                          SeriesAnalysis& out) {
  std::vector<FitResult> fits;
  for (const auto& name : builtin_flow_models().names()) {
    try {
      fits.push_back(fit_flow_curve(name, f.rates, f.stress));
    } catch (const std::exception& e) {
      warnings.push_back(fmt::format("{}: the {} fit failed: {}", s.label, name, e.what()));
    }
  }
  auto ranking = rank_by_aic(fits);
  std::vector<nlohmann::ordered_json> fit_entries;
  for (const auto& fit : fits) fit_entries.push_back(fit_json(fit, s));
  for (std::size_t r = 0; r < ranking.size(); ++r) {
    auto& fj = fit_entries[ranking[r].fit_index];
    fj["rank"] = r + 1;
    fj["delta"] = finite_or_null(ranking[r].delta);
    fj["akaike_weight"] = finite_or_null(ranking[r].weight);
  }
  for (auto& fj : fit_entries) out.fits.push_back(fj);
  if (!ranking.empty()) {
    const FitResult& best = fits[ranking.front().fit_index];
    sj["best_model"] = best.model_name;
    out.best_fits[s.fluid].emplace_back(s.volume_fraction, best);
  }
  return {std::move(fits), std::move(ranking)};
}

// Yield stress, four ways kept apart (analysis.hpp §3): three fits' intercepts with the Akaike
// weight of their model, and the seed's straight torque line (kept in sj).
void add_yield_stresses(const Series& s, const FitPoints& f, const std::vector<FitResult>& fits,
                        const std::vector<ModelRanking>& ranking, const RunAnalysisInputs& in,
                        nlohmann::ordered_json& sj, SeriesAnalysis& out) {
  for (const auto& [model, method] :
       {std::pair{"bingham", "bingham_intercept"}, std::pair{"casson", "casson_intercept"},
        std::pair{"herschel_bulkley", "herschel_bulkley"}}) {
    const auto it = std::find_if(fits.begin(), fits.end(), [&](const FitResult& x) { return x.model_name == model; });
    if (it == fits.end()) continue;
    auto yj = yield_json(yield_stress_from_fit(*it, method), s);
    // How much the data support the model the estimate comes from (an intercept of a model
    // with weight ~0 is a fitting artefact, not a material property).
    const auto index = static_cast<std::size_t>(it - fits.begin());
    for (const auto& r : ranking)
      if (r.fit_index == index) yj["akaike_weight"] = finite_or_null(r.weight);
    out.yields.push_back(yj);
  }
  const TorqueLineFit line = fit_torque_line(in.plate, f.rates, f.torques);
  out.yields.push_back(yield_json(line.yield_stress, s));
  sj["torque_line"] = {{"intercept", line.intercept},
                       {"intercept_std_error", finite_or_null(line.intercept_std_error)},
                       {"slope", line.slope},
                       {"slope_std_error", finite_or_null(line.slope_std_error)},
                       {"plastic_viscosity", line.plastic_viscosity},
                       {"plastic_viscosity_ci95", interval(line.plastic_viscosity_ci95)},
                       {"residuals", line.residuals}};
}

// One flow curve: the rim stress and validity of its points (written into them), the fits ranked
// by AICc, the yield stresses, into `out`.
void analyse_series(Series& s, nlohmann::ordered_json& points, const RunAnalysisInputs& in, SeriesAnalysis& out) {
  std::sort(s.point_indices.begin(), s.point_indices.end(), [&](std::size_t a, std::size_t b) {
    return number(points[a], "shear_rate") < number(points[b], "shear_rate");
  });
  nlohmann::ordered_json sj;
  sj["label"] = s.label;
  sj["fluid"] = s.fluid;
  sj["volume_fraction"] = s.volume_fraction;
  sj["points"] = s.point_indices.size();
  auto warnings = nlohmann::ordered_json::array();
  const FlowCurveData d = flow_curve_data(s, points);
  if (d.rates.size() < 2) {
    warnings.push_back(fmt::format("{}: {} finished point(s): the plate correction and the fits need at least 2",
                                   s.label, d.rates.size()));
    sj["warnings"] = warnings;
    out.series.push_back(sj);
    return;
  }
  const RimStressCurve curve = rim_stress_curve(in.plate, d.rates, d.torques, d.relative_errors);
  const std::vector<bool> valid = add_rim_stress_and_validity(s, d, curve, points, in);
  const FitPoints f = choose_fit_points(s, d, curve, valid, points, warnings);
  sj["fitted_points"] = f.rates.size();
  const auto [fits, ranking] = fit_and_rank(s, f, sj, warnings, out);
  add_yield_stresses(s, f, fits, ranking, in, sj, out);
  sj["warnings"] = warnings;
  out.series.push_back(sj);
}

// η_r(φ) of one fluid at the largest shear rate every φ of that fluid reached, against the
// correlations.
nlohmann::ordered_json relative_viscosity_of(const std::string& name, const SeriesAnalysis& analysis,
                                             const std::vector<Series>& series, const nlohmann::ordered_json& points,
                                             const RunAnalysisInputs& in) {
  nlohmann::ordered_json rj;
  rj["fluid"] = name;
  auto warnings = nlohmann::ordered_json::array();
  const auto found = analysis.best_fits.find(name);
  if (found == analysis.best_fits.end()) {
    warnings.push_back(name + ": no flow curve could be fitted, so there is no relative viscosity");
    rj["warnings"] = warnings;
    return rj;
  }
  const auto& by_phi = found->second;
  double reference_rate = std::numeric_limits<double>::infinity();
  for (const auto& [phi, fit] : by_phi) reference_rate = std::min(reference_rate, fit.max_shear_rate);
  rj["reference_shear_rate"] = reference_rate;

  // The liquid's viscosity: its measured flow curve (φ = 0) when there is one, so plate and
  // inertia effects cancel in the ratio; else its rheology law.
  const auto liquid_fit = std::find_if(by_phi.begin(), by_phi.end(), [](const auto& e) { return e.first == 0.0; });
  FlowPrediction liquid;
  if (liquid_fit != by_phi.end()) {
    liquid = predict(liquid_fit->second, reference_rate);
    rj["liquid_viscosity_source"] = "measured flow curve at φ = 0 (" + liquid_fit->second.model_name + " fit)";
  } else {
    liquid.shear_rate = reference_rate;
    liquid.viscosity = find_fluid(in, name).properties.rheology->viscosity(reference_rate);
    liquid.viscosity_std_error = 0;
    rj["liquid_viscosity_source"] = "the liquid's rheology law (no φ = 0 points)";
  }
  rj["liquid_viscosity"] = liquid.viscosity;
  rj["liquid_viscosity_std_error"] = finite_or_null(liquid.viscosity_std_error);

  std::vector<RelativeViscosityPoint> rv;
  auto rv_json = nlohmann::ordered_json::array();
  for (const auto& [phi, fit] : by_phi) {
    FlowPrediction suspension = predict(fit, reference_rate);
    // The fit sees only the scatter between the points; an error they share (one suspension
    // box serving every rate of a φ, so its statistical error moves every torque together)
    // it cannot see. The smallest relative torque error of the φ's points bounds it from below.
    double shared = std::numeric_limits<double>::infinity();
    for (const auto& s : series)
      if (s.fluid == name && s.volume_fraction == phi)
        for (const std::size_t i : s.point_indices)
          shared = std::min(shared, number(points[i], "torque_std_error") / number(points[i], "torque"));
    const bool floored = std::isfinite(shared) && shared * suspension.viscosity > suspension.viscosity_std_error;
    if (floored) suspension.viscosity_std_error = shared * suspension.viscosity;
    RelativeViscosityPoint p = relative_viscosity(phi, suspension, liquid);
    if (phi == 0.0 && liquid_fit != by_phi.end()) p = {0.0, 1.0, 0.0};  // the liquid against itself
    rv.push_back(p);
    rv_json.push_back({{"volume_fraction", phi},
                       {"relative_viscosity", p.relative_viscosity},
                       {"std_error", p.std_error},
                       {"viscosity", suspension.viscosity},
                       {"viscosity_std_error", finite_or_null(suspension.viscosity_std_error)},
                       {"std_error_source", floored ? "the points' shared statistical error" : "the flow-curve fit"},
                       {"model", fit.model_name}});
  }
  rj["points"] = rv_json;
  auto correlations = nlohmann::ordered_json::array();
  try {
    const RelativeViscosityAnalysis a = analyze_relative_viscosity(rv);
    for (const auto* c : {&a.einstein, &a.batchelor, &a.krieger_dougherty, &a.maron_pierce})
      correlations.push_back(correlation_json(*c));
  } catch (const std::exception& e) {
    warnings.push_back(fmt::format("{}: correlations not compared: {}", name, e.what()));
  }
  if (std::none_of(rv.begin(), rv.end(), [](const auto& p) { return p.volume_fraction > 0; }))
    warnings.push_back(name + ": no finished point with φ > 0: η_r(φ) is the liquid alone and φ_m is not fitted");
  rj["correlations"] = correlations;
  rj["warnings"] = warnings;
  return rj;
}

}  // namespace

void add_flow_analysis(nlohmann::ordered_json& summary, const RunAnalysisInputs& in) {
  if (in.fluids.empty()) throw std::invalid_argument("add_flow_analysis: no fluids");
  auto& points = summary["points"];
  // Flow curves carry φ in their label when the run has suspension points.
  const bool has_suspension = std::any_of(points.begin(), points.end(), [](const auto& p) {
    return p.contains("volume_fraction") && p["volume_fraction"].template get<double>() > 0;
  });
  std::vector<std::string> fluid_names;
  for (const auto& p : points) {
    const std::string name = p.value("fluid", in.fluids.front().name);
    if (std::find(fluid_names.begin(), fluid_names.end(), name) == fluid_names.end()) fluid_names.push_back(name);
  }

  std::vector<Series> series = group_into_series(points, in, fluid_names, has_suspension);
  SeriesAnalysis analysis;
  for (auto& s : series) analyse_series(s, points, in, analysis);
  // η_r(φ) per fluid at the largest shear rate every φ of that fluid reached.
  auto relative = nlohmann::ordered_json::array();
  for (const auto& name : fluid_names) relative.push_back(relative_viscosity_of(name, analysis, series, points, in));

  summary["series"] = analysis.series;
  summary["fits"] = analysis.fits;
  summary["yield_stress"] = analysis.yields;
  summary["relative_viscosity"] = relative;
}

}  // namespace rheosim::rheometer
