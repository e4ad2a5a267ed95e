// Tests for src/cdpowder/core/pieces.hpp: the cuts of a range into pieces cover every index
// once, in order, on a runner or on the caller, in the chunk asked for; run_pieces_in hands
// them out in the order given; pieces_of keeps to its bounds; half_of's first half is the
// shorter. And the counting sort in pieces of solver/nlgs/group_by_part.hpp.
#include "cdpowder/core/pieces.hpp"

#include "cdpowder/solver/nlgs/group_by_part.hpp"
#include "cdpowder/solver/nlgs/tile_threads.hpp"
#include "support/backward_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cdpowder {
namespace {

TEST(Pieces, RunChunksVisitsEveryIndexOnceOnAnyRunner) {
  TileThreads two(2);
  TileThreads three(3);
  for (PieceRunner* runner : {static_cast<PieceRunner*>(nullptr), static_cast<PieceRunner*>(&two),
                              static_cast<PieceRunner*>(&three)}) {
    for (const std::size_t count : {std::size_t{0}, std::size_t{1}, kChunkIndices,
                                    kChunkIndices + 1, 5 * kChunkIndices + 17}) {
      std::vector<int> visits(count, 0);
      run_chunks(runner, count, [&](std::size_t first, std::size_t last) {
        ASSERT_LE(first, last);
        ASSERT_LE(last, count);
        // a piece is a chunk, or the whole range on the caller
        if (runner != nullptr && count > kChunkIndices) {
          EXPECT_EQ(first % kChunkIndices, 0U);
          EXPECT_LE(last - first, kChunkIndices);
        }
        for (std::size_t i = first; i < last; ++i) ++visits[i];
      });
      for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(visits[i], 1) << i << " of " << count;
    }
  }
}

/// Runs the pieces one after the other, in the order it is handed them.
class RecordingRunner final : public PieceRunner {
 public:
  void run_pieces(std::uint32_t pieces, Task task, const void* context) override {
    for (std::uint32_t p = 0; p < pieces; ++p) task(context, p);
  }
};

// run_pieces_in hands a runner the pieces in the order given (the rest after it, in their own
// order) and runs them on the caller in piece order; every piece once either way.
TEST(Pieces, RunPiecesInHandsThePiecesOutInTheOrderGiven) {
  RecordingRunner recording;
  TileThreads three(3);
  const std::vector<std::uint32_t> order{3, 0, 2, 1};
  std::vector<std::uint32_t> handed;
  run_pieces_in(&recording, order, 6, [&](std::uint32_t p) { handed.push_back(p); });
  EXPECT_EQ(handed, (std::vector<std::uint32_t>{3, 0, 2, 1, 4, 5}));
  handed.clear();
  run_pieces_in(nullptr, order, 6, [&](std::uint32_t p) { handed.push_back(p); });
  EXPECT_EQ(handed, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5}));
  std::vector<int> visits(6, 0);  // each piece writes its own entry
  run_pieces_in(&three, order, 6, [&](std::uint32_t p) { ++visits[p]; });
  EXPECT_EQ(visits, std::vector<int>(6, 1));
}

TEST(Pieces, RunChunksTakesTheChunkItIsGiven) {
  TileThreads two(2);
  constexpr std::size_t kChunk = 512;
  const std::size_t count = 3 * kChunk + 5;
  std::vector<int> visits(count, 0);
  std::vector<std::size_t> firsts;  // written by each piece at its own index
  firsts.assign(chunks_of(count, kChunk), count);
  run_chunks(
      &two, count,
      [&](std::size_t first, std::size_t last) {
        ASSERT_EQ(first % kChunk, 0U);
        ASSERT_EQ(last, std::min(count, first + kChunk));
        firsts[first / kChunk] = first;
        for (std::size_t i = first; i < last; ++i) ++visits[i];
      },
      kChunk);
  for (std::size_t p = 0; p < firsts.size(); ++p) EXPECT_EQ(firsts[p], p * kChunk);
  for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(visits[i], 1) << i;
}

TEST(Pieces, PiecesOfStaysWithinOneAndTheMost) {
  EXPECT_EQ(pieces_of(0), 1U);
  EXPECT_EQ(pieces_of(1), 1U);
  EXPECT_EQ(pieces_of(kChunkIndices), 1U);
  EXPECT_EQ(pieces_of(kChunkIndices + 1), 2U);
  EXPECT_EQ(pieces_of(std::size_t{1000} * kChunkIndices), kMaxPieces);
}

TEST(Pieces, PieceOfCutsTheRangeInOrderAndTwoPiecesAreTheHalves) {
  for (const std::size_t count :
       {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{1000}}) {
    for (std::uint32_t pieces = 1; pieces <= 9; ++pieces) {
      std::size_t next = 0;
      for (std::uint32_t p = 0; p < pieces; ++p) {
        const IndexRange range = piece_of(count, pieces, p);
        EXPECT_EQ(range.first, next);
        EXPECT_LE(range.first, range.last);
        next = range.last;
      }
      EXPECT_EQ(next, count);
    }
    // the halves: the first the shorter by one when count is odd
    EXPECT_EQ(half_of(count, 0).first, 0U);
    EXPECT_EQ(half_of(count, 0).last, count / 2);
    EXPECT_EQ(half_of(count, 1).first, count / 2);
    EXPECT_EQ(half_of(count, 1).last, count);
  }
}

// The counting sort by part in pieces (three pieces of 4 096 indices and more, on a runner
// that runs them backwards and on two threads) gives the order and starts of the sort in one
// piece; a part without indices is an empty range.
TEST(GroupByPart, InPiecesGivesTheOrderOfTheSortInOnePiece) {
  const std::size_t n = 3 * kChunkIndices + 123;
  const std::size_t parts = 37;
  std::vector<std::uint32_t> part(n);
  std::uint64_t state = 12345;
  for (std::uint32_t& p : part) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    p = static_cast<std::uint32_t>((state >> 33) % (parts - 1));  // the last part stays empty
  }
  const auto part_of = [&](std::size_t i) { return part[i]; };
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> next;
  std::vector<ContactIndex> order;
  group_by_part(n, parts, part_of, start, next, order);
  BackwardRunner backward;
  TileThreads two(2);
  for (PieceRunner* runner :
       {static_cast<PieceRunner*>(&backward), static_cast<PieceRunner*>(&two)}) {
    std::vector<std::uint32_t> pieced_start;
    std::vector<std::uint32_t> pieced_next;
    std::vector<ContactIndex> pieced_order;
    group_by_part(runner, n, parts, part_of, pieced_start, pieced_next, pieced_order);
    EXPECT_EQ(pieced_start, start);
    EXPECT_EQ(pieced_order, order);
  }
  EXPECT_EQ(start[parts - 1], start[parts]);
  EXPECT_EQ(start[parts], n);
}

}  // namespace
}  // namespace cdpowder
