// tile_threads.cpp — pieces in one range per thread, claimed there first and then from the
// others' ranges, in one OpenMP parallel region a run.
#include "cdpowder/solver/nlgs/tile_threads.hpp"

#include <omp.h>

namespace cdpowder {

void TileThreads::solve_claimed(int thread) {
  // its own range first, then the others' in turn
  for (int k = 0; k < threads_; ++k) {
    Range& range = ranges_[static_cast<std::size_t>((thread + k) % threads_)];
    for (;;) {
      const std::uint32_t piece = range.next.fetch_add(1, std::memory_order_relaxed);
      if (piece >= range.end) break;
      task_(context_, piece);
    }
  }
}

void TileThreads::run_pieces(std::uint32_t pieces, Task task, const void* context) {
  if (threads_ == 1 || pieces <= 1) {
    for (std::uint32_t p = 0; p < pieces; ++p) task(context, p);
    return;
  }
  task_ = task;
  context_ = context;
  const auto threads = static_cast<std::uint64_t>(threads_);
  for (std::uint64_t k = 0; k < threads; ++k) {
    ranges_[k].next.store(static_cast<std::uint32_t>(k * pieces / threads),
                          std::memory_order_relaxed);
    ranges_[k].end = static_cast<std::uint32_t>((k + 1) * pieces / threads);
  }
  // the region's start orders the ranges before every claim, and its closing barrier every
  // piece before the return
#pragma omp parallel num_threads(threads_) default(none)
  solve_claimed(omp_get_thread_num());
}

TileThreads* TileThreadsSlot::get(int threads) {
  if (threads <= 1) {
    threads_.reset();
  } else if (!threads_ || threads_->size() != threads) {
    threads_ = std::make_unique<TileThreads>(threads);
  }
  return threads_.get();
}

}  // namespace cdpowder
