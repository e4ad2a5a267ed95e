// Benchmarks of contact detection (physics.md §4.3): ns per particle for the cell grid and
// the candidate geometry of a dense packing.
#include "cdpowder/detect/detect_contacts.hpp"
#include "support/packings.hpp"

#include <benchmark/benchmark.h>

namespace cdpowder::bench {
namespace {

void BM_DetectContacts(benchmark::State& state) {
  Packing packing = fcc_packing_with_vacancies(static_cast<int>(state.range(0)));
  StepWorkspace work(1);
  for (auto _ : state) {
    detect_contacts(packing.world, packing.settings.detection(), work.grid, work.contacts);
    benchmark::DoNotOptimize(work.contacts.pairs.data());
  }
  const auto n = static_cast<double>(packing.world.bodies.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
  state.counters["candidates"] = static_cast<double>(work.contacts.size());
  state.counters["ns_per_particle"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * n,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_DetectContacts)->Arg(1000)->Arg(100000)->Unit(benchmark::kMicrosecond);

/// Detection as a step of a run does it: the candidate list kept from the step before (its
/// cover checked, the pairs searched in lanes), the spheres at rest.
void BM_DetectContactsListKept(benchmark::State& state) {
  Packing packing = fcc_packing_with_vacancies(static_cast<int>(state.range(0)));
  StepWorkspace work(1);
  CandidateList list;
  detect_contacts(packing.world, packing.settings.detection(), work.grid, work.contacts, &list);
  for (auto _ : state) {
    detect_contacts(packing.world, packing.settings.detection(), work.grid, work.contacts, &list);
    benchmark::DoNotOptimize(work.contacts.pairs.data());
  }
  const auto n = static_cast<double>(packing.world.bodies.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
  state.counters["candidates"] = static_cast<double>(list.pairs().size());
  state.counters["contacts"] = static_cast<double>(work.contacts.size());
  state.counters["ns_per_particle"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * n,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_DetectContactsListKept)->Arg(1000)->Arg(100000)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace cdpowder::bench
