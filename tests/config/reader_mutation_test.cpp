// The readers of user input (scene TOML, --set override, particles CSV, sweep file) under
// seeded random inputs: mutations of a valid input of each reader. None may crash, trip a
// sanitizer (the ci-sanitize run), let an exception other than ConfigError escape, or answer
// with an issue longer than one line (fuzz/reader_checks.hpp). The libFuzzer targets of the
// `fuzz` preset run the same checks on inputs of their own choosing (docs/testing.md).
#include "reader_checks.hpp"

#include "cdpowder/config/config_error.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>

namespace cdpowder::fuzz {
namespace {

/// Pieces a mutation inserts or puts in place of a byte: the syntax of the three formats,
/// numbers at and beyond the edges of double and int64, names of keys and sections, a byte
/// order mark, control bytes and a long run.
constexpr std::array<std::string_view, 44> kPieces = {
    "=",
    "\"",
    "'",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    ",",
    ".",
    "\n",
    "\r\n",
    "#",
    "\t",
    " ",
    "-",
    "e",
    "1e309",
    "-1e309",
    "nan",
    "inf",
    "-0",
    "0x10",
    "99999999999999999999999",
    "1e-320",
    R"(""")",
    "true",
    "\xEF\xBB\xBF",
    std::string_view("\0", 1),
    "\xFF\xFE",
    "contact.mu_roll",
    "solver.dt",
    "deposition.spheres",
    "system.lx",
    "[grid.contact]",
    "[[points]]",
    "set",
    "seeds",
    "scene",
    "x,y,z,r",
    "fixed",
    "1,2,3,4",
    "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
    "a"
    "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
    "a"};

/// 1 to 4 random edits of `text`: a byte replaced, a piece inserted or put in place of a byte, a
/// range deleted or doubled, the text cut short. std::mt19937_64's raw output only (its
/// sequence is fixed by the standard), so every platform mutates alike.
std::string mutate(std::string text, std::mt19937_64& random) {
  const auto below = [&](std::size_t n) { return n == 0 ? 0 : random() % n; };
  const std::size_t edits = 1 + below(4);
  for (std::size_t e = 0; e < edits; ++e) {
    const std::size_t at = below(text.size() + 1);
    const std::string_view piece = kPieces[below(kPieces.size())];
    switch (below(6)) {
      case 0:
        if (at < text.size()) text[at] = static_cast<char>(below(256));
        break;
      case 1:
        text.insert(at, piece);
        break;
      case 2:
        if (at < text.size()) text.replace(at, 1, piece);
        break;
      case 3:
        text.erase(at, 1 + below(16));
        break;
      case 4:
        text.insert(at, text.substr(at, 1 + below(32)));
        break;
      default:
        text.resize(at);
        break;
    }
  }
  return text;
}

/// The input as a failure message shows it: escaped, at most 300 characters.
std::string printable(std::string_view input) {
  constexpr std::size_t kShown = 300;
  return one_line(input.substr(0, kShown));
}

constexpr int kInputsPerReader = 3000;

TEST(ReaderMutation, TheValidExamplesAreAccepted) {
  for (const Reader reader : kReaders) {
    EXPECT_EQ(check_reader(reader, valid_example(reader)), "") << reader_name(reader);
  }
}

// What libFuzzer found after the mutation test passed (the `fuzz` preset, 2026-11-25): an
// override whose value holds 40 NUL bytes, echoed cut to 40 characters and then escaped to 160.
TEST(ReaderMutation, TheFuzzersFindingsStayFixed) {
  const std::string nul_run = "l=\"s=al" + std::string(40, '\0') + "lrunar\"";
  EXPECT_EQ(check_reader(Reader::SetOverride, nul_run), "");
  // the echo is escaped before it is cut: 100 NUL bytes show as 40 characters and a length
  std::string ten_escapes;
  for (int i = 0; i < 10; ++i) ten_escapes += "\\x00";
  EXPECT_EQ(shown(std::string(100, '\0')), ten_escapes + "… (100 characters)");
}

TEST(ReaderMutation, EveryMutatedInputIsAcceptedOrRejectedWithOneLineIssues) {
  for (const Reader reader : kReaders) {
    std::mt19937_64 random(0x5eed0000U + static_cast<std::uint64_t>(reader));
    int failures = 0;
    for (int i = 0; i < kInputsPerReader && failures < 5; ++i) {
      const std::string input = mutate(std::string(valid_example(reader)), random);
      const std::string finding = check_reader(reader, input);
      if (!finding.empty()) {
        ++failures;
        ADD_FAILURE() << reader_name(reader) << " input " << i << ": " << finding
                      << "\ninput: " << printable(input);
      }
    }
  }
}

}  // namespace
}  // namespace cdpowder::fuzz
