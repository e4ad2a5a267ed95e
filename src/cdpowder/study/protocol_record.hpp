// protocol_record.hpp — protocol.json: what a run of a sweep's Python protocol leaves once its
// function has returned (python/cdpowder/protocol.py writes it; docs/sweeps.md, "A Python
// protocol"). The engine's summary.json in the same folder holds the results; this record
// says which protocol ran and for which point's scene, since the protocol may change the
// scene as it goes (a load raised in steps) and the summary then names the last one.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace cdpowder {

inline constexpr std::string_view kProtocolRecordFile = "protocol.json";

struct ProtocolRecord {
  std::string protocol;    ///< "FILE:FUNCTION" as the sweep file names it
  std::string scene_toml;  ///< the point's resolved scene, which the function was given
};

/// The record in `folder`; nullopt when there is none or it is not a complete record (it is
/// written atomically, after the function returned).
std::optional<ProtocolRecord> read_protocol_record(const std::filesystem::path& folder);

}  // namespace cdpowder
