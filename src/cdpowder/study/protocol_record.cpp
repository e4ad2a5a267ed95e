// protocol_record.cpp — protocol.json read with nlohmann::json (protocol_record.hpp).
#include "cdpowder/study/protocol_record.hpp"

#include <nlohmann/json.hpp>

#include <fstream>

namespace cdpowder {

std::optional<ProtocolRecord> read_protocol_record(const std::filesystem::path& folder) {
  std::ifstream in(folder / kProtocolRecordFile, std::ios::binary);
  if (!in) return std::nullopt;
  const nlohmann::json record = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!record.is_object()) return std::nullopt;
  const auto protocol = record.find("protocol");
  const auto scene = record.find("scene");
  if (protocol == record.end() || !protocol->is_string() || scene == record.end() ||
      !scene->is_string()) {
    return std::nullopt;
  }
  return ProtocolRecord{protocol->get<std::string>(), scene->get<std::string>()};
}

}  // namespace cdpowder
