// timeseries.hpp — timeseries.csv, one row every K steps or every Δ of time, written while the run
// goes on and renamed into place when it ends (a killed run leaves no half file under that name).
#pragma once

#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/cadence.hpp"
#include "cdpowder/solver/step.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace cdpowder {

/// Where the time series of an earlier process is cut for a run continued from the
/// checkpoint after step `step`: its header and its rows of earlier steps are kept (a row
/// of the checkpoint's own step is written again only if the cadence says so, so the forced
/// last row of an interrupted run goes; rows after it, of a run killed later, go too).
struct TimeseriesCut {
  std::uintmax_t bytes = 0;             ///< length of what is kept
  std::int64_t rows = 0;                ///< data rows kept
  std::optional<double> last_row_time;  ///< time of the last row kept [t0]
  bool has_header = false;              ///< the column names line was found
  /// a whole line that is neither a comment, the column names nor a row (an edited or
  /// damaged file): its number (from 1) and text; the cut ends before it
  int bad_line = 0;
  std::string bad_text;
};

/// Reads `file` (a time series as TimeseriesWriter writes it) up to the first row of step
/// `step` or later, a line cut short (a process killed while writing) or a line that is not
/// a row (named in bad_line: the caller refuses it, rather than dropping the rows after it).
/// Throws std::runtime_error when the file cannot be read.
TimeseriesCut cut_timeseries(const std::filesystem::path& file, std::int64_t step);

class TimeseriesWriter {
 public:
  TimeseriesWriter(const std::filesystem::path& path, const std::string& header, Cadence cadence);

  /// Continues an earlier process's time series `existing` (its temporary or final file) cut
  /// as `cut` says (cut_timeseries), with the cadence going on from the last row kept.
  TimeseriesWriter(const std::filesystem::path& path, const std::filesystem::path& existing,
                   const TimeseriesCut& cut, Cadence cadence);

  /// Writes a row if the cadence says one is due (or `force`), at most one per step.
  void record(const World& world, const StepReport& report, bool force = false);

  /// Whether a row could not be written, and why (the run goes on; commit() throws it).
  [[nodiscard]] bool failed() const { return file_.failed(); }

  [[nodiscard]] const std::string& error() const { return file_.error(); }

  void commit() { file_.commit(); }

  /// Writes the buffered rows to the file now (before a checkpoint).
  void flush() { file_.flush(); }

  /// The file's name until commit().
  [[nodiscard]] const std::filesystem::path& temporary() const { return file_.temporary(); }

 private:
  AtomicFileStream file_;
  Cadence cadence_;
  std::int64_t last_step_ = -1;
};

}  // namespace cdpowder
