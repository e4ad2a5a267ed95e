// reader_checks.hpp — one input through one reader of user input (a scene's TOML, a --set
// override, a particles CSV, a sweep file), judged as the command line would see it: accepted,
// or rejected with a ConfigError whose every issue is one line of at most kMaxIssueLength
// characters. Anything else is a bug: another exception escaping the reader (returned as a
// finding) or a crash or sanitizer report (the process dies). Used by the seeded mutation
// test of the default test run (tests/config/reader_mutation_test.cpp) and by the libFuzzer
// targets of the `fuzz` preset (docs/testing.md, "Fuzzing the readers").
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

namespace cdpowder::fuzz {

enum class Reader { Scene, SetOverride, ParticlesCsv, SweepFile };

inline constexpr std::array<Reader, 4> kReaders = {Reader::Scene, Reader::SetOverride,
                                                   Reader::ParticlesCsv, Reader::SweepFile};

/// An issue longer than this has echoed input without bound (inputs are echoed escaped and
/// cut to 40 characters, keys to 60, a parser's excerpt to 100: config_error.hpp `shown`;
/// the longest bounded message, a malformed override's, reaches ≈ 340).
inline constexpr std::size_t kMaxIssueLength = 400;

[[nodiscard]] std::string_view reader_name(Reader reader);

/// A valid input of each reader, a start for mutations.
[[nodiscard]] std::string_view valid_example(Reader reader);

/// "" when `reader` handled `input` well (accepted, or rejected with one-line issues), else
/// what went wrong.
[[nodiscard]] std::string check_reader(Reader reader, std::string_view input);

}  // namespace cdpowder::fuzz
