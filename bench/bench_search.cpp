// Contact search cost: CellGrid against MultiLevelGrid on random beds (the engine's random
// source: no overlaps, solid fraction 0.3, ~20,000 grains, number density ∝ d^-2 between
// d_max/ratio and d_max, periodic in x and y) for size ratios 1 to 50, and the multi-level
// grid's cost estimate against its measured time for every forced number of levels.
// Run: OMP_NUM_THREADS=1 build/bench/tsubu_bench --benchmark_filter=Search
// (bench/search_scaling.py runs it and plots bench/results/search_scaling.png).
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "tsubu/scenario/scenario.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {
namespace {

constexpr double kPhi = 0.3, kDMax = 0.01;
constexpr double kParticles = 20000;

// The bed of one size ratio, built once per process through a scenario file.
const World& bed(int ratio) {
  static std::map<int, std::unique_ptr<World>> beds;
  auto& w = beds[ratio];
  if (w) return *w;
  const double d_min = kDMax / ratio;
  // Mean grain volume of n(d) ∝ d^-2 on [d_min, d_max] (one size when ratio = 1).
  const double mean_d3 = ratio == 1 ? d_min * d_min * d_min
                                    : 0.5 * (kDMax * kDMax - d_min * d_min) / (1 / d_min - 1 / kDMax);
  const double side = std::cbrt(kParticles * M_PI / 6 * mean_d3 / kPhi);
  const std::string dist = ratio == 1 ? "{ type = \"single\", diameter = " + std::to_string(kDMax) + " }"
                                      : "{ type = \"talbot\", d_min = " + std::to_string(d_min) +
                                            ", d_max = " + std::to_string(kDMax) + ", exponent = 1 }";
  const auto path = std::filesystem::temp_directory_path() / ("tsubu_bench_search_" + std::to_string(ratio) + ".toml");
  {
    std::ofstream f(path);
    f << "[simulation]\nduration = 1\ndt = 1e-5\nseed = " << 40 + ratio << "\n"
      << "[domain]\nlower = [0, 0, 0]\nupper = [" << side << ", " << side << ", " << side << "]\nperiodic = [\"x\", \"y\"]\n"
      << "[[materials]]\nname = \"glass\"\ndensity = 2500\nyoungs_modulus = 1e7\npoisson = 0.3\n"
      << "[[particles]]\nsource = \"random\"\nmaterial = \"glass\"\nlower = [0, 0, 0]\nupper = [" << side << ", " << side
      << ", " << side << "]\nsolid_fraction = " << kPhi << "\ndistribution = " << dist << "\n";
  }
  w = std::make_unique<World>(build_world(load_scenario(path.string())));
  std::filesystem::remove(path);
  return *w;
}

double margin_of(int ratio) { return 0.1 * kDMax / ratio; }  // a tenth of the smallest diameter

template <class Search>
void run(benchmark::State& state, Search& search, int ratio) {
  const World& w = bed(ratio);
  std::vector<Pair> pairs;
  for (auto _ : state) {
    search.find_pairs(w.particles, w.domain, margin_of(ratio), pairs);
    benchmark::DoNotOptimize(pairs.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
  state.counters["ratio"] = ratio;
  state.counters["particles"] = static_cast<double>(w.particles.size());
  state.counters["pairs"] = static_cast<double>(pairs.size());
}

void SearchCell(benchmark::State& state) {
  CellGrid grid;
  run(state, grid, static_cast<int>(state.range(0)));
  state.counters["levels"] = 1;
}

void SearchMultiLevel(benchmark::State& state) {
  MultiLevelGrid grid;  // automatic number of levels
  run(state, grid, static_cast<int>(state.range(0)));
  state.counters["levels"] = grid.levels();
}

// Forced M levels, with the cost estimate of M levels beside the time.
void SearchLevels(benchmark::State& state) {
  const int ratio = static_cast<int>(state.range(0)), levels = static_cast<int>(state.range(1));
  MultiLevelGrid grid(levels);
  const auto estimates = grid.estimate(bed(ratio).particles, bed(ratio).domain, margin_of(ratio));
  if (levels > static_cast<int>(estimates.size())) {
    state.SkipWithError("fewer levels hold particles");
    for (auto _ : state) {
    }
    return;
  }
  run(state, grid, ratio);
  const auto& e = estimates[static_cast<std::size_t>(levels - 1)];
  state.counters["levels"] = levels;
  state.counters["estimate"] = e.total();
  state.counters["est_cells"] = e.cells;
  state.counters["est_candidates"] = e.candidates;
  state.counters["est_binning"] = e.binning;
}

BENCHMARK(SearchCell)->Arg(1)->Arg(2)->Arg(5)->Arg(10)->Arg(20)->Arg(50)->Unit(benchmark::kMillisecond);
BENCHMARK(SearchMultiLevel)->Arg(1)->Arg(2)->Arg(5)->Arg(10)->Arg(20)->Arg(50)->Unit(benchmark::kMillisecond);
BENCHMARK(SearchLevels)
    ->ArgsProduct({{2, 5, 10, 20, 50}, {1, 2, 3, 4, 5, 6, 7}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace tsubu
