// fuzz_reader.cpp — a libFuzzer target: one reader (CDPOWDER_FUZZ_READER, the index into
// kReaders: 0 scene, 1 --set, 2 particles CSV, 3 sweep file) on the fuzzer's inputs. A
// finding of check_reader aborts, so libFuzzer keeps the input that caused it.
#include "reader_checks.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using cdpowder::fuzz::kReaders;
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::string finding = cdpowder::fuzz::check_reader(kReaders[CDPOWDER_FUZZ_READER], input);
  if (!finding.empty()) {
    std::fprintf(stderr, "%s reader: %s\n",
                 std::string(cdpowder::fuzz::reader_name(kReaders[CDPOWDER_FUZZ_READER])).c_str(),
                 finding.c_str());
    std::abort();
  }
  return 0;
}
