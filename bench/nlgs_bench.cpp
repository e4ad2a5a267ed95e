// Benchmarks of the NLGS stage (physics.md §7): ns per contact update of one pass, and the
// passes a cold-started solve of a frozen packing needs (a counter, not a time).
#include "cdpowder/solver/nlgs/nlgs.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"
#include "support/packings.hpp"

#include <benchmark/benchmark.h>

namespace cdpowder::bench {
namespace {

// One pass in the solver's order (range(1): 0 = the default per-step block permutation,
// 1 = a fully random permutation as the group used); items are contact visits.
void BM_NlgsPass(benchmark::State& state) {
  Packing packing = fcc_packing_with_vacancies(static_cast<int>(state.range(0)));
  StepWorkspace work(1);
  prepare_contacts(packing, work);
  Contacts& contacts = work.contacts;
  prepare_visit_order(contacts, VisitOrder::RandomEachStep, work.solver);
  if (state.range(1) == 1) {
    shuffle_indices(std::span<ContactIndex>(contacts.visit_order), work.solver.rng);
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(run_scalar_pass(contacts, work.velocities));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(contacts.size()));
  state.counters["contacts"] = static_cast<double>(contacts.size());
  state.counters["ns_per_update"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(contacts.size()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_NlgsPass)
    ->Args({1000, 0})
    ->Args({100000, 0})
    ->Args({1000, 1})
    ->Args({100000, 1})
    ->Unit(benchmark::kMicrosecond);

// One pass of the coloured kernel (solver.kernel = "coloured"): the step's colours in one
// random order, batches of 4 pair contacts per colour; items are contact visits. range(1):
// contacts per colouring chunk (0 = the solver's kColourChunk, 1 = one chunk); the pairs are
// stored in colour order, as in the solver. Counters:
// colours, the share of contacts in the sequential group (overflow and walls), the share of
// unused lanes. CDPOWDER_KERNEL_ISA=sse2 (or avx2) keeps the SSE2 (or AVX2) kernel on a machine
// with wider vectors.
void BM_NlgsPassColoured(benchmark::State& state) {
  Packing packing = fcc_packing_with_vacancies(static_cast<int>(state.range(0)));
  StepWorkspace work(1);
  prepare_contacts(packing, work);
  Contacts& contacts = work.contacts;
  ColouredPass& pass = work.solver.coloured;
  const auto chunk = static_cast<std::size_t>(state.range(1));
  prepare_coloured_pass(contacts, work.velocities, pass,
                        chunk == 0 ? kColourChunk : (chunk == 1 ? 0 : chunk));
  order_groups(pass, VisitOrder::RandomEachStep, work.solver.rng);
  for (auto _ : state) {
    benchmark::DoNotOptimize(run_coloured_pass(contacts, work.velocities, pass));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(contacts.size()));
  state.counters["contacts"] = static_cast<double>(contacts.size());
  state.counters["colours"] = static_cast<double>(pass.colours());
  state.counters["tiles"] = static_cast<double>(work.solver.tiles.grid.tiles());
  state.counters["sequential"] =
      static_cast<double>(pass.sequential.size()) / static_cast<double>(contacts.size());
  state.counters["idle_lanes"] =
      1.0 - static_cast<double>(contacts.pairs.size() - pass.colouring.overflow.size()) /
                (static_cast<double>(kBatchLanes) * static_cast<double>(pass.batches()));
  state.counters["ns_per_update"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(contacts.size()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_NlgsPassColoured)
    ->Args({1000, 0})
    ->Args({100000, 0})
    ->Args({1000, 1})
    ->Args({100000, 1})
    ->Args({100000, 512})
    ->Args({100000, 8192})
    ->Unit(benchmark::kMicrosecond);

// The coloured pass on range(1) threads (solver.threads), the step in tiles of the default
// width (range(2) = 1, tiles.hpp) or not: the same bits for any thread count, so only the time
// differs. {n, 1, 0} against {n, 1, 1} is the cost of the tiles on one thread.
void BM_NlgsPassColouredThreads(benchmark::State& state) {
  Packing packing = fcc_packing_with_vacancies(static_cast<int>(state.range(0)));
  StepWorkspace work(1);
  prepare_contacts(packing, work);
  Contacts& contacts = work.contacts;
  ColouredPass& pass = work.solver.coloured;
  if (state.range(2) != 0) {
    assign_tiles(packing.world.bodies.position, packing.world.box,
                 packing.world.bodies.max_radius(), 0.0, contacts, work.solver.tiles);
  }
  prepare_coloured_pass(contacts, work.velocities, pass, kColourChunk, &work.solver.tiles);
  order_groups(pass, VisitOrder::RandomEachStep, work.solver.rng);
  TileThreads threads(static_cast<int>(state.range(1)));
  for (auto _ : state) {
    benchmark::DoNotOptimize(run_coloured_pass(contacts, work.velocities, pass, &threads));
  }
  state.counters["contacts"] = static_cast<double>(contacts.size());
  state.counters["colours"] = static_cast<double>(pass.colours());
  state.counters["tiles"] = static_cast<double>(work.solver.tiles.grid.tiles());
  state.counters["ns_per_update"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(contacts.size()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_NlgsPassColouredThreads)
    ->Args({1000, 1, 0})
    ->Args({1000, 1, 1})
    ->Args({1000, 2, 1})
    ->Args({10000, 1, 0})
    ->Args({10000, 1, 1})
    ->Args({10000, 2, 1})
    ->Args({100000, 1, 0})
    ->Args({100000, 1, 1})
    ->Args({100000, 2, 1})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

// A whole cold-started solve of the frozen packing under the piston, at the default
// settings (Anderson acceleration) and as plain NLGS; reports the passes it took.
void BM_NlgsSolveColdStart(benchmark::State& state) {
  Packing packing = fcc_packing_with_vacancies(static_cast<int>(state.range(0)));
  SolverSettings settings = packing.settings.solver;
  settings.acceleration_depth = static_cast<int>(state.range(1));
  settings.max_passes = 20000;
  SolverStats stats;
  for (auto _ : state) {
    state.PauseTiming();
    StepWorkspace work(1);
    prepare_contacts(packing, work);
    state.ResumeTiming();
    stats = solve_nlgs(work.contacts, work.velocities, settings, 1.0, work.solver);
  }
  state.counters["passes"] = stats.passes;
  state.counters["converged"] = stats.converged ? 1 : 0;
}

BENCHMARK(BM_NlgsSolveColdStart)
    ->Args({1015, 5})
    ->Args({1015, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace cdpowder::bench
