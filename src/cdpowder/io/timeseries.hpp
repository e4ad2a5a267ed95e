// timeseries.hpp — timeseries.csv, one row every K steps, written while the run goes on
// and renamed into place when it ends (a killed run leaves no half file under that name).
#pragma once

#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/solver/step.hpp"

#include <filesystem>
#include <string>

namespace cdpowder {

class TimeseriesWriter {
 public:
  TimeseriesWriter(const std::filesystem::path& path, const std::string& header, int every);

  /// Writes a row if the step index is a multiple of `every` (or `force`).
  void record(const World& world, const StepReport& report, bool force = false);

  void commit() { file_.commit(); }

 private:
  AtomicFileStream file_;
  int every_;
  std::int64_t last_step_ = -1;
};

}  // namespace cdpowder
