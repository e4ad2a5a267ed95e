// ranks_test.cpp — a program not started by an MPI launcher is one rank, and the collectives
// of core/ranks.hpp are then what one rank's would be (the job of several ranks is tested
// under mpirun by tests/parallel/same_bits_ranks_test.py).
#include "cdpowder/core/ranks.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace cdpowder {
namespace {

TEST(Ranks, WithoutALauncherTheProgramIsRankZeroOfOne) {
  EXPECT_EQ(rank_count(), 1);
  EXPECT_EQ(this_rank(), 0);
  EXPECT_TRUE(any_rank(true));
  EXPECT_FALSE(any_rank(false));
}

TEST(Ranks, AGatherOfOneRankCopiesItsBytes) {
  std::array<std::byte, 3> mine{std::byte{1}, std::byte{2}, std::byte{3}};
  std::array<std::byte, 3> all{};
  const std::array<int, 1> counts{3};
  gather_from_all_ranks(mine, all, counts);
  EXPECT_EQ(all, mine);
}

TEST(Ranks, OneRankHasNobodyToExchangeWith) {
  EXPECT_NO_THROW(exchange_with_ranks({}, {}, 0));
  std::array<std::byte, 1> byte{};
  const std::array<RankBytes, 1> message{RankBytes{0, byte}};
  EXPECT_THROW(exchange_with_ranks(message, {}, 0), std::logic_error);
}

/// Sets an environment variable for one scope and puts back what was there.
class ScopedVariable {
 public:
  ScopedVariable(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value, 1);
  }

  ~ScopedVariable() {
    if (old_) {
      ::setenv(name_, old_->c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }

  ScopedVariable(const ScopedVariable&) = delete;
  ScopedVariable& operator=(const ScopedVariable&) = delete;
  ScopedVariable(ScopedVariable&&) = delete;
  ScopedVariable& operator=(ScopedVariable&&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(Ranks, SrunWithoutAnMpiPluginIsRefusedNamingThePlugin) {
  // srun --mpi=none -n 2 sets the step's task count and none of the launchers' variables:
  // each copy would run the whole job into the same folder
  const ScopedVariable tasks("SLURM_STEP_NUM_TASKS", "2");
  const std::string why = copies_without_ranks();
  if (ranks_built()) {
    EXPECT_NE(why.find("srun started 2 copies of cdpowder without an MPI plugin"),
              std::string::npos)
        << why;
    EXPECT_NE(why.find("--mpi=pmix"), std::string::npos) << why;
  } else {
    EXPECT_NE(why.find("built without MPI"), std::string::npos) << why;
  }
}

TEST(Ranks, ASlurmStepOfOneTaskRunsAsOneRank) {
  // srun -n 1 (or sbatch's batch step): one process, no launcher needed
  const ScopedVariable tasks("SLURM_STEP_NUM_TASKS", "1");
  EXPECT_EQ(copies_without_ranks(), "");
}

}  // namespace
}  // namespace cdpowder
