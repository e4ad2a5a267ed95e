// coloured_threads.cpp — a coloured sweep cut into pieces claimed by the threads in visiting
// order, and the sums added afterwards in the order one thread would have added them.
#include "cdpowder/solver/coloured_threads.hpp"

#include <algorithm>
#include <chrono>
#include <cstddef>

namespace cdpowder {

namespace {

constexpr int kIndexBits = 20;
constexpr std::uint64_t kIndexMask = (std::uint64_t{1} << kIndexBits) - 1;
constexpr std::uint32_t kMaxPieces = kIndexMask;
constexpr std::uint64_t kIdMask = (std::uint64_t{1} << (64 - 2 * kIndexBits)) - 1;

/// Sweeps between two tries of the slower mode (adaptive mode): one sweep in 16 may be the
/// slower, while a change of load is seen within a few steps.
constexpr std::uint64_t kProbeInterval = 16;
/// Weight of the newest sweep in the recent time per contact of its mode.
constexpr double kRecentWeight = 0.25;

/// The claim word of a fresh sweep. The id wraps after 2^24 sweeps: a worker would have to
/// stall between reading the word and its compare-exchange for that many sweeps (and find the
/// same piece count) to claim a stale piece.
std::uint64_t claim_word(std::uint32_t id, std::uint32_t pieces) {
  return ((std::uint64_t{id} & kIdMask) << (2 * kIndexBits)) |
         (std::uint64_t{pieces} << kIndexBits);
}

}  // namespace

bool ColouredThreads::claim(std::uint32_t& piece) {
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

void ColouredThreads::solve_claimed() {
  std::uint32_t index = 0;
  while (claim(index)) {
    const Piece& piece = pieces_[index];
    // the barrier between colours: pieces complete in group order (a piece waits for all
    // pieces of the groups before it), so a count of done pieces says which groups are done
    spin_until([&] { return done_.load(std::memory_order_acquire) >= piece.wait_for; });
    if (piece.sequential) {
      // the piston couples all its contacts through one velocity: one thread, in order
      const ColouredSweep& sweep = *sweep_;
      for (std::size_t i = 0; i < sweep.sequential.size(); ++i) {
        double normal_force = 0.0;
        double cohesion = 0.0;
        const VisitChange change =
            solve_contact(sweep.sequential[i], *contacts_, *velocities_, normal_force, cohesion);
        sequential_visits_[i] = {change.change_sq, closed_normal(normal_force, cohesion)};
      }
    } else {
      solve_batches_kept(*sweep_, piece.first, piece.last, *velocities_, *contacts_,
                         batch_visits_.data() + piece.first);
    }
    done_.fetch_add(1, std::memory_order_release);
  }
}

void ColouredThreads::work(void* self, int /*thread*/) {
  static_cast<ColouredThreads*>(self)->solve_claimed();
}

SweepSums ColouredThreads::sweep(Contacts& contacts, VelocityCache& velocities,
                                 const ColouredSweep& sweep) {
  if (!adaptive_) return sweep_on_threads(contacts, velocities, sweep);
  // each mode once, then the faster of late, and the other one every kProbeInterval sweeps
  bool threaded = true;
  bool probe = false;
  if (threaded_ns_ != 0.0) {
    threaded = solo_ns_ != 0.0 && threaded_ns_ <= solo_ns_;
    probe = solo_ns_ != 0.0 && ++sweeps_ % kProbeInterval == 0;
    if (probe) threaded = !threaded;
  }
  // waking parked workers (a futex wake, tens of µs) is a cost of the step, not of the mode
  const bool waking = threaded && pool_.parked();
  const auto start = std::chrono::steady_clock::now();
  const SweepSums sums = threaded ? sweep_on_threads(contacts, velocities, sweep)
                                  : run_coloured_sweep(contacts, velocities, sweep);
  const double ns =
      std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() /
      static_cast<double>(std::max<std::size_t>(contacts.size(), 1));
  double& recent = threaded ? threaded_ns_ : solo_ns_;
  if (!waking || recent == 0.0) {
    recent = recent == 0.0 ? ns : (1.0 - kRecentWeight) * recent + kRecentWeight * ns;
  }
  // the workers sleep while the caller sweeps alone by choice (not for one probe)
  if (!threaded && !probe) pool_.park();
  return sums;
}

SweepSums ColouredThreads::sweep_on_threads(Contacts& contacts, VelocityCache& velocities,
                                            const ColouredSweep& sweep) {
  // each colour in one contiguous piece per thread: neighbouring batches touch neighbouring
  // spheres (pairs are coloured in storage order), so two threads rarely share a line
  const std::size_t colours = sweep.colours();
  const auto threads = static_cast<std::uint64_t>(size());
  pieces_.clear();
  for (const std::uint32_t group : sweep.group_order) {
    const auto wait_for = static_cast<std::uint32_t>(pieces_.size());
    if (group == colours) {
      if (!sweep.sequential.empty()) pieces_.push_back({0, 0, true, wait_for});
      continue;
    }
    const std::uint32_t first = sweep.colour_batches[group];
    const std::uint64_t count = sweep.colour_batches[group + 1] - first;
    const std::uint64_t cuts = std::min(threads, count);
    for (std::uint64_t p = 0; p < cuts; ++p) {
      pieces_.push_back({static_cast<std::uint32_t>(first + count * p / cuts),
                         static_cast<std::uint32_t>(first + count * (p + 1) / cuts), false,
                         wait_for});
    }
  }
  if (pieces_.size() > kMaxPieces) return run_coloured_sweep(contacts, velocities, sweep);
  contacts_ = &contacts;
  velocities_ = &velocities;
  sweep_ = &sweep;
  batch_visits_.resize(sweep.batches.size());
  sequential_visits_.resize(sweep.sequential.size());
  const auto pieces = static_cast<std::uint32_t>(pieces_.size());
  done_.store(0, std::memory_order_relaxed);
  claim_.store(claim_word(++sweep_id_, pieces), std::memory_order_release);
  pool_.start(work, this);
  solve_claimed();
  spin_until([&] { return done_.load(std::memory_order_acquire) == pieces; });
  return add_in_visiting_order();
}

SweepSums ColouredThreads::add_in_visiting_order() const {
  SweepSums sums;
  const ColouredSweep& sweep = *sweep_;
  const std::size_t colours = sweep.colours();
  for (const std::uint32_t group : sweep.group_order) {
    if (group == colours) {
      for (const KeptVisit& visit : sequential_visits_) {
        add_kept_visit(sums, visit.change_sq, visit.closed_normal);
      }
      continue;
    }
    for (std::uint32_t i = sweep.colour_batches[group]; i < sweep.colour_batches[group + 1]; ++i) {
      const BatchVisits& visits = batch_visits_[i];
      for (std::uint32_t l = 0; l < sweep.batches[i].lanes; ++l) {
        add_kept_visit(sums, visits.change_sq[l], visits.closed_normal[l]);
      }
    }
  }
  return sums;
}

ColouredThreads* ColouredThreadsSlot::get(int threads) {
  if (threads <= 1) {
    threads_.reset();
  } else if (!threads_ || threads_->size() != threads) {
    threads_.reset();  // the old workers stop before the new ones start
    threads_ = std::make_unique<ColouredThreads>(threads);
  }
  return threads_.get();
}

}  // namespace cdpowder
