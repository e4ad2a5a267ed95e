// slab_threads.cpp — pieces claimed from one counter, done counted on another.
#include "cdpowder/solver/nlgs/slab_threads.hpp"

namespace cdpowder {

namespace {

constexpr int kIndexBits = 16;
constexpr std::uint64_t kIndexMask = (std::uint64_t{1} << kIndexBits) - 1;

std::uint64_t claim_word(std::uint32_t id, std::uint32_t pieces) {
  return (std::uint64_t{id} << (2 * kIndexBits)) | (std::uint64_t{pieces} << kIndexBits);
}

}  // namespace

bool SlabThreads::claim(std::uint32_t& piece) {
  std::uint64_t word = claim_.load(std::memory_order_acquire);
  for (;;) {
    const auto next = static_cast<std::uint32_t>(word & kIndexMask);
    const auto pieces = static_cast<std::uint32_t>((word >> kIndexBits) & kIndexMask);
    if (next >= pieces) return false;
    if (claim_.compare_exchange_weak(word, word + 1, std::memory_order_acquire,
                                     std::memory_order_acquire)) {
      piece = next;
      return true;
    }
  }
}

void SlabThreads::solve_claimed() {
  std::uint32_t piece = 0;
  while (claim(piece)) {
    task_(context_, piece);
    done_.fetch_add(1, std::memory_order_release);
  }
}

void SlabThreads::work(void* self, int /*thread*/) {
  static_cast<SlabThreads*>(self)->solve_claimed();
}

void SlabThreads::run_pieces(std::uint32_t pieces, Task task, const void* context) {
  if (size() == 1 || pieces <= 1 || pieces > kIndexMask) {
    for (std::uint32_t p = 0; p < pieces; ++p) task(context, p);
    return;
  }
  task_ = task;
  context_ = context;
  done_.store(0, std::memory_order_relaxed);
  claim_.store(claim_word(++run_id_, pieces), std::memory_order_release);
  pool_.start(work, this);
  solve_claimed();
  spin_until([&] { return done_.load(std::memory_order_acquire) == pieces; });
}

SlabThreads* SlabThreadsSlot::get(int threads) {
  if (threads <= 1) {
    threads_.reset();
  } else if (!threads_ || threads_->size() != threads) {
    threads_.reset();  // the old workers stop before the new ones start
    threads_ = std::make_unique<SlabThreads>(threads);
  }
  return threads_.get();
}

}  // namespace cdpowder
