// What the still fluid's load costs per grain (buoyancy, Schiller-Naumann drag, Stokes
// torque): grain by grain (fluid_load, as the block steps call it) and a batch at a time
// (fluid_loads, as the fixed-step evaluation calls it; the same bits). 3000 grains of 0.6 to
// 10 mm moving at up to 0.5 m/s through water. Run on an idle machine:
//   build/bench/tsubu_bench --benchmark_filter=FluidLoads
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "tsubu/fluid/fluid.hpp"

namespace tsubu {
namespace {

void FluidLoads(benchmark::State& state) {
  const bool batched = state.range(0) != 0;
  Fluid f;
  f.enabled = true, f.density = 1000, f.viscosity = 1e-6;
  const std::size_t n = 3000;
  std::vector<double> d(n);
  std::vector<Vec3> u(n), w(n);
  std::vector<Crowding> crowd(n);
  std::vector<FluidLoad> out(n);
  std::uint64_t s = 7;
  const auto uniform = [&] {  // in [0, 1)
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(s >> 11) * 0x1.0p-53;
  };
  for (std::size_t k = 0; k < n; ++k) {
    d[k] = 6e-4 + 9.4e-3 * uniform();
    u[k] = {0.2 * uniform() - 0.1, 0.2 * uniform() - 0.1, -0.5 * uniform()};
    w[k] = {20 * uniform(), 20 * uniform(), 20 * uniform()};
  }
  const Vec3 g{0, 0, -9.81};
  for (auto _ : state) {
    if (batched) {
      fluid_loads(f, g, n, d.data(), u.data(), w.data(), crowd.data(), out.data());
    } else {
      for (std::size_t k = 0; k < n; ++k) out[k] = fluid_load(f, d[k], g, u[k], w[k], crowd[k]);
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.counters["grain_loads_per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * n), benchmark::Counter::kIsRate);
}

BENCHMARK(FluidLoads)->ArgName("batched")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace tsubu
