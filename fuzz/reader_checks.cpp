// reader_checks.cpp — the readers under test and what counts as handling an input well.
#include "reader_checks.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/particles_csv.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/model/bodies.hpp"
#include "cdpowder/study/sweep_plan.hpp"

#include <exception>
#include <filesystem>
#include <new>
#include <vector>

namespace cdpowder::fuzz {

namespace {

// A compaction of 100 spheres as the quick example has it, the base of the --set target.
constexpr std::string_view kScene = R"([system]
lx = 15.0
ly = 15.0

[deposition]
spheres = 100
radius = 1.0
capture_radius = 3.0
seed = 1

[contact]
mu = 0.3
mu_roll = 1.0
mu_twist = 1.0
cohesion_force = 1.0
cohesion_range = 0.01

[piston]
enabled = true
mass = 360.0
pressure = 0.0025

[run]
until_blocked = true
max_duration = 5000.0
)";

constexpr std::string_view kOverride = "contact.mu_roll=0.3";

constexpr std::string_view kParticles = R"(# cdpowder particles
x,y,z,r,vx,vy,vz,wx,wy,wz,fixed
1.5,2.0,1.0,1.0,0,0,0,0,0,0,0
4.0,2.0,1.0,1.0,0.1,0,-0.2,0,0,0.3,0
2.5,4.0,2.5,0.8,0,0,0,0,0,0,1
)";

constexpr std::string_view kSweep = R"(scene = "scene.toml"
seeds = 3
set = ["run.max_duration=100"]

[grid.contact]
mu_roll = [0.0, 0.3, 1.0]
mu_twist = [0.0, 1.0]

[[points]]
contact = { mu_roll = 0.1, mu_twist = 0.1 }
)";

/// The issues of a rejection, each one line of at most kMaxIssueLength characters.
std::string judge(const ConfigError& error) {
  if (error.issues().empty()) return "a ConfigError without an issue";
  for (const ConfigIssue& issue : error.issues()) {
    const std::string text = format(issue);
    if (text.find_first_of("\n\r") != std::string::npos) {
      return "an issue of several lines: " + text.substr(0, 200);
    }
    if (text.size() > kMaxIssueLength) {
      return "an issue of " + std::to_string(text.size()) + " characters: " + text.substr(0, 200);
    }
  }
  return "";
}

void read(Reader reader, std::string_view input) {
  const std::filesystem::path here = ".";  // relative names are resolved, never opened
  switch (reader) {
    case Reader::Scene:
      (void)read_scene_text(input, "fuzz.toml", {}, here);
      return;
    case Reader::SetOverride:
      (void)read_scene_text(kScene, "scene.toml", {std::string(input)}, here);
      return;
    case Reader::ParticlesCsv: {
      Bodies bodies;
      read_particles_csv_text(input, "fuzz.csv", 1.0, bodies);
      return;
    }
    case Reader::SweepFile:
      (void)read_sweep_plan_text(input, "fuzz_sweep.toml", here);
      return;
  }
}

}  // namespace

std::string_view reader_name(Reader reader) {
  switch (reader) {
    case Reader::Scene:
      return "scene";
    case Reader::SetOverride:
      return "--set";
    case Reader::ParticlesCsv:
      return "particles CSV";
    case Reader::SweepFile:
      return "sweep file";
  }
  return "?";
}

std::string_view valid_example(Reader reader) {
  switch (reader) {
    case Reader::Scene:
      return kScene;
    case Reader::SetOverride:
      return kOverride;
    case Reader::ParticlesCsv:
      return kParticles;
    case Reader::SweepFile:
      return kSweep;
  }
  return "";
}

std::string check_reader(Reader reader, std::string_view input) {
  try {
    read(reader, input);
    return "";
  } catch (const ConfigError& error) {
    return judge(error);
  } catch (const std::bad_alloc&) {
    return "std::bad_alloc escaped the reader";
  } catch (const std::exception& error) {
    return std::string("an exception other than ConfigError: ") + error.what();
  }
}

}  // namespace cdpowder::fuzz
