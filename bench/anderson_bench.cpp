// Benchmark of one Anderson mixing step (anderson.hpp) with a full history, on iterates of
// the length a paper-size step mixes (8 doubles per contact, ≈ 1 100 contacts) and a large
// one; items are doubles of the iterate.
#include "cdpowder/solver/nlgs/anderson.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cdpowder::bench {
namespace {

// range(0): length n of the iterates, range(1): depth m
void BM_AndersonMix(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  AndersonAccelerator accelerator(static_cast<int>(state.range(1)));
  // a contracting linear map x → 0.9 x + b with a smooth b: the fit stays well posed
  AlignedVector<double> x(n);
  AlignedVector<double> g(n);
  AlignedVector<double> next(n);
  const auto map = [&] {
    for (std::size_t i = 0; i < n; ++i)
      g[i] = 0.9 * x[i] + std::sin(0.001 * static_cast<double>(i));
  };
  for (std::size_t i = 0; i < n; ++i) x[i] = std::cos(0.01 * static_cast<double>(i));
  for (int k = 0; k <= state.range(1) + 1; ++k) {  // fill the history
    map();
    accelerator.extrapolate(x, g, next);
    x.swap(next);
  }
  map();
  for (auto _ : state) {
    benchmark::DoNotOptimize(accelerator.extrapolate(x, g, next));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
  state.counters["ns_per_double"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(n),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_AndersonMix)->Args({8800, 5})->Args({2800000, 5})->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace cdpowder::bench
