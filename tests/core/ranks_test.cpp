// ranks_test.cpp — a program not started by an MPI launcher is one rank, and the collectives
// of core/ranks.hpp are then what one rank's would be (the job of several ranks is tested
// under mpirun by tests/parallel/same_bits_ranks_test.py).
#include "cdpowder/core/ranks.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <stdexcept>
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

}  // namespace
}  // namespace cdpowder
