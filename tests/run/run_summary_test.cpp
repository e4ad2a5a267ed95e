// run_summary_test.cpp — summary.json written and read back field for field, the summaries
// committed under results/ (schema 0, no "schema" key) still read, and every kind of bad file
// gets a message naming the field.
#include "cdpowder/run/run_summary.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <string>

namespace cdpowder {
namespace {

RunSummary example_summary() {
  RunSummary s;
  s.program.version = "9.9.9";
  s.program.commit = "abcdef123456";
  s.program.kernel = "avx2";
  s.program.cpu = "AMD EPYC";
  s.seed = 18446744073709551557ULL;  // beyond 2^53: must not pass through a double
  s.porosity = 0.6430459140388864;
  s.initial_porosity = 0.9273698405723986;
  s.packing_volume = 11910.837345958858;
  s.spheres = 1015;
  s.time = 1234.5;
  s.piston = {true, 19.05, 1.5e-10, 1.5625, 0.0025, 1.5625, 1.5625076, 4.87e-6};
  s.stress.volume = 11910.8;
  s.stress.sigma << 1, 2, 3, 4, 5, 6, 7, 8, 9.5;
  s.stress.sigma_compressive = 2.0 * s.stress.sigma;
  s.stress.sigma_tensile = -s.stress.sigma;
  s.stress.compressive_contacts = 1200;
  s.stress.tensile_contacts = 900;
  s.stress.piston_load_per_area = 0.0025;
  s.stress.bottom_load_per_area = 0.00251;
  s.stress.sigma_zz_over_pressure = 1.0001;
  s.stress.sigma_zz_compressive_over_pressure = 5.3;
  s.stress.sigma_zz_tensile_over_pressure = -4.3;
  s.contacts = {2331, 2264, 2286, 4.35};
  s.accuracy.mean_overlap = 4.6e-7;
  s.accuracy.max_overlap = 1.2e-5;
  s.accuracy.max_overlap_during_run = 1.9e-5;
  s.accuracy.max_net_force = 0.0083;
  s.accuracy.max_cohesive_opening_per_range = 0.0997;
  s.accuracy.last_step_residual = 3.3e-7;
  s.accuracy.last_step_error_estimate = 7.8e-7;
  s.accuracy.last_step_converged = true;
  s.accuracy.capped_steps = 350;
  s.accuracy.final_solve = RunSummary::Accuracy::FinalSolve{1632, true, 3.3e-7, 7.8e-7};
  s.kinetic_energy = 4.8e-9;
  s.max_speed = 2.4e-5;
  s.rms_speed = 1.06e-6;
  s.run.blocked = true;
  s.run.blocked_by = "probe";
  s.run.probes = 1;
  s.run.probe_passes = 1632;
  s.run.probe_seconds = 0.06;
  s.run.until_blocked = true;
  s.run.steps = 28163;
  s.run.dt_min = 0.0037;
  s.run.dt_max = 0.02;
  s.run.repeated_steps = 29;
  s.run.repeated_passes = 2577;
  s.run.total_passes = 1223803;
  s.run.passes_per_step = 43.45;
  s.run.threaded_steps = 27440;
  s.run.wall_seconds = 42.06;
  s.run.stage_seconds = {1.25, 0.97, 37.9, 0.37, 1.24};
  s.scene_toml = "[system]\nlx = 25.0\n";
  return s;
}

TEST(RunSummary, WrittenAndReadBackFieldForField) {
  const RunSummary s = example_summary();
  const std::string text = run_summary_json(s);
  const RunSummary r = parse_run_summary(text);
  EXPECT_EQ(r.schema, kRunSummarySchema);
  EXPECT_EQ(nlohmann::json::parse(text).at("schema"), kRunSummarySchema);
  EXPECT_EQ(r.program.commit, s.program.commit);
  EXPECT_EQ(r.program.kernel, s.program.kernel);
  EXPECT_EQ(r.program.cpu, s.program.cpu);
  EXPECT_EQ(r.seed, s.seed);
  EXPECT_EQ(r.porosity, s.porosity);  // nlohmann writes the shortest round-trip form
  EXPECT_EQ(r.spheres, s.spheres);
  EXPECT_EQ(r.piston.force_imbalance, s.piston.force_imbalance);
  EXPECT_EQ(r.stress.sigma, s.stress.sigma);
  EXPECT_EQ(r.stress.sigma_tensile, s.stress.sigma_tensile);
  EXPECT_EQ(r.stress.tensile_contacts, s.stress.tensile_contacts);
  EXPECT_EQ(r.stress.sigma_zz_tensile_over_pressure, s.stress.sigma_zz_tensile_over_pressure);
  EXPECT_EQ(r.contacts.coordination_number, s.contacts.coordination_number);
  EXPECT_EQ(r.accuracy.capped_steps, s.accuracy.capped_steps);
  ASSERT_TRUE(r.accuracy.final_solve.has_value());
  EXPECT_EQ(r.accuracy.final_solve->passes, 1632);
  EXPECT_EQ(r.run.blocked_by, "probe");
  EXPECT_EQ(r.run.total_passes, s.run.total_passes);
  EXPECT_EQ(r.run.threaded_steps, s.run.threaded_steps);
  EXPECT_EQ(r.run.stage_seconds, s.run.stage_seconds);
  EXPECT_FALSE(r.fault.has_value());
  EXPECT_EQ(r.scene_toml, s.scene_toml);
  // the resolved scene is also there as a JSON object, for tools without a TOML parser
  EXPECT_EQ(nlohmann::json::parse(text).at("scene").at("system").at("lx"), 25.0);
  // and writing what was read gives the same text
  EXPECT_EQ(run_summary_json(r), text);
}

TEST(RunSummary, NumbersNotMeasuredAreNullAndReadAsNaN) {
  RunSummary s = example_summary();
  s.stress.sigma_zz_over_pressure = std::nan("");  // no applied pressure
  s.accuracy.final_solve.reset();
  s.run.blocked = false;
  s.run.blocked_by.clear();
  const std::string text = run_summary_json(s);
  const nlohmann::json j = nlohmann::json::parse(text);
  EXPECT_TRUE(j.at("stress").at("sigma_zz_over_pressure").is_null());
  EXPECT_TRUE(j.at("accuracy").at("final_solve").is_null());
  EXPECT_TRUE(j.at("run").at("blocked_by").is_null());
  const RunSummary r = parse_run_summary(text);
  EXPECT_TRUE(std::isnan(r.stress.sigma_zz_over_pressure));
  EXPECT_FALSE(r.accuracy.final_solve.has_value());
  EXPECT_TRUE(r.run.blocked_by.empty());
}

TEST(RunSummary, AFaultIsWrittenAndRead) {
  RunSummary s = example_summary();
  s.run.failed = true;
  s.fault = RunFault{"overlap", 12, -1, 345, 6.7, 0.25, "sphere 12 overlaps by 0.25 R"};
  const RunSummary r = parse_run_summary(run_summary_json(s));
  ASSERT_TRUE(r.fault.has_value());
  EXPECT_EQ(r.fault->quantity, "overlap");
  EXPECT_EQ(r.fault->body, 12);
  EXPECT_EQ(r.fault->other, -1);  // written as null
  EXPECT_EQ(r.fault->step, 345);
  EXPECT_EQ(r.fault->message, s.fault->message);
  EXPECT_TRUE(r.run.failed);
}

/// Schemas 0 and 1 called the NLGS pass a sweep.
void rename_pass_fields_as_before_schema_2(nlohmann::json& j) {
  nlohmann::json& run = j.at("run");
  for (const auto& [now, before] :
       {std::pair{"total_passes", "total_sweeps"}, std::pair{"passes_per_step", "sweeps_per_step"},
        std::pair{"repeated_passes", "repeated_sweeps"},
        std::pair{"probe_passes", "probe_sweeps"}}) {
    run[before] = run.at(now);
    run.erase(now);
  }
  nlohmann::json& final_solve = j.at("accuracy").at("final_solve");
  if (!final_solve.is_null()) {
    final_solve["sweeps"] = final_solve.at("passes");
    final_solve.erase("passes");
  }
}

TEST(RunSummary, SchemaOneReadsItsSweepsAsPasses) {
  const RunSummary written = example_summary();
  nlohmann::json j = nlohmann::json::parse(run_summary_json(written));
  j["schema"] = 1;
  rename_pass_fields_as_before_schema_2(j);
  const RunSummary r = parse_run_summary(j.dump());
  EXPECT_EQ(r.schema, 1);
  EXPECT_EQ(r.run.total_passes, written.run.total_passes);
  EXPECT_EQ(r.run.passes_per_step, written.run.passes_per_step);
  EXPECT_EQ(r.run.repeated_passes, written.run.repeated_passes);
  EXPECT_EQ(r.run.probe_passes, written.run.probe_passes);
  ASSERT_EQ(r.accuracy.final_solve.has_value(), written.accuracy.final_solve.has_value());
  if (r.accuracy.final_solve) {
    EXPECT_EQ(r.accuracy.final_solve->passes, written.accuracy.final_solve->passes);
  }
}

TEST(RunSummary, SchemaZeroIsAFileWithoutTheKeyAndItsMissingFieldsAreAbsent) {
  nlohmann::json j = nlohmann::json::parse(run_summary_json(example_summary()));
  j.erase("schema");
  j.erase("fault");
  j.at("run").erase("failed");
  j.at("run").erase("dt_min");
  j.at("accuracy").erase("max_cohesive_opening_per_range");
  j.at("program").erase("kernel");
  j.at("program").erase("cpu");
  rename_pass_fields_as_before_schema_2(j);
  const RunSummary r = parse_run_summary(j.dump());
  EXPECT_EQ(r.schema, 0);
  EXPECT_TRUE(r.program.kernel.empty());
  EXPECT_TRUE(r.program.cpu.empty());
  EXPECT_FALSE(r.run.failed);
  EXPECT_TRUE(std::isnan(r.run.dt_min));
  EXPECT_TRUE(std::isnan(r.accuracy.max_cohesive_opening_per_range));
  EXPECT_EQ(r.porosity, example_summary().porosity);
}

TEST(RunSummary, EveryCommittedSummaryStillReads) {
  // the sweeps under results/ were written before the schema existed (and by programs with
  // fewer fields); each must read, or a resumed sweep would rerun it
  const std::filesystem::path results = std::filesystem::path(CDPOWDER_SOURCE_DIR) / "results";
  int read = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(results)) {
    if (entry.path().filename() != "summary.json") continue;
    SCOPED_TRACE(entry.path().string());
    const std::optional<RunSummary> s = read_run_summary(entry.path());
    ASSERT_TRUE(s.has_value());
    EXPECT_LE(s->schema, kRunSummarySchema);
    EXPECT_GT(s->porosity, 0.0);
    EXPECT_LT(s->porosity, 1.0);
    EXPECT_FALSE(s->program.commit.empty());
    EXPECT_FALSE(s->scene_toml.empty());
    ++read;
  }
  EXPECT_GE(read, 313);
}

/// parse_run_summary's message for `text`, "" if it reads.
std::string error_of(const std::string& text) {
  try {
    (void)parse_run_summary(text);
  } catch (const SummaryError& e) {
    return e.what();
  }
  return "";
}

TEST(RunSummary, BadFilesNameWhatIsWrong) {
  const nlohmann::json good = nlohmann::json::parse(run_summary_json(example_summary()));
  EXPECT_NE(error_of("{ not json").find("not JSON"), std::string::npos);

  nlohmann::json newer = good;
  newer["schema"] = kRunSummarySchema + 1;
  EXPECT_NE(error_of(newer.dump()).find("newer cdpowder"), std::string::npos);

  nlohmann::json no_steps = good;
  no_steps.at("run").erase("steps");
  EXPECT_EQ(error_of(no_steps.dump()), "summary.json: \"run.steps\" is missing");

  nlohmann::json text_porosity = good;
  text_porosity["porosity"] = "0.6";
  EXPECT_EQ(error_of(text_porosity.dump()), "summary.json: \"porosity\" is not a number");

  nlohmann::json fractional = good;
  fractional.at("stress")["tensile_contacts"] = 3.5;
  EXPECT_EQ(error_of(fractional.dump()),
            "summary.json: \"stress.tensile_contacts\" is not a whole number");

  nlohmann::json bad_matrix = good;
  bad_matrix.at("stress")["sigma"] = {1, 2, 3};
  EXPECT_EQ(error_of(bad_matrix.dump()), "summary.json: \"stress.sigma\" is not a 3×3 array");

  // a file that does not read is no summary: the sweep runs that run again
  EXPECT_FALSE(read_run_summary(std::filesystem::path(CDPOWDER_SOURCE_DIR) / "no_such_file.json"));
}

}  // namespace
}  // namespace cdpowder
