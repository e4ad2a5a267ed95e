// pieces.hpp — work cut into a few pieces that write no common memory, run side by side on
// whatever threads the caller has (solver/nlgs/tile_threads.hpp) or one after the other. The
// stages of a step take a PieceRunner, so a lower layer (detection) runs on the solver's
// threads without knowing them. The pieces are fixed by the work, never by the thread count:
// every result that combines pieces is combined in piece order by the caller, so it has the
// same bits on one thread or two.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace cdpowder {

class PieceRunner {
 public:
  /// noexcept: a piece that threw would leave another thread writing into the frame of a run
  /// that is gone, so a throw ends the program instead (pieces throw nothing but a failed
  /// allocation of a scratch vector, which keeps its capacity from step to step)
  using Task = void (*)(const void* context, std::uint32_t piece) noexcept;

  /// Runs task(context, piece) for piece = 0 … pieces − 1, each exactly once, and returns
  /// when all are done. Pieces must not write common memory.
  virtual void run_pieces(std::uint32_t pieces, Task task, const void* context) = 0;

 protected:
  PieceRunner() = default;
  ~PieceRunner() = default;
  PieceRunner(const PieceRunner&) = default;
  PieceRunner(PieceRunner&&) = default;
  PieceRunner& operator=(const PieceRunner&) = default;
  PieceRunner& operator=(PieceRunner&&) = default;
};

/// Runs task(0) … task(pieces − 1) on `runner`, or one after the other on the caller when
/// `runner` is null.
template <typename Task>
void run_pieces(PieceRunner* runner, std::uint32_t pieces, const Task& task) {
  if (runner == nullptr) {
    for (std::uint32_t p = 0; p < pieces; ++p) task(p);
    return;
  }
  runner->run_pieces(
      pieces,
      [](const void* t, std::uint32_t piece) noexcept { (*static_cast<const Task*>(t))(piece); },
      &task);
}

/// run_pieces for task(0) … task(pieces − 1), the pieces handed to `runner`'s threads in
/// `order` (a permutation of them; pieces past its end in their own order) and run on the
/// caller in piece order, the order of memory. A runner gives each thread a contiguous range of
/// what it is handed first (TileThreads), so `order` chooses which pieces go together: a tiled
/// step hands its tiles out row by row (ColouredPass::strip_order), so that a thread takes the
/// same rows in every stage and their data stays in its core's cache. What a piece computes
/// does not depend on it.
template <typename Task>
void run_pieces_in(PieceRunner* runner, std::span<const std::uint32_t> order, std::uint32_t pieces,
                   const Task& task) {
  if (runner == nullptr) {
    run_pieces(runner, pieces, task);  // piece order
    return;
  }
  run_pieces(runner, pieces, [&](std::uint32_t i) { task(i < order.size() ? order[i] : i); });
}

/// The consecutive indices of one piece of run_chunks.
inline constexpr std::size_t kChunkIndices = 4096;

/// Chunks of `chunk` indices that [0, count) takes, the last one shorter: ⌈count / chunk⌉.
inline std::size_t chunks_of(std::size_t count, std::size_t chunk) {
  return (count + chunk - 1) / chunk;
}

/// Runs task(first, last) over [0, count) cut into pieces of `chunk` consecutive indices (the
/// last one shorter) on `runner`, or once over the whole range on the caller when `runner` is
/// null or the range is one piece. For loops whose iterations write no common memory and
/// combine nothing (a gather, a scatter through a permutation, a renaming): how they are cut
/// does not change what they compute. A chunk of large elements (a batch of 8 pairs) is
/// given fewer indices.
template <typename Task>
void run_chunks(PieceRunner* runner, std::size_t count, const Task& task,
                std::size_t chunk = kChunkIndices) {
  if (runner == nullptr || count <= chunk) {
    task(std::size_t{0}, count);
    return;
  }
  const auto pieces = static_cast<std::uint32_t>(chunks_of(count, chunk));
  run_pieces(runner, pieces, [&](std::uint32_t piece) {
    const std::size_t first = std::size_t{piece} * chunk;
    task(first, std::min(count, first + chunk));
  });
}

/// The most pieces of a stage whose pieces each keep a result of their own in an array (a
/// maximum, a flag, a list of contacts found), so that no step allocates for them.
inline constexpr std::uint32_t kMaxPieces = 64;

/// How many pieces such a stage cuts [0, count) into: one a kChunkIndices, at least one, at
/// most kMaxPieces. Fixed by the count, never by the threads.
inline std::uint32_t pieces_of(std::size_t count) {
  return static_cast<std::uint32_t>(
      std::clamp<std::size_t>(chunks_of(count, kChunkIndices), 1, kMaxPieces));
}

/// The indices of each piece of a stage that cuts [0, count) into about pieces_of(count)
/// pieces of whole chunks of kChunkIndices (the last piece shorter): every piece starts at a
/// multiple of kChunkIndices, so at a whole block of lanes. Fixed by the count, never by the
/// threads; a stage that sums its pieces' results adds them in piece order. [0, count) takes
/// chunks_of(count, indices_per_piece(count)) pieces.
inline std::size_t indices_per_piece(std::size_t count) {
  return std::max<std::size_t>(1, chunks_of(chunks_of(count, pieces_of(count)), kChunkIndices)) *
         kChunkIndices;
}

/// The indices [first, last) of one piece.
struct IndexRange {
  std::size_t first = 0;
  std::size_t last = 0;
};

/// Piece `piece` of [0, count) cut into pieces of `per_piece` consecutive indices, the last
/// one shorter: the pieces of indices_per_piece(count) that the stages below cut.
inline IndexRange chunk_range(std::size_t count, std::size_t per_piece, std::size_t piece) {
  const std::size_t first = piece * per_piece;
  return {first, std::min(count, first + per_piece)};
}

/// Runs task(first, last, sums) over [0, count) cut into the pieces of indices_per_piece (at
/// most kMaxPieces), each piece with a value-initialised Sums of its own, side by side on
/// `runner` or in piece order on the caller, and returns the pieces' Sums joined in piece order
/// (Sums::merge adds the next piece's): the same bits on any number of threads. The pieces'
/// Sums are held on the caller's stack (kMaxPieces of them: a few kB for sums of a cache line),
/// so a stage allocates nothing.
template <typename Sums, typename Task>
Sums run_summed_pieces(PieceRunner* runner, std::size_t count, const Task& task) {
  const std::size_t per_piece = indices_per_piece(count);
  const auto pieces =
      static_cast<std::uint32_t>(std::max<std::size_t>(1, chunks_of(count, per_piece)));
  std::array<Sums, kMaxPieces> sums{};
  run_pieces(runner, pieces, [&](std::uint32_t p) {
    const IndexRange range = chunk_range(count, per_piece, p);
    task(range.first, range.last, sums[p]);
  });
  for (std::uint32_t p = 1; p < pieces; ++p) sums.front().merge(sums[p]);
  return sums.front();
}

/// Piece `piece` of `pieces` near-equal consecutive ranges of [0, count): [⌊count p/P⌋,
/// ⌊count (p + 1)/P⌋).
inline IndexRange piece_of(std::size_t count, std::uint32_t pieces, std::uint32_t piece) {
  return {count * piece / pieces, count * (piece + std::size_t{1}) / pieces};
}

/// The half of [0, count) that piece `piece` (0 or 1) of two takes; the first half is the
/// shorter by one when count is odd.
inline IndexRange half_of(std::size_t count, std::uint32_t piece) {
  return piece_of(count, 2, piece);
}

}  // namespace cdpowder
