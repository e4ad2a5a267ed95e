// tile_threads.cpp — pieces in one range per thread, claimed there first and then from the
// others' ranges; done counted on one counter.
#include "cdpowder/solver/nlgs/tile_threads.hpp"

namespace cdpowder {

namespace {

constexpr int kIndexBits = 16;
constexpr std::uint64_t kIndexMask = (std::uint64_t{1} << kIndexBits) - 1;

std::uint64_t range_word(std::uint32_t id, std::uint32_t first, std::uint32_t end) {
  return (std::uint64_t{id} << (2 * kIndexBits)) | (std::uint64_t{end} << kIndexBits) | first;
}

}  // namespace

bool TileThreads::claim(int range, std::uint32_t& piece) {
  std::atomic<std::uint64_t>& claim = ranges_[static_cast<std::size_t>(range)].word;
  std::uint64_t word = claim.load(std::memory_order_acquire);
  for (;;) {
    const auto next = static_cast<std::uint32_t>(word & kIndexMask);
    const auto end = static_cast<std::uint32_t>((word >> kIndexBits) & kIndexMask);
    if (next >= end) return false;
    if (claim.compare_exchange_weak(word, word + 1, std::memory_order_acquire,
                                    std::memory_order_acquire)) {
      piece = next;
      return true;
    }
  }
}

void TileThreads::solve_claimed(int thread) {
  // its own range first, then the others' in turn
  const int threads = size();
  for (int k = 0; k < threads; ++k) {
    const int range = (thread + k) % threads;
    std::uint32_t piece = 0;
    while (claim(range, piece)) {
      task_(context_, piece);
      done_.fetch_add(1, std::memory_order_release);
    }
  }
}

void TileThreads::work(void* self, int thread) {
  static_cast<TileThreads*>(self)->solve_claimed(thread);
}

void TileThreads::run_pieces(std::uint32_t pieces, Task task, const void* context) {
  if (size() == 1 || pieces <= 1 || pieces > kIndexMask) {
    for (std::uint32_t p = 0; p < pieces; ++p) task(context, p);
    return;
  }
  task_ = task;
  context_ = context;
  done_.store(0, std::memory_order_relaxed);
  const std::uint32_t id = ++run_id_;
  const auto threads = static_cast<std::uint64_t>(size());
  for (std::uint64_t k = 0; k < threads; ++k) {
    const auto first = static_cast<std::uint32_t>(k * pieces / threads);
    const auto end = static_cast<std::uint32_t>((k + 1) * pieces / threads);
    ranges_[k].word.store(range_word(id, first, end), std::memory_order_release);
  }
  pool_.start(work, this);
  solve_claimed(0);
  spin_until([&] { return done_.load(std::memory_order_acquire) == pieces; });
}

TileThreads* TileThreadsSlot::get(int threads) {
  if (threads <= 1) {
    threads_.reset();
  } else if (!threads_ || threads_->size() != threads) {
    threads_.reset();  // the old workers stop before the new ones start
    threads_ = std::make_unique<TileThreads>(threads);
  }
  return threads_.get();
}

}  // namespace cdpowder
