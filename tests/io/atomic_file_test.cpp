// Tests for src/cdpowder/io/atomic_file.cpp: files appear whole under their final name or not at
// all, and no temporary ('.'-prefixed file in the same folder) is left behind.
#include "cdpowder/io/atomic_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

// getrlimit and setrlimit are POSIX
#include <sys/resource.h>

namespace cdpowder {
namespace {

using ::testing::HasSubstr;
using namespace std::string_view_literals;
namespace fs = std::filesystem;

/// A fresh folder for the files of one test, removed at its end.
class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("cdpowder_atomic_file_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
  }

  void TearDown() override { fs::remove_all(dir_); }

  /// The whole file as bytes.
  static std::string read(const fs::path& file) {
    std::ifstream stream(file, std::ios::binary);
    std::ostringstream text;
    text << stream.rdbuf();
    return text.str();
  }

  /// Names in `dir_` that start with '.': the temporaries of atomic_file.
  [[nodiscard]] std::vector<std::string> hidden_files() const {
    std::vector<std::string> names;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      if (name.starts_with('.')) {
        names.push_back(name);
      }
    }
    return names;
  }

  fs::path dir_;
};

// Binary content with a NUL, a CR LF and no final newline: written byte for byte.
constexpr std::string_view kContent = "a,b\r\n1,2\n\0tail"sv;

TEST_F(AtomicFile, WriteCreatesFileWithExactContentAndNoTemporary) {
  const fs::path file = dir_ / "summary.json";
  write_file_atomically(file, kContent);
  EXPECT_EQ(read(file), kContent);
  EXPECT_THAT(hidden_files(), ::testing::IsEmpty());
}

TEST_F(AtomicFile, OverwriteReplacesTheOldContentWhole) {
  const fs::path file = dir_ / "particles.csv";
  write_file_atomically(file, std::string(1000, 'x'));
  write_file_atomically(file, "short\n");
  EXPECT_EQ(read(file), "short\n");  // no tail of the longer old content
  EXPECT_THAT(hidden_files(), ::testing::IsEmpty());
}

TEST_F(AtomicFile, WriteIntoMissingFolderThrowsNamingThePathAndCreatesNothing) {
  const fs::path missing = dir_ / "no_such_folder";
  const fs::path file = missing / "out.csv";
  try {
    write_file_atomically(file, kContent);
    FAIL() << "no exception writing into a missing folder";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr(file.string()));
    EXPECT_THAT(error.what(), HasSubstr("No such file or directory"));
  }
  EXPECT_FALSE(fs::exists(missing));
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(AtomicFile, StreamWithoutCommitLeavesNoFileAndNoTemporary) {
  const fs::path file = dir_ / "timeseries.csv";
  {
    AtomicFileStream out(file);
    out.write("t,z\n0,1\n");
    EXPECT_FALSE(fs::exists(file));  // not under the final name while being written
  }
  EXPECT_FALSE(fs::exists(file));
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(AtomicFile, StreamWithCommitAppearsWithTheStreamedContent) {
  const fs::path file = dir_ / "timeseries.csv";
  {
    AtomicFileStream out(file);
    out.write("t,z\n");
    out.write("0,1\n");
    out.commit();
  }
  EXPECT_EQ(read(file), "t,z\n0,1\n");
  EXPECT_THAT(hidden_files(), ::testing::IsEmpty());
}

TEST_F(AtomicFile, StreamDestroyedWithoutCommitLeavesPreviousFileUntouched) {
  const fs::path file = dir_ / "timeseries.csv";
  write_file_atomically(file, kContent);
  {
    AtomicFileStream out(file);
    out.write("new content that must never appear\n");
    EXPECT_EQ(read(file), kContent);  // also untouched while the stream is open
  }
  EXPECT_EQ(read(file), kContent);
  EXPECT_THAT(hidden_files(), ::testing::IsEmpty());
}

// A file written through a sink by a writer (the outputs at scale): the bytes as written, one
// write far above the stream's buffer included; a writer that throws leaves no file.
TEST_F(AtomicFile, AFileFilledThroughItsSinkHoldsWhatWasWritten) {
  const fs::path file = dir_ / "particles.csv";
  const std::string large(3 * kOutputChunkBytes + 17, 'x');
  write_file_atomically(file, [&](OutputSink& sink) {
    sink.write("head\n");
    sink.write(large);
    sink.write("tail\n");
  });
  EXPECT_EQ(read(file), "head\n" + large + "tail\n");
  EXPECT_THAT(hidden_files(), ::testing::IsEmpty());

  const fs::path broken = dir_ / "contacts.csv";
  EXPECT_THROW(write_file_atomically(broken,
                                     [&](OutputSink& sink) {
                                       sink.write("half a file");
                                       throw std::runtime_error("the writer failed");
                                     }),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(broken));
  EXPECT_THAT(hidden_files(), ::testing::IsEmpty());
}

// The rename's own reason (once the cleanup's error code overwrote it: "…: Success")
TEST_F(AtomicFile, AFailedRenameReportsItsReasonAndLeavesNoTemporary) {
  const fs::path target = dir_ / "summary.json";
  fs::create_directories(target / "occupied");  // a non-empty folder cannot be replaced
  try {
    write_file_atomically(target, kContent);
    FAIL() << "no exception renaming over a folder";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr("cannot write " + target.string()));
    EXPECT_THAT(error.what(), ::testing::Not(HasSubstr("Success")));
  }
  EXPECT_THAT(hidden_files(), ::testing::IsEmpty());
}

// A write that fails in the middle of a run (a full disk; here the file-size limit, which
// fails the same write(2) with EFBIG) is remembered with its reason, later writes are
// dropped, and commit() throws it and leaves no file.
TEST_F(AtomicFile, AStreamThatCannotWriteSaysWhyAndCommitsNothing) {
  rlimit before{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &before), 0);
  const auto previous_handler = signal(SIGXFSZ, SIG_IGN);  // EFBIG instead of the signal
  rlimit small = before;
  small.rlim_cur = rlim_t{100} * 1024;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const fs::path file = dir_ / "timeseries.csv";
  {
    AtomicFileStream out(file);
    const std::string row(1000, 'r');
    for (int k = 0; k < 300 && !out.failed(); ++k) out.write(row);
    EXPECT_TRUE(out.failed());
    EXPECT_THAT(out.error(), HasSubstr("cannot write " + file.string() + ": File too large"));
    out.write(row);  // dropped, no second error
    EXPECT_THAT(out.error(), HasSubstr("File too large"));
    EXPECT_THROW(out.commit(), std::runtime_error);
  }
  setrlimit(RLIMIT_FSIZE, &before);
  signal(SIGXFSZ, previous_handler);
  EXPECT_FALSE(fs::exists(file));
  EXPECT_THAT(hidden_files(), ::testing::IsEmpty());
}

}  // namespace
}  // namespace cdpowder
