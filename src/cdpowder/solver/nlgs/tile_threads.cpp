// tile_threads.cpp — pieces in one range per thread, claimed there first and then from the
// others' ranges, in one OpenMP parallel region a run.
#include "cdpowder/solver/nlgs/tile_threads.hpp"

#include <cstdlib>
#include <omp.h>
#include <string_view>

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

bool ThreadChoice::always_threaded_from_environment() {
  static const bool always = [] {
    const char* value = std::getenv("CDPOWDER_ALWAYS_THREADED");
    return value != nullptr && std::string_view(value) == "1";
  }();
  return always;
}

void ThreadChoice::record(double seconds, double updates) {
  if (always_) return;
  if (updates > 0.0 && seconds >= 0.0) {
    seconds_ += seconds;
    updates_ += updates;
  }
  if (++steps_ % kBlockSteps != 0) return;
  const std::size_t way = threaded_ ? 1 : 0;
  if (updates_ > 0.0) per_update_[way] = seconds_ / updates_;
  seconds_ = updates_ = 0.0;
  if (trying_) {
    judge_try(way);
    since_try_ = 1;  // the try was a block: a try every try_every_ blocks
    return;
  }
  const bool unmeasured = per_update_[1 - way] == 0.0;
  if (unmeasured || confirming_ || faster(1 - way) || ++since_try_ >= try_every_) {
    trying_ = true;
    threaded_ = !threaded_;
  }
}

void ThreadChoice::judge_try(std::size_t tried) {
  trying_ = false;
  const std::size_t kept = 1 - tried;
  if (!faster(tried)) {
    confirming_ = false;
    const bool clear_loss = per_update_[tried] > kClearLoss * per_update_[kept];
    try_every_ = clear_loss ? std::min(2 * try_every_, kMaxTryEvery) : kTryEvery;
    threaded_ = kept == 1;
    return;
  }
  try_every_ = kTryEvery;
  if (confirming_) {  // the second try in a row that won: the tried way is kept from now on
    confirming_ = false;
    threaded_ = tried == 1;
    return;
  }
  confirming_ = true;  // one block of the kept way, then the deciding try
  threaded_ = kept == 1;
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
