// run_summary.cpp — summary.json with nlohmann::json (escaping, number formatting): the
// measurements gathered, written and read back in one place.
#include "cdpowder/run/run_summary.hpp"

#include "cdpowder/analysis/coordination.hpp"
#include "cdpowder/analysis/energy_budget.hpp"
#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/analysis/stress.hpp"
#include "cdpowder/core/lanes.hpp"
#include "cdpowder/setup/deposition.hpp"
#include "cdpowder/version.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

namespace cdpowder {

namespace {

using nlohmann::json;

constexpr double kAbsent = std::numeric_limits<double>::quiet_NaN();

/// The stage names of "stage_seconds", in Stage order.
constexpr std::array<const char*, static_cast<std::size_t>(Stage::Count)> kStageNames{
    "detect_contacts", "build_local_problems", "solve_nlgs", "integrate", "analyse"};

// ---- gathering -----------------------------------------------------------------------------

/// The normal forces the spheres put on each wall, per area of the cell: what σzz should
/// equal in a packing at rest between them (their mean under the packing's own weight)
/// [F_coh/R²].
std::pair<double, double> wall_loads_per_area(const Contacts& contacts, double area) {
  double piston = 0.0;
  double bottom = 0.0;
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    const double push = contacts.wall_actions[k].normal_force;
    (contacts.walls[k].wall == WallKind::Piston ? piston : bottom) += push;
  }
  return {piston / area, bottom / area};
}

RunSummary::Stress stress_of(const World& world, const Contacts& contacts, double volume,
                             double pressure) {
  const StressTensors sigma = stress_tensors(contacts, volume);
  RunSummary::Stress s;
  s.volume = volume;
  s.sigma = sigma.total;
  s.sigma_compressive = sigma.compressive;
  s.sigma_tensile = sigma.tensile;
  s.compressive_contacts = sigma.compressive_contacts;
  s.tensile_contacts = sigma.tensile_contacts;
  std::tie(s.piston_load_per_area, s.bottom_load_per_area) =
      wall_loads_per_area(contacts, world.box.area());
  const bool loaded = pressure > 0.0;
  s.sigma_zz_over_pressure = loaded ? sigma.total(2, 2) / pressure : kAbsent;
  s.sigma_zz_compressive_over_pressure = loaded ? sigma.compressive(2, 2) / pressure : kAbsent;
  s.sigma_zz_tensile_over_pressure = loaded ? sigma.tensile(2, 2) / pressure : kAbsent;
  return s;
}

}  // namespace

RunSummary::Energy energy_budget(const ContactLaws& laws, const World& world,
                                 const Contacts& contacts, const RunResult& result) {
  RunSummary::Energy e;
  e.complete = result.energy_known && result.steps > 0 && budget_is_complete(world);
  if (!e.complete) {
    e.piston_work = e.gravity_work = e.kinetic_start = e.kinetic_end = e.cohesive_start =
        e.cohesive_end = e.breaking_work = e.dissipated = kAbsent;
    return e;
  }
  const EnergyAtStart& start = result.energy_start;
  const Piston& piston = world.walls.piston;
  const double g_z = world.gravity.z();
  e.piston_work = piston.enabled ? piston.force * (start.piston_height - piston.height) : 0.0;
  if (g_z != 0.0) {  // (a zero g_z times a fall would write −0)
    e.gravity_work =
        g_z * (height_moment(world) - start.height_moment) +
        (piston.enabled ? g_z * piston.mass * (piston.height - start.piston_height) : 0.0);
  }
  e.kinetic_start = start.kinetic_energy;
  e.kinetic_end = kinetic_energy(world);
  e.cohesive_start = start.cohesive_energy;
  e.cohesive_end = cohesive_energy(contacts, laws);
  e.bonds_formed = result.bonds.formed();
  e.bonds_broken = result.bonds.broken();
  e.breaking_work = static_cast<double>(result.bonds.pairs_broken) * laws.spheres.cohesion_force *
                        laws.spheres.cohesion_range +
                    static_cast<double>(result.bonds.walls_broken) * laws.walls.cohesion_force *
                        laws.walls.cohesion_range;
  e.dissipated = e.piston_work + e.gravity_work - (e.kinetic_end - e.kinetic_start) -
                 (e.cohesive_end - e.cohesive_start);
  return e;
}

namespace {

RunSummary::Run run_counts(const Scene& scene, const RunResult& result) {
  RunSummary::Run r;
  r.blocked = result.blocked;
  if (result.blocked) r.blocked_by = result.blocked_by_probe ? "probe" : "window";
  r.probes = result.probes;
  r.probe_passes = result.probe_passes;
  r.probe_seconds = result.probe_seconds;
  r.unbalanced_rest_solves = result.unbalanced_rest_solves;
  r.not_blocked = result.not_blocked;
  r.interrupted = result.interrupted;
  r.failed = result.fault.has_value();
  r.until_blocked = scene.run.until_blocked;
  r.steps = result.steps;
  r.dt_min = result.min_dt;
  r.dt_max = result.max_dt;
  r.repeated_steps = result.repeated_steps;
  r.repeated_passes = result.repeated_passes;
  r.total_passes = result.total_passes;
  r.passes_per_step = result.steps > 0 ? static_cast<double>(result.total_passes) /
                                             static_cast<double>(result.steps)
                                       : 0.0;
  r.threaded_steps = result.threaded_steps;
  r.wall_seconds = result.wall_seconds;
  r.stage_seconds = result.stage_seconds;
  return r;
}

// ---- writing -------------------------------------------------------------------------------

json matrix_json(const Mat3& m) {
  json rows = json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({m(i, 0), m(i, 1), m(i, 2)});
  return rows;
}

/// The resolved scene as a JSON object (toml++ converts).
json scene_json(const std::string& scene_toml) {
  std::ostringstream text;
  text << toml::json_formatter{toml::parse(scene_toml)};
  return json::parse(text.str());
}

/// The first CPU's model name, family and model from /proc/cpuinfo, "AMD EPYC (family 25,
/// model 1)": a virtual machine's CPUs of different generations may share one name. Empty
/// where the system has no such file.
std::string cpu_description() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string name;
  std::string family;
  std::string model;
  std::string line;
  while (std::getline(cpuinfo, line) && !line.empty()) {  // the first CPU's block
    // "key<tabs>: value"
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string key = line.substr(0, colon);
    key.erase(key.find_last_not_of(" \t") + 1);  // npos + 1 = 0: a key of blanks is empty
    const std::size_t first = line.find_first_not_of(" \t", colon + 1);
    const std::string value = first == std::string::npos ? std::string{} : line.substr(first);
    if (key == "model name") name = value;
    if (key == "cpu family") family = value;
    if (key == "model") model = value;
  }
  if (name.empty()) return {};
  if (family.empty() || model.empty()) return name;
  return fmt::format("{} (family {}, model {})", name, family, model);
}

/// This build and where it runs.
RunSummary::Program this_program() {
  RunSummary::Program p;
  p.version = kVersion;
  p.commit = kGitCommit;
  p.kernel = lanes::kernel_isa_name();
  p.cpu = cpu_description();
  return p;
}

json program_json(const RunSummary::Program& p) {
  return {{"name", p.name},
          {"version", p.version},
          {"commit", p.commit},
          {"kernel", p.kernel},
          {"cpu", p.cpu}};
}

json fault_json(const RunFault& f) {
  const auto index = [](std::int64_t i) { return i >= 0 ? json(i) : json(nullptr); };
  return {{"quantity", f.quantity}, {"sphere", index(f.body)}, {"other_sphere", index(f.other)},
          {"step", f.step},         {"time", f.time},          {"value", f.value},
          {"message", f.message}};
}

json accuracy_json(const RunSummary::Accuracy& a) {
  json j = {{"mean_overlap", a.mean_overlap},
            {"max_overlap", a.max_overlap},
            {"max_overlap_during_run", a.max_overlap_during_run},
            {"max_net_force", a.max_net_force},
            {"max_cohesive_opening_per_range", a.max_cohesive_opening_per_range},
            {"last_step_residual", a.last_step_residual},
            {"last_step_error_estimate", a.last_step_error_estimate},
            {"last_step_converged", a.last_step_converged},
            {"capped_steps", a.capped_steps},
            {"final_solve", nullptr}};
  if (a.final_solve) {
    j["final_solve"] = {{"passes", a.final_solve->passes},
                        {"converged", a.final_solve->converged},
                        {"residual", a.final_solve->residual},
                        {"error_estimate", a.final_solve->error_estimate}};
  }
  return j;
}

json run_json(const RunSummary::Run& r) {
  json stages = json::object();
  for (std::size_t s = 0; s < kStageNames.size(); ++s) stages[kStageNames[s]] = r.stage_seconds[s];
  return {{"blocked", r.blocked},
          {"blocked_by", r.blocked_by.empty() ? json(nullptr) : json(r.blocked_by)},
          {"probes", r.probes},
          {"probe_passes", r.probe_passes},
          {"probe_seconds", r.probe_seconds},
          {"unbalanced_rest_solves", r.unbalanced_rest_solves},
          {"not_blocked", r.not_blocked.empty() ? json(nullptr) : json(r.not_blocked)},
          {"interrupted", r.interrupted},
          {"failed", r.failed},
          {"until_blocked", r.until_blocked},
          {"steps", r.steps},
          {"dt_min", r.dt_min},
          {"dt_max", r.dt_max},
          {"repeated_steps", r.repeated_steps},
          {"repeated_passes", r.repeated_passes},
          {"total_passes", r.total_passes},
          {"passes_per_step", r.passes_per_step},
          {"threaded_steps", r.threaded_steps},
          {"wall_seconds", r.wall_seconds},
          {"stage_seconds", stages}};
}

// ---- reading -------------------------------------------------------------------------------

/// One object of the file and its place in it ("run", "accuracy.final_solve"), for messages.
/// Absent optional fields read as absent values (NaN, 0, false, ""); a field of the wrong
/// type, or an absent required one, throws SummaryError naming it.
class Fields {
 public:
  Fields(const json& object, std::string where) : object_(object), where_(std::move(where)) {
    if (!object_.is_object()) fail("", "is not a JSON object");
  }

  [[nodiscard]] bool has(const char* key) const {
    const auto it = object_.find(key);
    return it != object_.end() && !it->is_null();
  }

  /// A number; JSON null (how non-finite numbers are written) and an absent key read as NaN.
  [[nodiscard]] double number(const char* key, bool required = false) const {
    const json* v = find(key, required);
    if (v == nullptr) return kAbsent;
    if (!v->is_number()) fail(key, "is not a number");
    return v->get<double>();
  }

  template <typename Int>
  [[nodiscard]] Int count(const char* key, bool required = false) const {
    const json* v = find(key, required);
    if (v == nullptr) return Int{0};
    if (v->is_number_unsigned()) return static_cast<Int>(v->get<std::uint64_t>());
    if (v->is_number_integer()) return static_cast<Int>(v->get<std::int64_t>());
    // counts are written as integers; a float that is a whole number is accepted too
    if (!v->is_number_float() || std::trunc(v->get<double>()) != v->get<double>()) {
      fail(key, "is not a whole number");
    }
    return static_cast<Int>(v->get<double>());
  }

  [[nodiscard]] bool flag(const char* key, bool required = false) const {
    const json* v = find(key, required);
    if (v == nullptr) return false;
    if (!v->is_boolean()) fail(key, "is not true or false");
    return v->get<bool>();
  }

  [[nodiscard]] std::string text(const char* key, bool required = false) const {
    const json* v = find(key, required);
    if (v == nullptr) return {};
    if (!v->is_string()) fail(key, "is not a string");
    return v->get<std::string>();
  }

  [[nodiscard]] Mat3 matrix(const char* key) const {
    const json* v = find(key, false);
    if (v == nullptr) return Mat3::Constant(kAbsent);
    Mat3 m;
    const bool shaped = v->is_array() && v->size() == 3;
    for (int i = 0; i < 3; ++i) {
      const json* row = shaped ? &(*v)[static_cast<std::size_t>(i)] : nullptr;
      if (row == nullptr || !row->is_array() || row->size() != 3) fail(key, "is not a 3×3 array");
      for (int k = 0; k < 3; ++k) {
        const json& x = (*row)[static_cast<std::size_t>(k)];
        if (!x.is_null() && !x.is_number()) fail(key, "holds something other than numbers");
        m(i, k) = x.is_null() ? kAbsent : x.get<double>();
      }
    }
    return m;
  }

  /// A nested object; an absent one (a schema-0 file) reads as an empty object.
  [[nodiscard]] Fields section(const char* key, bool required = false) const {
    const json* v = find(key, required);
    static const json empty = json::object();
    return {v == nullptr ? empty : *v,
            where_.empty() ? std::string(key) : fmt::format("{}.{}", where_, key)};
  }

 private:
  const json* find(const char* key, bool required) const {
    const auto it = object_.find(key);
    if (it != object_.end() && !it->is_null()) return &*it;
    if (required) fail(key, "is missing");
    return nullptr;
  }

  [[noreturn]] void fail(const char* key, const char* what) const {
    // (formatted, not "." + std::string: GCC 12 warns falsely on that at -O3, -Wrestrict)
    const std::string name = *key == '\0'     ? where_
                             : where_.empty() ? std::string(key)
                                              : fmt::format("{}.{}", where_, key);
    throw SummaryError(fmt::format("summary.json: \"{}\" {}", name.empty() ? "(top)" : name, what));
  }

  const json& object_;
  std::string where_;
};

RunSummary::Stress read_stress(const Fields& s) {
  RunSummary::Stress stress;
  stress.volume = s.number("volume");
  stress.sigma = s.matrix("sigma");
  stress.sigma_compressive = s.matrix("sigma_compressive");
  stress.sigma_tensile = s.matrix("sigma_tensile");
  stress.compressive_contacts = s.count<std::size_t>("compressive_contacts", true);
  stress.tensile_contacts = s.count<std::size_t>("tensile_contacts", true);
  stress.piston_load_per_area = s.number("piston_load_per_area");
  stress.bottom_load_per_area = s.number("bottom_load_per_area");
  stress.sigma_zz_over_pressure = s.number("sigma_zz_over_pressure");
  stress.sigma_zz_compressive_over_pressure = s.number("sigma_zz_compressive_over_pressure");
  stress.sigma_zz_tensile_over_pressure = s.number("sigma_zz_tensile_over_pressure");
  return stress;
}

/// A pass count's field: schema 2 calls the NLGS pass a pass, 0 and 1 a sweep.
const char* pass_field(int schema, const char* passes, const char* sweeps) {
  return schema >= 2 ? passes : sweeps;
}

RunSummary::Accuracy read_accuracy(const Fields& a, int schema) {
  RunSummary::Accuracy accuracy;
  accuracy.mean_overlap = a.number("mean_overlap");
  accuracy.max_overlap = a.number("max_overlap");
  accuracy.max_overlap_during_run = a.number("max_overlap_during_run");
  accuracy.max_net_force = a.number("max_net_force");
  accuracy.max_cohesive_opening_per_range = a.number("max_cohesive_opening_per_range");
  accuracy.last_step_residual = a.number("last_step_residual");
  accuracy.last_step_error_estimate = a.number("last_step_error_estimate");
  accuracy.last_step_converged = a.flag("last_step_converged");
  accuracy.capped_steps = a.count<std::int64_t>("capped_steps", true);
  if (a.has("final_solve")) {
    const Fields f = a.section("final_solve");
    accuracy.final_solve = RunSummary::Accuracy::FinalSolve{
        f.count<int>(pass_field(schema, "passes", "sweeps")), f.flag("converged"),
        f.number("residual"), f.number("error_estimate")};
  }
  return accuracy;
}

RunSummary::Run read_run(const Fields& r, int schema) {
  RunSummary::Run run;
  run.blocked = r.flag("blocked", true);
  run.blocked_by = r.text("blocked_by");
  run.probes = r.count<int>("probes");
  run.probe_passes = r.count<std::int64_t>(pass_field(schema, "probe_passes", "probe_sweeps"));
  run.probe_seconds = r.number("probe_seconds");
  run.unbalanced_rest_solves = r.count<int>("unbalanced_rest_solves");
  run.not_blocked = r.text("not_blocked");  // summaries before it: none
  run.interrupted = r.flag("interrupted", true);
  run.failed = r.flag("failed");  // summaries before faults existed: false
  run.until_blocked = r.flag("until_blocked");
  run.steps = r.count<std::int64_t>("steps", true);
  run.dt_min = r.number("dt_min");
  run.dt_max = r.number("dt_max");
  run.repeated_steps = r.count<std::int64_t>("repeated_steps");
  run.repeated_passes =
      r.count<std::int64_t>(pass_field(schema, "repeated_passes", "repeated_sweeps"));
  run.total_passes =
      r.count<std::int64_t>(pass_field(schema, "total_passes", "total_sweeps"), true);
  run.passes_per_step = r.number(pass_field(schema, "passes_per_step", "sweeps_per_step"));
  run.threaded_steps = r.count<std::int64_t>("threaded_steps");  // summaries before it: 0
  run.wall_seconds = r.number("wall_seconds", true);
  const Fields stages = r.section("stage_seconds");
  for (std::size_t s = 0; s < kStageNames.size(); ++s) {
    run.stage_seconds[s] = stages.number(kStageNames[s]);
  }
  return run;
}

RunFault read_fault(const Fields& f) {
  RunFault fault;
  fault.quantity = f.text("quantity");
  fault.body = f.has("sphere") ? f.count<std::int64_t>("sphere") : -1;
  fault.other = f.has("other_sphere") ? f.count<std::int64_t>("other_sphere") : -1;
  fault.step = f.count<std::int64_t>("step");
  fault.time = f.number("time");
  fault.value = f.number("value");
  fault.message = f.text("message");
  return fault;
}

}  // namespace

RunSummary summarise_run(const Scene& scene, const World& world, const Contacts& contacts,
                         const RunResult& result, double initial_porosity) {
  const StepDiagnostics& d = result.last.diagnostics;
  const Piston& piston = world.walls.piston;
  const double pressure = piston.enabled ? piston.force / world.box.area() : 0.0;

  RunSummary s;
  s.program = this_program();
  s.seed = scene.step.solver.seed;
  s.porosity = porosity(world);
  s.initial_porosity = initial_porosity;
  s.packing_volume = packing_volume(world);
  s.spheres = world.bodies.size();
  s.time = world.time;
  s.piston = {piston.enabled,         piston.height,     piston.velocity,
              piston.force,           pressure,          piston.enabled ? piston_load(world) : 0.0,
              d.piston_contact_force, d.piston_imbalance};
  s.stress = stress_of(world, contacts, s.packing_volume, pressure);
  s.contacts = {d.contacts, d.closed_contacts, d.cohesive_contacts,
                coordination_number(contacts, world.bodies.size())};
  RunSummary::Accuracy& a = s.accuracy;
  a.mean_overlap = d.mean_overlap;
  a.max_overlap = d.max_overlap;
  a.max_overlap_during_run = result.max_overlap_seen;
  a.max_net_force = d.max_net_force;
  a.max_cohesive_opening_per_range = result.max_cohesive_opening_per_range;
  a.last_step_residual = result.last.solver.residual;
  a.last_step_error_estimate = result.last.solver.error_estimate;
  a.last_step_converged = result.last.solver.converged;
  a.capped_steps = result.capped_steps;
  if (result.final_solve) {
    a.final_solve = RunSummary::Accuracy::FinalSolve{
        result.final_solve->passes, result.final_solve->converged, result.final_solve->residual,
        result.final_solve->error_estimate};
  }
  s.kinetic_energy = d.kinetic_energy;
  s.max_speed = d.max_speed;
  s.rms_speed = d.rms_speed;
  s.energy = energy_budget(scene.step.laws, world, contacts, result);
  s.run = run_counts(scene, result);
  s.fault = result.fault;
  s.scene_toml = scene.effective_toml;
  return s;
}

std::string run_summary_json(const RunSummary& s) {
  json j;
  j["schema"] = s.schema;
  j["program"] = program_json(s.program);
  j["seed"] = s.seed;
  j["porosity"] = s.porosity;
  j["initial_porosity"] = s.initial_porosity;
  j["packing_volume"] = s.packing_volume;
  j["spheres"] = s.spheres;
  j["time"] = s.time;
  const RunSummary::PistonState& p = s.piston;
  j["piston"] = {{"enabled", p.enabled},
                 {"height", p.height},
                 {"velocity", p.velocity},
                 {"applied_force", p.applied_force},
                 {"applied_pressure", p.applied_pressure},
                 {"load", p.load},
                 {"contact_force", p.contact_force},
                 {"force_imbalance", p.force_imbalance}};
  const RunSummary::Stress& st = s.stress;
  j["stress"] = {{"volume", st.volume},
                 {"sigma", matrix_json(st.sigma)},
                 {"sigma_compressive", matrix_json(st.sigma_compressive)},
                 {"sigma_tensile", matrix_json(st.sigma_tensile)},
                 {"compressive_contacts", st.compressive_contacts},
                 {"tensile_contacts", st.tensile_contacts},
                 {"piston_load_per_area", st.piston_load_per_area},
                 {"bottom_load_per_area", st.bottom_load_per_area},
                 {"sigma_zz_over_pressure", st.sigma_zz_over_pressure},
                 {"sigma_zz_compressive_over_pressure", st.sigma_zz_compressive_over_pressure},
                 {"sigma_zz_tensile_over_pressure", st.sigma_zz_tensile_over_pressure}};
  j["contacts"] = {{"candidates", s.contacts.candidates},
                   {"closed", s.contacts.closed},
                   {"cohesive", s.contacts.cohesive},
                   {"coordination_number", s.contacts.coordination_number}};
  j["accuracy"] = accuracy_json(s.accuracy);
  j["kinetic_energy"] = s.kinetic_energy;
  j["max_speed"] = s.max_speed;
  j["rms_speed"] = s.rms_speed;
  const RunSummary::Energy& e = s.energy;
  j["energy"] = {{"complete", e.complete},         {"piston_work", e.piston_work},
                 {"gravity_work", e.gravity_work}, {"kinetic_start", e.kinetic_start},
                 {"kinetic_end", e.kinetic_end},   {"cohesive_start", e.cohesive_start},
                 {"cohesive_end", e.cohesive_end}, {"bonds_formed", e.bonds_formed},
                 {"bonds_broken", e.bonds_broken}, {"breaking_work", e.breaking_work},
                 {"dissipated", e.dissipated}};
  j["run"] = run_json(s.run);
  j["fault"] = s.fault ? fault_json(*s.fault) : json(nullptr);
  j["scene"] = scene_json(s.scene_toml);
  j["scene_toml"] = s.scene_toml;
  return j.dump(2) + "\n";
}

RunSummary parse_run_summary(std::string_view json_text) {
  json j;
  try {
    j = json::parse(json_text);
  } catch (const json::parse_error& e) {
    throw SummaryError(fmt::format("summary.json: not JSON ({})", e.what()));
  }
  const Fields top(j, "");
  RunSummary s;
  s.schema = top.count<int>("schema");  // absent: 0
  if (s.schema < 0 || s.schema > kRunSummarySchema) {
    throw SummaryError(fmt::format(
        "summary.json: schema {} is not one this program reads (0 to {}): written by a newer "
        "cdpowder?",
        s.schema, kRunSummarySchema));
  }
  const Fields program = top.section("program", true);
  s.program.name = program.text("name");
  s.program.version = program.text("version");
  s.program.commit = program.text("commit", true);
  s.program.kernel = program.text("kernel");
  s.program.cpu = program.text("cpu");
  s.seed = top.count<std::uint64_t>("seed");
  s.porosity = top.number("porosity", true);
  s.initial_porosity = top.number("initial_porosity");
  s.packing_volume = top.number("packing_volume");
  s.spheres = top.count<std::size_t>("spheres");
  s.time = top.number("time");
  const Fields p = top.section("piston");
  s.piston = {p.flag("enabled"),         p.number("height"),           p.number("velocity"),
              p.number("applied_force"), p.number("applied_pressure"), p.number("load"),
              p.number("contact_force"), p.number("force_imbalance")};
  s.stress = read_stress(top.section("stress", true));
  const Fields c = top.section("contacts");
  s.contacts = {c.count<std::size_t>("candidates"), c.count<std::size_t>("closed"),
                c.count<std::size_t>("cohesive"), c.number("coordination_number")};
  s.accuracy = read_accuracy(top.section("accuracy", true), s.schema);
  s.kinetic_energy = top.number("kinetic_energy");
  s.max_speed = top.number("max_speed");
  s.rms_speed = top.number("rms_speed");
  const Fields e = top.section("energy");
  s.energy = {e.flag("complete"),
              e.number("piston_work"),
              e.number("gravity_work"),
              e.number("kinetic_start"),
              e.number("kinetic_end"),
              e.number("cohesive_start"),
              e.number("cohesive_end"),
              e.count<std::int64_t>("bonds_formed"),
              e.count<std::int64_t>("bonds_broken"),
              e.number("breaking_work"),
              e.number("dissipated")};
  s.run = read_run(top.section("run", true), s.schema);
  if (top.has("fault")) s.fault = read_fault(top.section("fault"));
  s.scene_toml = top.text("scene_toml", true);
  return s;
}

std::optional<RunSummary> read_run_summary(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) return std::nullopt;
  std::ostringstream text;
  text << stream.rdbuf();
  try {
    return parse_run_summary(text.str());
  } catch (const SummaryError&) {
    return std::nullopt;
  }
}

std::string deposit_summary_json(const Scene& scene, const World& world) {
  json j;
  j["schema"] = kRunSummarySchema;
  j["program"] = program_json(this_program());
  j["seed"] = scene.deposition ? scene.deposition->seed : 0;
  j["spheres"] = world.bodies.size();
  j["porosity"] = deposit_porosity(world.bodies, world.box);
  j["height"] = deposit_height(world.bodies);
  j["grain_volume"] = grain_volume(world.bodies);
  j["scene"] = scene_json(scene.effective_toml);
  j["scene_toml"] = scene.effective_toml;
  return j.dump(2) + "\n";
}

}  // namespace cdpowder
