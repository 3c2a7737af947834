#include "rheosim/rheometer/sweep_summary.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string_view>
#include <utility>

#include "rheosim/core/output.hpp"
#include "rheosim/core/report_page.hpp"
#include "rheosim/core/run_summary.hpp"

namespace rheosim::rheometer {

namespace {

using core::SummaryReader;

Interval95 interval_of(const SummaryReader& r, std::string_view key) {
  const std::vector<MaybeNumber> bounds = r.numbers_or_null(key);
  if (bounds.size() != 2) r.refuse(key, "[lower, upper]");
  return {bounds[0], bounds[1]};
}

std::vector<std::string> texts_if_any(const SummaryReader& r, std::string_view key) {
  return r.has(key) ? r.texts(key) : std::vector<std::string>{};
}

SweepPointRecord point_of(const SummaryReader& p) {
  SweepPointRecord out;
  out.fluid = p.text("fluid");
  out.volume_fraction = p.optional_number("volume_fraction").value_or(0.0);
  out.shear_rate = p.number("shear_rate");
  out.converged = p.boolean("converged");
  out.method = p.has("method") ? p.text("method") : std::string();
  out.model = p.has("model") ? p.text("model") : std::string();
  out.model_reason = p.has("model_reason") ? p.text("model_reason") : std::string();
  if (!out.converged) {
    out.failure = p.has("failure") ? p.text("failure") : std::string();
    return out;
  }
  out.torque = p.number("torque");
  out.warnings = texts_if_any(p, "warnings");
  if (const auto cost = p.optional_object("cost"))
    out.cost = PointCost{cost->number("dem"),   cost->number("void_fraction"),     cost->number("forces"),
                         cost->number("fluid"), cost->number("coupling_overhead"), cost->optional_number("near_field")};
  for (auto [key, value] : {std::pair{"angular_velocity", &out.angular_velocity},
                            {"torque_fluid", &out.torque_fluid},
                            {"torque_contact", &out.torque_contact},
                            {"torque_lubrication", &out.torque_lubrication},
                            {"torque_stresslet", &out.torque_stresslet},
                            {"torque_couple", &out.torque_couple},
                            {"torque_grid", &out.torque_grid},
                            {"torque_half_grid", &out.torque_half_grid},
                            {"inertia_effect", &out.inertia_effect},
                            {"torque_quadrature", &out.torque_quadrature},
                            {"strain", &out.strain},
                            {"estimated_error", &out.estimated_error},
                            {"torque_std_error", &out.torque_std_error},
                            {"torque_analytic", &out.torque_analytic},
                            {"rel_error", &out.rel_error},
                            {"torque_creeping", &out.torque_creeping},
                            {"creeping_rel_error", &out.creeping_rel_error},
                            {"gap_reynolds_number", &out.gap_reynolds_number},
                            {"wall_time", &out.wall_time},
                            {"iterations", &out.iterations},
                            {"log_slope", &out.log_slope},
                            {"log_slope_std_error", &out.log_slope_std_error},
                            {"apparent_stress", &out.apparent_stress},
                            {"rim_stress", &out.rim_stress},
                            {"apparent_viscosity", &out.apparent_viscosity},
                            {"viscosity", &out.viscosity},
                            {"normal_force", &out.normal_force},
                            {"n1_minus_n2", &out.n1_minus_n2},
                            {"n1", &out.n1},
                            {"n2", &out.n2}})
    *value = p.optional_number(key);
  if (const auto v = p.optional_object("validity")) {
    PointChecks checks;
    checks.gap_reynolds = v->number_or_null("gap_reynolds");
    checks.particle_reynolds = v->number_or_null("particle_reynolds");
    checks.stokes = v->number_or_null("stokes");
    checks.gap_to_diameter = v->number_or_null("gap_to_diameter");
    checks.gap_reynolds_ok = v->boolean("gap_reynolds_ok");
    checks.particle_reynolds_ok = v->boolean("particle_reynolds_ok");
    checks.stokes_ok = v->boolean("stokes_ok");
    checks.gap_to_diameter_ok = v->boolean("gap_to_diameter_ok");
    checks.valid = v->boolean("valid");
    checks.messages = v->texts("messages");
    out.validity = std::move(checks);
  }
  out.used_in_fits = p.optional_boolean("used_in_fits");
  return out;
}

SeriesRecord series_of(const SummaryReader& s) {
  SeriesRecord out;
  out.label = s.text("label");
  out.fluid = s.text("fluid");
  out.volume_fraction = s.number("volume_fraction");
  out.points = s.count("points");
  if (s.has("fitted_points")) out.fitted_points = s.count("fitted_points");
  if (s.has("best_model")) out.best_model = s.text("best_model");
  if (const auto line = s.optional_object("torque_line"))
    out.torque_line = TorqueLine{line->number("intercept"),
                                 line->number("slope"),
                                 line->number_or_null("intercept_std_error"),
                                 line->number_or_null("slope_std_error"),
                                 line->number("plastic_viscosity"),
                                 interval_of(*line, "plastic_viscosity_ci95"),
                                 line->numbers("residuals")};
  out.warnings = texts_if_any(s, "warnings");
  return out;
}

FitRecord fit_of(const SummaryReader& f) {
  FitRecord out;
  out.label = f.text("label");
  out.fluid = f.text("fluid");
  out.volume_fraction = f.number("volume_fraction");
  out.model = f.text("model");
  out.equation = f.text("equation");
  out.converged = f.boolean("converged");
  out.iterations = f.integer("iterations");
  out.stop_reason = f.text("stop_reason");
  out.points = f.integer("points");
  out.degrees_of_freedom = f.integer("degrees_of_freedom");
  out.residual_std = f.number_or_null("residual_std");
  out.sum_of_squares = f.number_or_null("sum_of_squares");
  out.aic = f.number_or_null("aic");
  out.aicc = f.number_or_null("aicc");
  out.min_shear_rate = f.number("min_shear_rate");
  out.max_shear_rate = f.number("max_shear_rate");
  for (const auto& p : f.objects("parameters"))
    out.parameters.push_back({p.text("name"), p.text("symbol"), p.text("unit"), p.number_or_null("value"),
                              p.number_or_null("std_error"), interval_of(p, "ci95")});
  const nlohmann::json& correlation = f.at("correlation");
  if (!correlation.is_array() ||
      !std::all_of(correlation.begin(), correlation.end(), [](const nlohmann::json& row) { return row.is_array(); }))
    f.refuse("correlation", "a list of rows of numbers");
  for (const auto& row : correlation) {
    std::vector<MaybeNumber> values;
    for (const auto& c : row) values.push_back(c.is_number() ? MaybeNumber(c.get<double>()) : std::nullopt);
    out.correlation.push_back(std::move(values));
  }
  out.shear_rate = f.numbers("shear_rate");
  out.residuals = f.numbers_or_null("residuals");
  for (const auto& w : f.objects("warnings"))
    out.warnings.push_back({w.text("kind"), w.text("parameter"), w.text("message")});
  out.rank = f.count("rank");
  out.delta = f.number_or_null("delta");
  out.akaike_weight = f.number_or_null("akaike_weight");
  return out;
}

YieldRecord yield_of(const SummaryReader& y) {
  YieldRecord out;
  out.label = y.text("label");
  out.fluid = y.text("fluid");
  out.volume_fraction = y.number("volume_fraction");
  out.method = y.text("method");
  out.value = y.number_or_null("value");
  out.std_error = y.number_or_null("std_error");
  out.ci95 = interval_of(y, "ci95");
  out.significant = y.boolean("significant");
  out.converged = y.boolean("converged");
  out.warnings = texts_if_any(y, "warnings");
  out.akaike_weight = y.optional_number("akaike_weight");
  return out;
}

RelativeViscosityRecord relative_viscosity_of(const SummaryReader& r) {
  RelativeViscosityRecord out;
  out.fluid = r.text("fluid");
  out.warnings = texts_if_any(r, "warnings");
  if (!r.has("reference_shear_rate")) return out;  // nothing fitted
  out.reference_shear_rate = r.number_or_null("reference_shear_rate");
  out.liquid_viscosity_source = r.text("liquid_viscosity_source");
  out.liquid_viscosity = r.number_or_null("liquid_viscosity");
  out.liquid_viscosity_std_error = r.number_or_null("liquid_viscosity_std_error");
  for (const auto& p : r.objects("points"))
    out.points.push_back({p.number("volume_fraction"), p.number_or_null("relative_viscosity"),
                          p.number_or_null("std_error"), p.number_or_null("viscosity"),
                          p.number_or_null("viscosity_std_error"), p.text("std_error_source"), p.text("model")});
  for (const auto& c : r.objects("correlations"))
    out.correlations.push_back({c.text("name"), c.numbers_or_null("predicted"), c.number_or_null("sum_of_squares"),
                                c.number_or_null("max_packing"), c.number_or_null("max_packing_std_error"),
                                interval_of(c, "max_packing_ci95"), c.number_or_null("intrinsic_viscosity"),
                                c.integer("degrees_of_freedom"), c.number_or_null("aic"), c.boolean("converged"),
                                texts_if_any(c, "warnings")});
  return out;
}

using core::value_or_null;

nlohmann::ordered_json values_or_null(const std::vector<MaybeNumber>& xs) {
  auto out = nlohmann::ordered_json::array();
  for (const auto& x : xs) out.push_back(value_or_null(x));
  return out;
}

nlohmann::ordered_json interval_json(const Interval95& i) { return {value_or_null(i.lower), value_or_null(i.upper)}; }

nlohmann::ordered_json checks_json(const PointChecks& c) {
  nlohmann::ordered_json v;
  v["gap_reynolds"] = value_or_null(c.gap_reynolds);
  v["particle_reynolds"] = value_or_null(c.particle_reynolds);
  v["stokes"] = value_or_null(c.stokes);
  v["gap_to_diameter"] = value_or_null(c.gap_to_diameter);
  v["gap_reynolds_ok"] = c.gap_reynolds_ok;
  v["particle_reynolds_ok"] = c.particle_reynolds_ok;
  v["stokes_ok"] = c.stokes_ok;
  v["gap_to_diameter_ok"] = c.gap_to_diameter_ok;
  v["valid"] = c.valid;
  v["messages"] = c.messages;
  return v;
}

// What the flow analysis adds to a converged point, after the sweep's keys.
void add_flow_curve_keys(const SweepPointRecord& r, nlohmann::ordered_json& p) {
  if (r.n1_minus_n2) p["n1_minus_n2"] = *r.n1_minus_n2;
  if (r.apparent_stress) {
    p["log_slope"] = value_or_null(r.log_slope);
    p["log_slope_std_error"] = value_or_null(r.log_slope_std_error);
    p["apparent_stress"] = *r.apparent_stress;
    p["rim_stress"] = value_or_null(r.rim_stress);
    p["apparent_viscosity"] = value_or_null(r.apparent_viscosity);
    p["viscosity"] = value_or_null(r.viscosity);
  }
  if (r.validity) p["validity"] = checks_json(*r.validity);
  if (r.used_in_fits) p["used_in_fits"] = *r.used_in_fits;
}

}  // namespace

nlohmann::ordered_json to_json(const SweepPointRecord& r) {
  nlohmann::ordered_json p;
  p["fluid"] = r.fluid;
  p["volume_fraction"] = r.volume_fraction;
  p["shear_rate"] = r.shear_rate;
  if (!r.converged) {
    p["converged"] = false;
    p["method"] = r.method;
    p["model"] = r.model;
    p["model_reason"] = r.model_reason;
    p["failure"] = r.failure;
    return p;
  }
  p["angular_velocity"] = value_or_null(r.angular_velocity);
  p["torque"] = r.torque;
  p["torque_fluid"] = value_or_null(r.torque_fluid);
  p["torque_contact"] = value_or_null(r.torque_contact);
  if (r.torque_lubrication || r.torque_stresslet) {
    p["torque_lubrication"] = value_or_null(r.torque_lubrication);
    p["torque_stresslet"] = value_or_null(r.torque_stresslet);
    p["torque_couple"] = value_or_null(r.torque_couple);
  }
  p["torque_std_error"] = value_or_null(r.torque_std_error);
  if (r.torque_grid) {
    p["torque_grid"] = *r.torque_grid;                          // this grid's own torque (solver.extrapolate)
    p["torque_half_grid"] = value_or_null(r.torque_half_grid);  // half the cells in r and z
  }
  p["torque_creeping"] = value_or_null(r.torque_creeping);
  if (r.inertia_effect) p["inertia_effect"] = *r.inertia_effect;
  if (r.torque_quadrature) p["torque_quadrature"] = *r.torque_quadrature;
  if (r.torque_analytic) {
    p["torque_analytic"] = *r.torque_analytic;
    p["rel_error"] = value_or_null(r.rel_error);
    p["creeping_rel_error"] = value_or_null(r.creeping_rel_error);
  }
  if (r.normal_force) {
    p["normal_force"] = *r.normal_force;
    p["n1"] = value_or_null(r.n1);
    p["n2"] = value_or_null(r.n2);
  }
  if (!r.warnings.empty()) p["warnings"] = r.warnings;
  p["gap_reynolds_number"] = value_or_null(r.gap_reynolds_number);
  p["strain"] = value_or_null(r.strain);
  p["method"] = r.method;
  if (!r.model.empty()) {
    p["model"] = r.model;
    p["model_reason"] = r.model_reason;
    p["estimated_error"] = value_or_null(r.estimated_error);
  }
  p["iterations"] = static_cast<long long>(r.iterations.value_or(0.0));
  p["wall_time"] = value_or_null(r.wall_time);
  if (r.cost) {
    p["cost"] = {{"dem", r.cost->dem},
                 {"void_fraction", r.cost->void_fraction},
                 {"forces", r.cost->forces},
                 {"fluid", r.cost->fluid},
                 {"coupling_overhead", r.cost->coupling_overhead}};
    if (r.cost->near_field) p["cost"]["near_field"] = *r.cost->near_field;
  }
  p["converged"] = true;
  add_flow_curve_keys(r, p);
  return p;
}

nlohmann::ordered_json to_json(const SeriesRecord& s) {
  nlohmann::ordered_json j;
  j["label"] = s.label;
  j["fluid"] = s.fluid;
  j["volume_fraction"] = s.volume_fraction;
  j["points"] = s.points;
  if (s.fitted_points) j["fitted_points"] = *s.fitted_points;
  if (s.best_model) j["best_model"] = *s.best_model;
  if (const auto& line = s.torque_line)
    j["torque_line"] = {{"intercept", line->intercept},
                        {"intercept_std_error", value_or_null(line->intercept_std_error)},
                        {"slope", line->slope},
                        {"slope_std_error", value_or_null(line->slope_std_error)},
                        {"plastic_viscosity", line->plastic_viscosity},
                        {"plastic_viscosity_ci95", interval_json(line->plastic_viscosity_ci95)},
                        {"residuals", line->residuals}};
  j["warnings"] = s.warnings;
  return j;
}

nlohmann::ordered_json to_json(const FitRecord& f) {
  nlohmann::ordered_json j;
  j["label"] = f.label;
  j["fluid"] = f.fluid;
  j["volume_fraction"] = f.volume_fraction;
  j["model"] = f.model;
  j["equation"] = f.equation;
  j["converged"] = f.converged;
  j["iterations"] = f.iterations;
  j["stop_reason"] = f.stop_reason;
  j["points"] = f.points;
  j["degrees_of_freedom"] = f.degrees_of_freedom;
  j["residual_std"] = value_or_null(f.residual_std);
  j["sum_of_squares"] = value_or_null(f.sum_of_squares);
  j["aic"] = value_or_null(f.aic);
  j["aicc"] = value_or_null(f.aicc);
  j["min_shear_rate"] = f.min_shear_rate;
  j["max_shear_rate"] = f.max_shear_rate;
  auto parameters = nlohmann::ordered_json::array();
  for (const auto& p : f.parameters)
    parameters.push_back({{"name", p.name},
                          {"symbol", p.symbol},
                          {"unit", p.unit},
                          {"value", value_or_null(p.value)},
                          {"std_error", value_or_null(p.std_error)},
                          {"ci95", interval_json(p.ci95)}});
  j["parameters"] = parameters;
  auto correlation = nlohmann::ordered_json::array();
  for (const auto& row : f.correlation) correlation.push_back(values_or_null(row));
  j["correlation"] = correlation;
  j["shear_rate"] = f.shear_rate;
  j["residuals"] = values_or_null(f.residuals);
  auto warnings = nlohmann::ordered_json::array();
  for (const auto& w : f.warnings)
    warnings.push_back({{"kind", w.kind}, {"parameter", w.parameter}, {"message", w.message}});
  j["warnings"] = warnings;
  j["rank"] = f.rank;
  j["delta"] = value_or_null(f.delta);
  j["akaike_weight"] = value_or_null(f.akaike_weight);
  return j;
}

nlohmann::ordered_json to_json(const YieldRecord& y) {
  nlohmann::ordered_json j;
  j["label"] = y.label;
  j["fluid"] = y.fluid;
  j["volume_fraction"] = y.volume_fraction;
  j["method"] = y.method;
  j["value"] = value_or_null(y.value);
  j["std_error"] = value_or_null(y.std_error);
  j["ci95"] = interval_json(y.ci95);
  j["significant"] = y.significant;
  j["converged"] = y.converged;
  j["warnings"] = y.warnings;
  if (y.akaike_weight) j["akaike_weight"] = *y.akaike_weight;
  return j;
}

nlohmann::ordered_json to_json(const RelativeViscosityRecord& r) {
  nlohmann::ordered_json j;
  j["fluid"] = r.fluid;
  if (r.reference_shear_rate) {
    j["reference_shear_rate"] = *r.reference_shear_rate;
    j["liquid_viscosity_source"] = r.liquid_viscosity_source;
    j["liquid_viscosity"] = value_or_null(r.liquid_viscosity);
    j["liquid_viscosity_std_error"] = value_or_null(r.liquid_viscosity_std_error);
    auto points = nlohmann::ordered_json::array();
    for (const auto& p : r.points)
      points.push_back({{"volume_fraction", p.volume_fraction},
                        {"relative_viscosity", value_or_null(p.relative_viscosity)},
                        {"std_error", value_or_null(p.std_error)},
                        {"viscosity", value_or_null(p.viscosity)},
                        {"viscosity_std_error", value_or_null(p.viscosity_std_error)},
                        {"std_error_source", p.std_error_source},
                        {"model", p.model}});
    j["points"] = points;
    auto correlations = nlohmann::ordered_json::array();
    for (const auto& c : r.correlations)
      correlations.push_back({{"name", c.name},
                              {"predicted", values_or_null(c.predicted)},
                              {"sum_of_squares", value_or_null(c.sum_of_squares)},
                              {"max_packing", value_or_null(c.max_packing)},
                              {"max_packing_std_error", value_or_null(c.max_packing_std_error)},
                              {"max_packing_ci95", interval_json(c.max_packing_ci95)},
                              {"intrinsic_viscosity", value_or_null(c.intrinsic_viscosity)},
                              {"degrees_of_freedom", c.degrees_of_freedom},
                              {"aic", value_or_null(c.aic)},
                              {"converged", c.converged},
                              {"warnings", c.warnings}});
    j["correlations"] = correlations;
  }
  j["warnings"] = r.warnings;
  return j;
}

nlohmann::ordered_json to_json(const SweepSummary& s) {
  nlohmann::ordered_json j = core::to_json(s.head);
  j["radius"] = s.radius;
  j["gap"] = s.gap;
  if (const auto& g = s.grid) {
    j["grid"] = {{"radial_cells", g->radial_cells},
                 {"axial_cells", g->axial_cells},
                 {"radial_grading", g->radial_grading},
                 {"axial_stretching", g->axial_stretching},
                 {"extrapolate", g->extrapolate}};
    if (!g->applies_to.empty()) j["grid"]["applies_to"] = g->applies_to;
  }
  j["inertia"] = s.inertia;
  j["volume_fractions"] = s.volume_fractions;
  j["shear_rates"] = s.shear_rates;
  j["points_total"] = s.points_total;
  j["points_failed"] = s.points_failed;
  if (s.points_resumed) j["points_resumed"] = *s.points_resumed;
  j["wall_time"] = s.wall_time;
  const auto add_records = [&j](const char* key, const auto& list) {
    auto& array = j[key] = nlohmann::ordered_json::array();
    for (const auto& record : list) array.push_back(to_json(record));
  };
  add_records("points", s.points);
  auto& warnings = j["warnings"] = nlohmann::ordered_json::array();
  for (const auto& w : s.warnings) warnings.push_back({{"warning", w.warning}, {"points", w.points}});
  add_records("series", s.series);
  add_records("fits", s.fits);
  add_records("yield_stress", s.yield_stress);
  add_records("relative_viscosity", s.relative_viscosity);
  return j;
}

SweepSummary read_sweep_summary(const std::filesystem::path& run_dir) {
  const auto path = core::run_summary_file(run_dir);
  const nlohmann::json json = core::read_json(path);
  const SummaryReader r(json, path, "every rheometer and sweep run",
                        "pass the --out folder of a finished 'rheosim run' of a rheometer or sweep case");
  SweepSummary s;
  // Every rheometer case runs as a sweep and writes kind "sweep". Checked before any other key.
  if (const std::string kind = r.text("kind"); kind != "sweep")
    core::refuse_summary_kind(path, kind, "the summary of a rheometer or sweep run (kind \"sweep\")",
                              "an LDD run gets the LDD report; a summary of another kind: run its case again");
  s.head = core::read_summary_head(r);
  s.radius = r.number("radius");
  s.gap = r.number("gap");
  s.wall_time = r.number("wall_time");
  s.inertia = r.boolean("inertia");
  if (r.has("volume_fractions")) s.volume_fractions = r.numbers("volume_fractions");
  if (r.has("shear_rates")) s.shear_rates = r.numbers("shear_rates");
  if (r.has("points_total")) s.points_total = r.count("points_total");
  s.points_failed = r.count("points_failed");
  if (r.has("points_resumed")) s.points_resumed = r.count("points_resumed");
  if (const auto g = r.optional_object("grid"))
    s.grid = SweepGridRecord{g->integer("radial_cells"),
                             g->integer("axial_cells"),
                             g->number("radial_grading"),
                             g->optional_number("axial_stretching").value_or(0.0),
                             g->optional_boolean("extrapolate").value_or(false),
                             g->has("applies_to") ? g->text("applies_to") : std::string()};
  if (r.has("warnings"))
    for (const auto& w : r.objects("warnings")) s.warnings.push_back({w.text("warning"), w.count("points")});
  for (const auto& p : r.objects("points")) s.points.push_back(point_of(p));
  for (const auto& x : r.objects("series")) s.series.push_back(series_of(x));
  for (const auto& f : r.objects("fits")) s.fits.push_back(fit_of(f));
  for (const auto& y : r.objects("yield_stress")) s.yield_stress.push_back(yield_of(y));
  for (const auto& v : r.objects("relative_viscosity")) s.relative_viscosity.push_back(relative_viscosity_of(v));
  return s;
}

}  // namespace rheosim::rheometer
