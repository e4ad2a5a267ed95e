// output_sink.hpp — where an output's text or bytes go as they are made: a file being written
// (AtomicFileStream, atomic_file.hpp), a string (tests, small documents) or nowhere (a hash of
// the bytes, byte_stream.hpp). Writers hand over their output in pieces of about
// kOutputChunkBytes, so a file of 10⁶ spheres is never held whole in memory beside the state
// it is made from (docs/architecture.md, "State and outputs at scale").
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace cdpowder {

/// Bytes a writer gathers before it hands them to its sink.
inline constexpr std::size_t kOutputChunkBytes = std::size_t{64} * 1024;

class OutputSink {
 public:
  /// Takes the next bytes of the output.
  virtual void write(std::string_view bytes) = 0;

 protected:
  OutputSink() = default;
  ~OutputSink() = default;
  OutputSink(const OutputSink&) = default;
  OutputSink(OutputSink&&) = default;
  OutputSink& operator=(const OutputSink&) = default;
  OutputSink& operator=(OutputSink&&) = default;
};

/// Appends the output to a string.
class StringSink final : public OutputSink {
 public:
  explicit StringSink(std::string& out) : out_(&out) {}

  void write(std::string_view bytes) override { out_->append(bytes); }

 private:
  std::string* out_;
};

/// What `write(sink)` writes, as a string (the string forms of the writers).
template <typename Write>
std::string written_text(const Write& write) {
  std::string text;
  StringSink sink(text);
  write(static_cast<OutputSink&>(sink));
  return text;
}

/// Drops the output (a ByteWriter that only hashes).
class NullSink final : public OutputSink {
 public:
  void write(std::string_view /*bytes*/) override {}
};

/// A writer's text, gathered in a string and handed to the sink in chunks of about
/// kOutputChunkBytes: append to text(), call chunk_done() after each record, finish() at the
/// end.
class ChunkedText {
 public:
  explicit ChunkedText(OutputSink& sink) : sink_(&sink) { text_.reserve(2 * kOutputChunkBytes); }

  ChunkedText(const ChunkedText&) = delete;
  ChunkedText(ChunkedText&&) = delete;
  ChunkedText& operator=(const ChunkedText&) = delete;
  ChunkedText& operator=(ChunkedText&&) = delete;
  ~ChunkedText() = default;

  [[nodiscard]] std::string& text() { return text_; }

  /// Hands the text over once a chunk has gathered.
  void chunk_done() {
    if (text_.size() >= kOutputChunkBytes) finish();
  }

  /// Hands over what is left.
  void finish() {
    if (!text_.empty()) sink_->write(text_);
    text_.clear();
  }

 private:
  OutputSink* sink_;
  std::string text_;
};

}  // namespace cdpowder
