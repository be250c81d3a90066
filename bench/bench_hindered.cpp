// What hindered settling costs: velocity Verlet steps of quartz grains in water, with and
// without [fluid] hindered_settling, on a random suspension (solid fraction 0.3, ~5000 grains,
// periodic in x, y and z, no walls) of one size and of a Talbot mixture (Sigma = 2). Each
// grain's ball of 3 radii holds tens of neighbours; the benchmark reports particle-steps per
// second. Run on an idle machine:
//   OMP_NUM_THREADS=1 build/bench/tsubu_bench --benchmark_filter=Hindered
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "tsubu/sim/simulation.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/source/build_world.hpp"

namespace tsubu {
namespace {

// A fresh suspension of one size (mixture = 0) or of the Talbot mixture (mixture = 1).
Simulation suspension(bool hindered, int mixture) {
  const double side = mixture ? 0.06 : 0.1;  // about 5000 grains either way
  const std::string dist = mixture ? "{ type = \"talbot\", exponent = 0, spread = 2.0, d_max = 0.006 }"
                                   : "{ type = \"single\", diameter = 0.005 }";
  const auto path = std::filesystem::temp_directory_path() / "tsubu_bench_hindered.toml";
  {
    std::ofstream f(path);
    f << "[simulation]\nduration = 1\ndt = 5e-7\nseed = 5\ngravity = [0, 0, -9.81]\n"
      << "[domain]\nlower = [0, 0, 0]\nupper = [" << side << ", " << side << ", " << side
      << "]\nperiodic = [\"x\", \"y\", \"z\"]\n"
      << "[[materials]]\nname = \"quartz\"\ndensity = 2650\nyoungs_modulus = 1e9\npoisson = 0.17\n"
      << "[contact.default]\nnormal = \"hertz_sediment\"\ntangential = \"mindlin\"\nalpha = 0.2\nfriction = 0.5\n"
      << "[fluid]\ndensity = 1000\nkinematic_viscosity = 1e-6\nhindered_settling = " << (hindered ? "true" : "false")
      << "\n[search]\nmethod = \"multilevel\"\n"
      << "[[particles]]\nsource = \"random\"\nmaterial = \"quartz\"\nlower = [0, 0, 0]\nupper = [" << side << ", "
      << side << ", " << side << "]\nsolid_fraction = 0.3\ndistribution = " << dist << "\n";
  }
  const Scenario sc = load_scenario(path.string());
  std::filesystem::remove(path);
  return Simulation(build_world(sc), build_model(sc), Integrator::velocity_verlet, {});
}

void Hindered(benchmark::State& state) {
  Simulation sim = suspension(state.range(0) != 0, static_cast<int>(state.range(1)));
  sim.start();
  for (auto _ : state) sim.step();
  const World& w = sim.world();
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * w.particles.size()), benchmark::Counter::kIsRate);
  state.counters["particles"] = static_cast<double>(w.particles.size());
}

BENCHMARK(Hindered)->ArgNames({"hindered", "mixture"})->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace tsubu
