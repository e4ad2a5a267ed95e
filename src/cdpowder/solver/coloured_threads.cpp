// coloured_threads.cpp — a coloured sweep split among threads colour by colour, and the sums
// added afterwards in the order one thread would have added them.
#include "cdpowder/solver/coloured_threads.hpp"

#include <cstddef>
#include <cstdint>

namespace cdpowder {

namespace {

struct SweepJob {
  Contacts& contacts;
  VelocityCache& velocities;
  const ColouredSweep& sweep;
  SweepThreads& threads;
  ThreadedSweepScratch& scratch;
};

/// Thread t's part of the sweep. Every thread passes the same barriers: one after each group
/// but the last (run() itself waits for all threads at the end).
void sweep_share(void* context, int t) {
  const SweepJob& job = *static_cast<const SweepJob*>(context);
  const ColouredSweep& sweep = job.sweep;
  const std::size_t colours = sweep.colours();
  const auto n = static_cast<std::uint64_t>(job.threads.size());
  const auto thread = static_cast<std::uint64_t>(t);
  const std::size_t groups = sweep.group_order.size();
  for (std::size_t g = 0; g < groups; ++g) {
    const std::uint32_t group = sweep.group_order[g];
    if (group == colours) {
      if (sweep.sequential.empty()) continue;  // all threads skip its barrier alike
      if (t == 0) {
        // the piston couples all its contacts through one velocity: one thread, in order
        for (std::size_t i = 0; i < sweep.sequential.size(); ++i) {
          double normal_force = 0.0;
          double cohesion = 0.0;
          const VisitChange change = solve_contact(sweep.sequential[i], job.contacts,
                                                   job.velocities, normal_force, cohesion);
          job.scratch.sequential[i] = {change.change_sq, closed_normal(normal_force, cohesion)};
        }
      }
    } else {
      // a contiguous share of the colour's batches: neighbouring batches touch neighbouring
      // spheres (pairs are coloured in storage order), so the threads rarely share a line
      const std::uint32_t first = sweep.colour_batches[group];
      const std::uint64_t count = sweep.colour_batches[group + 1] - first;
      const auto begin = static_cast<std::uint32_t>(first + count * thread / n);
      const auto end = static_cast<std::uint32_t>(first + count * (thread + 1) / n);
      if (begin < end) {
        solve_batches_kept(sweep, begin, end, job.velocities, job.contacts,
                           job.scratch.batches.data() + begin);
      }
    }
    if (g + 1 < groups) job.threads.barrier(t);
  }
}

/// The kept visits added in the visiting order: run_coloured_sweep's sums, bit for bit.
SweepSums add_in_visiting_order(const ColouredSweep& sweep, const ThreadedSweepScratch& scratch) {
  SweepSums sums;
  const std::size_t colours = sweep.colours();
  for (const std::uint32_t group : sweep.group_order) {
    if (group == colours) {
      for (const KeptVisit& visit : scratch.sequential) {
        add_kept_visit(sums, visit.change_sq, visit.closed_normal);
      }
      continue;
    }
    for (std::uint32_t i = sweep.colour_batches[group]; i < sweep.colour_batches[group + 1]; ++i) {
      const BatchVisits& visits = scratch.batches[i];
      for (std::uint32_t l = 0; l < sweep.batches[i].lanes; ++l) {
        add_kept_visit(sums, visits.change_sq[l], visits.closed_normal[l]);
      }
    }
  }
  return sums;
}

}  // namespace

SweepSums run_coloured_sweep_threaded(Contacts& contacts, VelocityCache& velocities,
                                      const ColouredSweep& sweep, SweepThreads& threads,
                                      ThreadedSweepScratch& scratch) {
  scratch.batches.resize(sweep.batches.size());
  scratch.sequential.resize(sweep.sequential.size());
  SweepJob job{contacts, velocities, sweep, threads, scratch};
  threads.run(sweep_share, &job);
  return add_in_visiting_order(sweep, scratch);
}

}  // namespace cdpowder
