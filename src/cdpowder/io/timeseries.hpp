// timeseries.hpp — timeseries.csv, one row every K steps or every Δ of time, written while the run
// goes on and renamed into place when it ends (a killed run leaves no half file under that name).
#pragma once

#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/cadence.hpp"
#include "cdpowder/solver/step.hpp"

#include <filesystem>
#include <string>

namespace cdpowder {

class TimeseriesWriter {
 public:
  TimeseriesWriter(const std::filesystem::path& path, const std::string& header, Cadence cadence);

  /// Writes a row if the cadence says one is due (or `force`), at most one per step.
  void record(const World& world, const StepReport& report, bool force = false);

  /// Whether a row could not be written, and why (the run goes on; commit() throws it).
  [[nodiscard]] bool failed() const { return file_.failed(); }

  [[nodiscard]] const std::string& error() const { return file_.error(); }

  void commit() { file_.commit(); }

 private:
  AtomicFileStream file_;
  Cadence cadence_;
  std::int64_t last_step_ = -1;
};

}  // namespace cdpowder
