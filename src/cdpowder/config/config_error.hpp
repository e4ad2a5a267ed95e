// config_error.hpp — bad input (style guide 3.7): one ConfigIssue per mistake, formatted as
// `file:line:column: key: message`, and the ConfigError that carries all issues of a read
// at once. Also the "did you mean" suggestion shared by the scene and particle readers.
// app/main.cpp turns a ConfigError into its text and exit code 2.
#pragma once

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace cdpowder {

/// One mistake in the input. line/column are 1-based; 0 means unknown or not applicable.
struct ConfigIssue {
  std::string file;     ///< the file, or "--set" for a command-line override
  int line = 0;         ///< line in `file`, 0 if none
  int column = 0;       ///< column in `line`, 0 if none
  std::string key;      ///< dotted config key or CSV column name; may be empty
  std::string message;  ///< what was found and what is allowed
};

/// `text` on one line: line breaks, tabs and other control characters written as escapes
/// (\n, \r, \t, \xNN). Input echoed in a message (a TOML parser's excerpt, an override)
/// may hold them.
inline std::string one_line(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7F) {
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      constexpr std::string_view kHex = "0123456789abcdef";
      out += "\\x";
      out += kHex[byte >> 4U];
      out += kHex[byte & 0xFU];
    }
  }
  return out;
}

/// Longest key an issue shows: the longest of the scene's keys is 28 characters, an unknown
/// key from the input is cut (as `shown` cuts).
inline constexpr std::size_t kMaxShownKey = 60;

inline std::string shown(std::string_view text, std::size_t max_length);

/// `file:line:column: key: message`; line and column are left out when 0, file and key when
/// empty.
/// Always one line: the key is cut to kMaxShownKey characters and control characters in key
/// and message are escaped.
inline std::string format(const ConfigIssue& issue) {
  std::string text = issue.file;
  if (issue.line > 0) {
    text += ':' + std::to_string(issue.line);
    if (issue.column > 0) {
      text += ':' + std::to_string(issue.column);
    }
  }
  if (!text.empty()) text += ": ";  // an empty file name is said by the message
  if (!issue.key.empty()) {
    text += one_line(shown(issue.key, kMaxShownKey)) + ": ";
  }
  return text + one_line(issue.message);
}

/// Every issue of one read; what() is all of them, one per line.
class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(std::vector<ConfigIssue> issues)
      : std::runtime_error(join(issues)), issues_(std::move(issues)) {}

  [[nodiscard]] const std::vector<ConfigIssue>& issues() const { return issues_; }

 private:
  static std::string join(const std::vector<ConfigIssue>& issues) {
    std::string text;
    for (const ConfigIssue& issue : issues) {
      if (!text.empty()) {
        text += '\n';
      }
      text += format(issue);
    }
    return text;
  }

  std::vector<ConfigIssue> issues_;
};

/// Text from the input as a message shows it: on one line (one_line), at most `max_length`
/// characters (40 unless said; cut at a UTF-8 character boundary), longer text followed by
/// its length. Measured before: a 20 MB field was echoed whole.
inline std::string shown(std::string_view text, std::size_t max_length) {
  // escaped first (one_line), so a run of control characters cannot make it long again
  std::string escaped = one_line(text);
  if (escaped.size() <= max_length) return escaped;
  std::size_t cut = max_length;
  while (cut > 0 && (static_cast<unsigned char>(escaped[cut]) & 0xC0U) == 0x80U) --cut;
  return escaped.substr(0, cut) + "… (" + std::to_string(text.size()) + " characters)";
}

inline std::string shown(std::string_view text) {
  constexpr std::size_t kMax = 40;
  return shown(text, kMax);
}

/// Levenshtein distance between two names (used only on short key names).
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) {
    row[j] = j;
  }
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// "; did you mean 'x'?" for the first known name closest to `name` within edit distance 2,
/// or "" when none is that close. A typo must never fall back silently to a default.
inline std::string did_you_mean(std::string_view name, const std::vector<std::string>& known) {
  constexpr std::size_t kMaxDistance = 2;
  const std::string* best = nullptr;
  std::size_t best_distance = kMaxDistance + 1;
  for (const std::string& candidate : known) {
    const std::size_t distance = edit_distance(name, candidate);
    if (distance < best_distance) {
      best = &candidate;
      best_distance = distance;
    }
  }
  return best != nullptr ? "; did you mean '" + *best + "'?" : std::string();
}

}  // namespace cdpowder
