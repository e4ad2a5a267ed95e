// core_round_trip.hpp — how long a cache line takes to go from one core to another and back,
// the price of every hand-over between the threads of a two-thread step
// (docs/lab/2026-11-27-two-threads-and-the-core-path.md; today's figure: docs/performance.md,
// "Two threads"). On a virtual machine the two cores' path can change while a process runs: a
// two-thread timing is read beside this figure, taken just before and just after it.
#pragma once

namespace cdpowder::bench {

/// The median over a few batches of the round trip [ns] of one cache line between two threads
/// pinned to CPUs `first` and `second` (each waits for the other's store, then answers). NaN
/// where the threads cannot be pinned (fewer CPUs, or not Linux).
double core_round_trip_ns(int first = 0, int second = 1);

}  // namespace cdpowder::bench
