// duration.hpp — a wall-time duration as written on the command line (`cdpowder sweep
// --time-limit 2h30m`): a rule of the command line, not of the library.
#pragma once

#include <optional>
#include <string_view>

namespace cdpowder::app {

/// A duration as people write one on a command line: a number of seconds ("5400"), or
/// numbers with units h, m and s, largest first ("90m", "2.5h", "2h40m", "1h5m30s").
/// nullopt for anything else, for a unit given twice or out of order, and for a negative
/// or non-finite value.
std::optional<double> parse_duration(std::string_view text);

}  // namespace cdpowder::app
