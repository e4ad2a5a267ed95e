// cli_process.hpp — running the cdpowder program as a user would, for the CLI tests:
// a process with its exit status, stdout and stderr, and a scratch folder per test.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace cdpowder::testing {

struct ProcessResult {
  int status = 0;
  std::string out;
  std::string err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs `program arguments` through the shell, capturing stdout and stderr in `scratch`.
inline ProcessResult run_process(const std::string& program, const std::string& arguments,
                                 const std::filesystem::path& scratch) {
  const std::filesystem::path out = scratch / "stdout.txt";
  const std::filesystem::path err = scratch / "stderr.txt";
  const std::string command =
      program + " " + arguments + " >" + out.string() + " 2>" + err.string();
  const int raw = std::system(command.c_str());
  return {WEXITSTATUS(raw), slurp(out), slurp(err)};
}

#ifdef CDPOWDER_EXE
/// Runs the cdpowder program built with the tests (CDPOWDER_EXE, set by CMake for the CLI
/// tests) with `arguments`.
inline ProcessResult run_cdpowder(const std::string& arguments,
                                  const std::filesystem::path& scratch) {
  return run_process(CDPOWDER_EXE, arguments, scratch);
}
#endif

/// A fresh, empty scratch folder named after the running test, removed afterwards.
class ScratchFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // the process id keeps two test runs apart (two build trees tested at once shared a
    // folder, and one's clean-up deleted the other's outputs mid-run)
    scratch_ = std::filesystem::temp_directory_path() /
               ("cdpowder_cli_" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
                std::to_string(::getpid()));
    std::filesystem::remove_all(scratch_);
    std::filesystem::create_directories(scratch_);
  }

  void TearDown() override { std::filesystem::remove_all(scratch_); }

  std::filesystem::path scratch_;
};

}  // namespace cdpowder::testing
