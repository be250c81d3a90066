// ForceField::gather, the one gather of both evaluations (fixed steps and block steps), for
// the force field's own files: inlined into each loop over particles, so that the sums stay
// in registers.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include "tsubu/forces/force_field.hpp"

namespace tsubu {

template <bool WithRates>
inline void ForceField::gather(const World& world, std::size_t i, Gathered<WithRates>& g,
                               const std::vector<char>* is_active) const {
  const Particles& p = world.particles;
  const double r = p.radius[i];
  const auto& pairs = world.contacts.pairs();
  // Three loops, each of one side (ContactList::for_each_contact_of): the pairs where i is
  // second (it takes the reaction, -f: adding -f is subtracting f, to the bit), those where
  // it is first, its walls. Listed pairs that do not touch hold zeros and are added without
  // a test: no branch to miss.
  world.contacts.for_each_contact_of(i, [&](std::uint32_t k, auto side) {
    constexpr int kSide = decltype(side)::value;
    constexpr bool reaction = kSide < 0;  // i is the pair's j
    constexpr double sign = reaction ? -1.0 : 1.0;
    const Results& res = kSide == 0 ? wall_results_ : pair_results_;
    const Results::Entry& e = res.entry[k];
    g.force += sign * e.force_i;
    g.torque += res.torque(k, r);
    if (rolls_) g.torque += sign * res.rolling_i[k];
    const bool touch = e.delta > 0;
    (reaction ? g.count : g.own) += touch;
    g.deepest = std::max(g.deepest, e.delta);
    if constexpr (!WithRates) {
      if (shifts_) g.shift += reaction ? res.shift_j[k] : res.shift_i[k];
    } else {
      const Rates& rt = kSide == 0 ? wall_rates_[k] : pair_rates_[k];
      g.force_rate += sign * rt.force_i;
      // d/dt of -(r - delta/2) (n x F_t)
      g.torque_rate += (0.5 * rt.delta) * e.n_x_ft - (r - 0.5 * e.delta) * rt.n_x_ft;
      if (rolls_) g.torque_rate += sign * rt.rolling_i;
      if constexpr (reaction) g.evaluated += touch && !(*is_active)[pairs[k].i];  // once per contact
      else g.evaluated += touch;
      g.bound = std::min(g.bound, rt.step_bound);
      if (rt.touched_for > 0) ++g.began, g.touched_for = rt.touched_for;
      if (rt.released_for > 0) ++g.ended, g.released_for = rt.released_for;
      if (touch) {
        const double m_j = kSide == 0 ? std::numeric_limits<double>::infinity() : p.mass[reaction ? pairs[k].i : pairs[k].j];
        g.damping_over_mass += std::max(rt.damping, 3.5 * rt.tangential_damping) * (1 / p.mass[i] + 1 / std::sqrt(p.mass[i] * m_j));
        if (rolls_) {  // model EPSD's rolling dashpot turns i against its partner: C_r (1/I_i + 1/sqrt(I_i I_j))
          const double i_j = kSide == 0 ? std::numeric_limits<double>::infinity() : p.inertia[reaction ? pairs[k].i : pairs[k].j];
          g.damping_over_mass += rt.rolling_damping * (1 / p.inertia[i] + 1 / std::sqrt(p.inertia[i] * i_j));
        }
      }
    }
  });
}
}  // namespace tsubu
