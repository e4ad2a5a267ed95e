// Benchmarks of contact detection (physics.md §4.3): ns per particle for the cell grid and
// the candidate geometry of a dense packing.
#include "cdpowder/detect/detect_contacts.hpp"
#include "support/packings.hpp"

#include <benchmark/benchmark.h>

namespace cdpowder::bench {
namespace {

/// Detection of the packing state.range(0) spheres large, with the candidate list rebuilt
/// each time (kept = nullptr) or kept from the first call, as a step of a run does it (its
/// cover checked, the pairs searched in lanes; the spheres are at rest).
void run_detection(benchmark::State& state, CandidateList* kept) {
  Packing packing = fcc_packing_with_vacancies(static_cast<int>(state.range(0)));
  StepWorkspace work(1);
  if (kept != nullptr) {
    detect_contacts(packing.world, packing.settings.detection(), work.grid, work.contacts, kept);
  }
  for (auto _ : state) {
    detect_contacts(packing.world, packing.settings.detection(), work.grid, work.contacts, kept);
    benchmark::DoNotOptimize(work.contacts.pairs.data());
  }
  const auto n = static_cast<double>(packing.world.bodies.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
  state.counters["candidates"] = static_cast<double>(work.contacts.size());
  if (kept != nullptr) state.counters["listed"] = static_cast<double>(kept->pairs().size());
  state.counters["ns_per_particle"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * n,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_DetectContacts(benchmark::State& state) {
  run_detection(state, nullptr);
}

BENCHMARK(BM_DetectContacts)->Arg(1000)->Arg(100000)->Unit(benchmark::kMicrosecond);

void BM_DetectContactsListKept(benchmark::State& state) {
  CandidateList list;
  run_detection(state, &list);
}

BENCHMARK(BM_DetectContactsListKept)->Arg(1000)->Arg(100000)->Unit(benchmark::kMicrosecond);

/// The candidate list's rebuild alone (the cell grid and the pairs within the candidate gap
/// plus the margin), on a list and grid kept from call to call as a run keeps them: what a
/// step pays when its spheres have moved past the list's slack.
void BM_CandidateListRebuild(benchmark::State& state) {
  Packing packing = fcc_packing_with_vacancies(static_cast<int>(state.range(0)));
  const DetectionSettings settings = packing.settings.detection();
  const double gap = candidate_gap(packing.world, settings);
  CellGrid grid;
  CandidateList list;
  for (auto _ : state) {
    list.rebuild(packing.world.bodies, packing.world.box, grid, gap, settings.verlet_margin);
    benchmark::DoNotOptimize(list.pairs().data());
  }
  const auto n = static_cast<double>(packing.world.bodies.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
  state.counters["listed"] = static_cast<double>(list.pairs().size());
  state.counters["ns_per_particle"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * n,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_CandidateListRebuild)->Arg(1000)->Arg(100000)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace cdpowder::bench
