// summary.json of an LDD run written from and read into a RunSummary (rheosim/ldd/summary.hpp).
#include "rheosim/ldd/summary.hpp"

#include <string_view>

#include "rheosim/core/output.hpp"
#include "rheosim/core/report_page.hpp"
#include "rheosim/core/run_summary.hpp"
#include "rheosim/ldd/run.hpp"

namespace rheosim::ldd {

namespace {

using Json = nlohmann::ordered_json;
using core::SummaryReader;

constexpr std::string_view summary_hint = "pass the --out folder of a finished 'rheosim run' of a kind: ldd case";

using core::value_or_null;

Json centerline_json(const std::vector<CenterlineSample>& line, const char* position, const char* velocity) {
  auto out = Json::array();
  for (const auto& p : line) out.push_back({{position, p.position}, {velocity, p.velocity}});
  return out;
}

void add_cavity_keys(const RunSummary& s, Json& j) {
  j["reynolds_number"] = s.reynolds_number;
  j["final_residual"] = s.final_residual;
  j["wall_time"] = s.wall_time;
  j["resumed_at_steps"] = s.resumed_at_steps;
  j["centerlines"] = {{"vertical", centerline_json(s.vertical_centerline, "y", "u")},
                      {"horizontal", centerline_json(s.horizontal_centerline, "x", "v")}};
  if (const auto& g = s.ghia) {
    auto points = Json::array();
    for (const auto& p : g->points)
      points.push_back(
          {{"line", p.line}, {"coordinate", p.coordinate}, {"computed", p.computed}, {"reference", p.reference}});
    j["ghia"] = {{"reynolds", g->reynolds}, {"max_error", g->max_error}, {"points", points}};
  }
  j["warnings"] = s.warnings;
}

void add_dam_break_references(const RunSummary& s, Json& j) {
  if (const auto& a = s.thin_film_arrest)
    j["thin_film_arrest"] = {{"length", a->length},
                             {"front", a->front},
                             {"wall_height", a->wall_height},
                             {"relative_error", value_or_null(a->relative_error)},
                             {"fitted_yield_stress", value_or_null(a->fitted_yield_stress)},
                             {"fitted_length", value_or_null(a->fitted_length)},
                             {"fitted_rms_height_error", value_or_null(a->fitted_rms_height_error)}};
  if (const auto& t = s.table1) {
    auto rows = Json::array();
    for (const auto& r : t->rows)
      rows.push_back({{"t", r.t},
                      {"experiment", r.experiment},
                      {"front", value_or_null(r.front)},
                      {"error", value_or_null(r.error)},
                      {"ldd_seed", value_or_null(r.ldd_seed)}});
    j["table1"] = {{"rows", rows}, {"rms_error", value_or_null(t->rms_error)}, {"max_error", t->max_error}};
  }
  if (const auto& m = s.martin_moyce) {
    auto rows = Json::array();
    for (const auto& r : m->rows)
      rows.push_back({{"T", r.T},
                      {"Z_experiment", r.Z_experiment},
                      {"Z", value_or_null(r.Z)},
                      {"relative_error", value_or_null(r.relative_error)}});
    j["martin_moyce"] = {{"rows", rows}, {"max_relative_error", value_or_null(m->max_relative_error)}};
  }
}

void add_free_surface_keys(const RunSummary& s, Json& j) {
  j["volume_drift"] = s.volume_drift;
  j["bulk_compression"] = value_or_null(s.bulk_compression);
  j["bulk_number_compression"] = value_or_null(s.bulk_number_compression);
  j["kinetic_energy_peak"] = s.kinetic_energy_peak;
  j["energy_gain"] = value_or_null(s.energy_gain);
  j["repeated_solves"] = s.repeated_solves;
  j["warnings"] = s.warnings;
  j["repeated_with_lu"] = s.repeated_with_lu;  // of which; the rest with a fresh AMG hierarchy
  j["pressure_amg_plain_from"] = value_or_null(s.pressure_amg_plain_from);
  j["iterations_per_step"] = {{"pressure", s.pressure_iterations_per_step},
                              {"velocity", s.velocity_iterations_per_step}};
  j["neighbour_searches"] = s.neighbour_searches;
  j["wall_time"] = s.wall_time;
  j["resumed_at_steps"] = s.resumed_at_steps;
  if (s.scene == "dam_break") {
    auto front = Json::array();
    for (const auto& p : s.front) front.push_back({{"t", p.t}, {"x", p.x}});
    j["front"] = front;
    add_dam_break_references(s, j);
  }
  if (s.scene == "slump") {
    auto spread = Json::array();
    for (const auto& p : s.spread) spread.push_back({{"t", p.t}, {"diameter", p.diameter}, {"height", p.height}});
    j["spread"] = spread;
  }
  if (s.scene != "column") {
    j["final_spread"] = value_or_null(s.final_spread);
    j["final_height"] = value_or_null(s.final_height);
    j["yielded_fraction"] = value_or_null(s.yielded_fraction);
    j["largest_stress_ratio"] = value_or_null(s.largest_stress_ratio);
    j["arrested"] = s.arrested;
  }
  if (const auto& p = s.pashias)
    j["pashias"] = {{"yield_stress_ratio", p->yield_stress_ratio},
                    {"slump", p->slump},
                    {"measured_slump", value_or_null(p->measured_slump)},
                    {"difference", value_or_null(p->difference)},
                    {"von_mises_slump", p->von_mises_slump},
                    {"implied_yield_stress", value_or_null(p->implied_yield_stress)}};
  if (const auto& r = s.roussel_coussot)
    j["roussel_coussot"] = {{"diameter", r->diameter},
                            {"relative_error", value_or_null(r->relative_error)},
                            {"implied_yield_stress", value_or_null(r->implied_yield_stress)}};
  if (const auto& w = s.sloshing)
    j["sloshing"] = {{"period", w->period},
                     {"wave_energy", w->wave_energy},
                     {"compared_until", w->compared_until},
                     {"crossings", w->crossings},
                     {"measured_period", value_or_null(w->measured_period)},
                     {"relative_error", value_or_null(w->relative_error)},
                     {"first_crossing", value_or_null(w->first_crossing)}};
}

void read_cavity_keys(const SummaryReader& r, RunSummary& s) {
  s.reynolds_number = r.number("reynolds_number");
  s.final_residual = r.number("final_residual");
  const SummaryReader lines = r.object("centerlines");
  for (const auto& p : lines.objects("vertical")) s.vertical_centerline.push_back({p.number("y"), p.number("u")});
  for (const auto& p : lines.objects("horizontal")) s.horizontal_centerline.push_back({p.number("x"), p.number("v")});
  if (const auto g = r.optional_object("ghia")) {  // a square Newtonian cavity at a Reynolds number Ghia tabulates
    GhiaComparison ghia;
    ghia.reynolds = static_cast<int>(g->integer("reynolds"));
    ghia.max_error = g->number("max_error");
    for (const auto& p : g->objects("points"))
      ghia.points.push_back({p.text("line"), p.number("coordinate"), p.number("computed"), p.number("reference")});
    s.ghia = std::move(ghia);
  }
}

void read_dam_break_references(const SummaryReader& r, RunSummary& s) {
  // A yield-stress law on a horizontal floor: its shallow arrest (absent under a tilted gravity).
  if (s.yielded_fraction && r.has("thin_film_arrest")) {
    const SummaryReader a = r.object("thin_film_arrest");
    // No fit: the keys are null, or absent (summaries of older revisions).
    s.thin_film_arrest = ThinFilmArrestComparison{a.number("length"),
                                                  a.number("front"),
                                                  a.number("wall_height"),
                                                  a.number_or_null("relative_error"),
                                                  a.optional_number("fitted_yield_stress"),
                                                  a.optional_number("fitted_length"),
                                                  a.optional_number("fitted_rms_height_error")};
  }
  if (const auto t = r.optional_object("table1")) {
    Table1Comparison table;
    for (const auto& row : t->objects("rows"))
      table.rows.push_back({row.number("t"), row.number("experiment"), row.number_or_null("front"),
                            row.number_or_null("error"), row.number_or_null("ldd_seed")});
    table.rms_error = t->number_or_null("rms_error");
    table.max_error = t->number("max_error");
    s.table1 = std::move(table);
  }
  if (const auto m = r.optional_object("martin_moyce")) {
    MartinMoyceComparison mm;
    for (const auto& row : m->objects("rows"))
      mm.rows.push_back(
          {row.number("T"), row.number("Z_experiment"), row.number_or_null("Z"), row.number_or_null("relative_error")});
    mm.max_relative_error = m->number_or_null("max_relative_error");
    s.martin_moyce = std::move(mm);
  }
}

void read_free_surface_keys(const SummaryReader& r, RunSummary& s) {
  s.volume_drift = r.number("volume_drift");
  s.bulk_compression = r.optional_number("bulk_compression");
  s.bulk_number_compression = r.optional_number("bulk_number_compression");
  s.kinetic_energy_peak = r.number("kinetic_energy_peak");
  s.energy_gain = r.number_or_null("energy_gain");
  s.repeated_solves = r.count("repeated_solves");
  s.repeated_with_lu = r.count("repeated_with_lu");
  s.pressure_amg_plain_from = r.optional_number("pressure_amg_plain_from");
  const SummaryReader iterations = r.object("iterations_per_step");
  s.pressure_iterations_per_step = iterations.number("pressure");
  s.velocity_iterations_per_step = iterations.number("velocity");
  s.neighbour_searches = r.count("neighbour_searches");
  if (const auto w = r.optional_object("sloshing"))
    s.sloshing = SloshingComparison{w->number("period"),
                                    w->number("wave_energy"),
                                    w->number("compared_until"),
                                    w->count("crossings"),
                                    w->number_or_null("measured_period"),
                                    w->number_or_null("relative_error"),
                                    w->number_or_null("first_crossing")};
  if (s.scene == "column") return;
  s.final_spread = r.number("final_spread");
  s.final_height = r.number("final_height");
  s.yielded_fraction = r.number_or_null("yielded_fraction");
  s.largest_stress_ratio = r.optional_number("largest_stress_ratio");
  s.arrested = r.boolean("arrested");
  if (s.scene == "dam_break") {
    for (const auto& p : r.objects("front")) s.front.push_back({p.number("t"), p.number("x")});
    read_dam_break_references(r, s);
  } else {
    for (const auto& p : r.objects("spread"))
      s.spread.push_back({p.number("t"), p.number("diameter"), p.number("height")});
    if (const auto p = r.optional_object("pashias")) {
      // von_mises_slump is a function of τ′ alone: summaries written without it get it computed.
      const double ratio = p->number("yield_stress_ratio");
      s.pashias = CylinderSlumpComparison{
          ratio,
          p->number("slump"),
          p->number_or_null("measured_slump"),
          p->number_or_null("difference"),
          p->optional_number("von_mises_slump").value_or(ratio > 0 ? von_mises_cylinder_slump(ratio) : 0.0),
          p->optional_number("implied_yield_stress")};  // absent in summaries of older revisions
    }
    if (const auto c = r.optional_object("roussel_coussot"))
      s.roussel_coussot = ConeSpreadComparison{c->number("diameter"), c->number_or_null("relative_error"),
                                               c->optional_number("implied_yield_stress")};
  }
}

}  // namespace

nlohmann::ordered_json to_json(const RunSummary& s) {
  Json j = core::to_json(s.head);
  j["scene"] = s.scene;
  j["dimension"] = s.dimension;
  j["status"] = s.status;
  if (!s.message.empty()) j["message"] = s.message;
  j["nodes"] = s.nodes;
  j["fluid_nodes"] = s.fluid_nodes;
  j["spacing"] = s.spacing;
  j["time_step"] = s.time_step;
  if (!s.time_step_rule.empty()) j["time_step_rule"] = s.time_step_rule;
  j["steps"] = s.steps;
  j["time"] = s.time;
  j["threads"] = s.threads;
  j["ms_per_step"] = s.ms_per_step;
  const PhaseTimes& t = s.phase_seconds;
  j["phase_seconds"] = {{"neighbours", t.neighbours}, {"operators", t.operators}, {"rheology", t.rheology},
                        {"pressure", t.pressure},     {"momentum", t.momentum},   {"advection", t.advection},
                        {"reordering", t.reordering}};
  if (s.free_surface())
    add_free_surface_keys(s, j);
  else
    add_cavity_keys(s, j);
  return j;
}

RunSummary read_run_summary(const std::filesystem::path& summary_json) {
  const nlohmann::json json = core::read_json(summary_json);
  const SummaryReader r(json, summary_json, "every LDD run", std::string(summary_hint));
  if (const std::string kind = r.text("kind"); kind != "ldd")
    core::refuse_summary_kind(
        summary_json, kind, "the summary of a kind: ldd run",
        "'rheosim report' writes the report of a rheometer or sweep run with the rheometer report");
  RunSummary s;
  s.head = core::read_summary_head(r);
  s.scene = r.text("scene");
  s.dimension = static_cast<int>(r.count("dimension"));
  s.status = r.text("status");
  s.message = r.has("message") ? r.text("message") : std::string();
  s.nodes = r.count("nodes");
  s.fluid_nodes = r.count("fluid_nodes");
  s.spacing = r.number("spacing");
  s.time_step = r.number("time_step");
  s.time_step_rule = r.has("time_step_rule") ? r.text("time_step_rule") : std::string();
  s.steps = r.count("steps");
  s.time = r.number("time");
  s.threads = static_cast<int>(r.count("threads"));
  s.ms_per_step = r.number("ms_per_step");
  const SummaryReader phases = r.object("phase_seconds");
  s.phase_seconds = {phases.number("neighbours"), phases.number("operators"), phases.number("rheology"),
                     phases.number("pressure"),   phases.number("momentum"),  phases.number("advection"),
                     phases.number("reordering")};
  s.wall_time = r.number("wall_time");
  for (double step : r.numbers("resumed_at_steps")) s.resumed_at_steps.push_back(static_cast<std::size_t>(step));
  s.warnings = r.texts("warnings");
  if (s.free_surface())
    read_free_surface_keys(r, s);
  else
    read_cavity_keys(r, s);
  return s;
}

}  // namespace rheosim::ldd
