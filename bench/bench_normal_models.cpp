// Cost of one normal-force evaluation per model (the paper's Table 1 "time per evaluation"),
// all models on the same in-contact states, taken from real collisions in the order a
// contact meets them. Run: build/bench/tsubu_bench --benchmark_filter=Normal
#include <benchmark/benchmark.h>

#include <vector>

#include "tsubu/contact/law.hpp"
#include "tsubu/core/random.hpp"

namespace tsubu {
namespace {

// The states of real collisions, in the order a contact meets them: 256 head-on impacts of a
// sphere pair at touch phases spread over a step, stepped with model P (a = 0.01, e = 0.7)
// under symplectic Euler, every in-contact step recorded.
std::vector<ContactGeometry> contact_states(double k_n) {
  std::vector<ContactGeometry> states;
  const double m_eff = 2e-6, dt = 1e-4, d_c = 2e-3;
  const EnergyConserving p{k_n, 0.7, damping_ratio(0.7), 0};
  Random rng(7);
  for (int impact = 0; impact < 256; ++impact) {
    const double speed = rng.uniform(0.01, 1.0);
    double gap = rng.uniform(0, 1) * speed * dt, v = -speed;  // gap to touching, closing speed
    for (int step = 0; step < 100; ++step) {
      gap += v * dt;
      if (gap >= 0) {
        if (v > 0) break;
        continue;
      }
      ContactGeometry g;
      g.n = {0, 0, 1};
      g.delta = -gap;
      g.v_n = v;
      g.r_eff = 5e-4;
      g.m_eff = m_eff;
      g.d_mean = g.d_small = d_c;
      g.dt = dt;
      states.push_back(g);
      ContactHistory h;
      const NormalForce f = p.force(g, h);
      gap += f.gap_shift;
      v += f.f / m_eff * dt;
    }
  }
  return states;
}

template <class Model>
void NormalForceEvaluation(benchmark::State& state, Model model) {
  const std::vector<ContactGeometry> states = contact_states(1e4);
  ContactHistory h;
  std::size_t k = 0;
  for (auto _ : state) {
    const NormalForce f = model.force(states[k], h);
    benchmark::DoNotOptimize(f);
    if (++k == states.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

// k_n = 1e4 N/m with m* = 2e-6 kg and dt = 1e-4 s: a = k_n dt^2/m* = 0.05.
const double k_n = 1e4, e = 0.7;
BENCHMARK_CAPTURE(NormalForceEvaluation, C_linear, LinearDashpot{k_n, damping_ratio(e)});
BENCHMARK_CAPTURE(NormalForceEvaluation, T_hertz_tsuji, HertzTsuji{1e9, HertzTsuji::alpha_of(e)});
BENCHMARK_CAPTURE(NormalForceEvaluation, F_energy_conserving_2005, EnergyConserving2005{k_n, e, damping_ratio(e), 0});
BENCHMARK_CAPTURE(NormalForceEvaluation, P_energy_conserving, EnergyConserving{k_n, e, damping_ratio(e), 0});

}  // namespace
}  // namespace tsubu
