// Tests for src/cdpowder/io/atomic_file.cpp: files appear whole under their final name or not at
// all, and no temporary ('.'-prefixed file in the same folder) is left behind.
#include "cdpowder/io/atomic_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

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
  }
  EXPECT_FALSE(fs::exists(missing));
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(AtomicFile, StreamWithoutCommitLeavesNoFileAndNoTemporary) {
  const fs::path file = dir_ / "timeseries.csv";
  {
    AtomicFileStream out(file);
    out.stream() << "t,z\n0,1\n";
    EXPECT_FALSE(fs::exists(file));  // not under the final name while being written
  }
  EXPECT_FALSE(fs::exists(file));
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(AtomicFile, StreamWithCommitAppearsWithTheStreamedContent) {
  const fs::path file = dir_ / "timeseries.csv";
  {
    AtomicFileStream out(file);
    out.stream() << "t,z\n";
    out.stream() << "0,1\n";
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
    out.stream() << "new content that must never appear\n";
    out.stream().flush();
    EXPECT_EQ(read(file), kContent);  // also untouched while the stream is open
  }
  EXPECT_EQ(read(file), kContent);
  EXPECT_THAT(hidden_files(), ::testing::IsEmpty());
}

}  // namespace
}  // namespace cdpowder
