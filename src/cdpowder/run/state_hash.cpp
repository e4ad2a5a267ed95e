// state_hash.cpp — the state file's World and action sections, hashed.
#include "cdpowder/run/state_hash.hpp"

#include "cdpowder/io/byte_stream.hpp"
#include "cdpowder/run/state_file.hpp"

#include <fmt/format.h>

namespace cdpowder {

std::uint64_t state_hash(const World& world, const StepWorkspace& work) {
  NullSink nowhere;  // hashed as written, never held
  ByteWriter bytes(nowhere);
  write_world(bytes, world);
  write_actions(bytes, last_step_actions(work));
  return bytes.checksum();
}

std::string hash_text(std::uint64_t hash) {
  return fmt::format("{:#018x}", hash);
}

}  // namespace cdpowder
