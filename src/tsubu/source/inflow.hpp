// The inflow of the sedimentation experiment (docs/sedimentation.md; paper section
// 4.1, Eqs. 25 and 27; docs/sedimentation.md). A virtual column with the box's x-y extent as
// its base stands on the entry plane z = z_c, filled without overlap to the solid fraction
// phi_0 and falling at u_r; grain j at height z_0j enters at t_arr = (z_0j - z_c)/u_r, at z_c,
// with velocity -u_r. The mass flux is F = rho_p phi_0 L^2 u_r.
//
// The column is generated lazily, slab by slab of height H (at least 4 d_max and about 50
// grains), so that a run holds one slab of its future grains. Every slab is built from its own
// random streams (seeded from the seed and the slab's index), so the stream's state is a few
// counters. Slab k releases the grains with heights in [kH - h, (k+1)H - h), h = d_max: the
// band [kH - h, kH + h) around its lower boundary is placed first, on its own, and the core
// [kH + h, (k+1)H - h) after it, avoiding both its bands; cores never reach each other
// (they are 2h = 2 d_max apart), nor do bands (H - 2h >= 2 d_max), so no two grains of the
// column overlap, across slab boundaries and the periodic sides included. Slab 0 has no band
// below: its core starts at z_c. Each region (band or core) gets exactly phi_0 of its volume
// on average: diameters are drawn until the next one would pass the target, which is then
// kept with the probability (target - volume so far)/its volume.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tsubu/core/size_distribution.hpp"
#include "tsubu/core/vec3.hpp"
#include "tsubu/search/sphere_grid.hpp"
#include "tsubu/world/domain.hpp"

namespace tsubu {

struct InflowColumn {
  double x_low = 0, y_low = 0, length_x = 0, length_y = 0;  // the base: the box's x-y extent, m
  double entry_height = 0;    // z_c, m
  double speed = 0;           // u_r, m/s (downwards)
  double solid_fraction = 0;  // phi_0
  SizeDistribution sizes;
  double density = 0;         // rho_p, kg/m^3
  double mass_limit = 0;      // kg; 0: none
  double omega_star_rms = 0;  // Omega*_rms = d omega_rms / (2 u_r); 0: no spin
  double gravity = 0;         // |g|, m/s^2, for t_f

  double area() const { return length_x * length_y; }
  double mass_flux() const;          // F = rho_p phi_0 L^2 u_r (paper Eq. 25), kg/s
  double grains_per_second() const;  // F / (rho_p pi/6 E[d^3])
  double free_fall_time() const;     // t_f = sqrt(L/g), L = sqrt(area); 0 without gravity
  double flux_number() const;        // Q = F t_f, kg (spec section 2)
  // The slab height H: at least 4 d_max and about 50 grains; a slab is built with the band
  // above it, about (H + 2 d_max) phi_0 L^2 / E[pi/6 d^3] grains (slab_grains).
  double slab_height() const;
  double slab_grains() const;
};

// A grain released by the column.
struct NewGrain {
  std::int64_t serial = 0;  // 0, 1, 2, ... in the order of release (of arrival)
  double diameter = 0;      // m
  double x = 0, y = 0;      // m
  double arrival = 0;       // s: its centre is at z_c then (for a delayed grain: the time of its retry)
  Vec3 omega;               // rad/s
  std::int32_t delays = 0;  // times it could not enter
};

class InflowStream {
 public:
  // Everything that changes as grains are released; restore(state()) continues bit-identically.
  struct State {
    std::int64_t slab = 0;  // the slab being released
    std::int64_t next = 0;  // its next grain, in order of arrival
    std::int64_t released = 0;
    double mass_released = 0;    // kg
    bool limit_reached = false;  // the mass limit stopped the column
    std::int64_t delays = 0;     // grains turned back at the entry plane, counted each time
    std::int64_t delayed_grains = 0;  // grains turned back at least once
    std::vector<NewGrain> waiting;    // turned back, to retry
  };

  InflowStream(const InflowColumn& column, std::uint64_t seed);

  const InflowColumn& column() const { return column_; }

  // The grains due by time t: first those waiting at the entry plane (their arrival set to t),
  // then the column's grains with t_arr <= t in order of arrival, while the mass released stays
  // within the limit. The caller inserts each at position(g, t) or gives it back with delay().
  std::vector<NewGrain> due(double t);
  // A grain of due() that cannot enter now: it waits at the entry plane for the next due().
  void delay(NewGrain g);

  Vec3 position(const NewGrain& g, double t) const {
    return {g.x, g.y, column_.entry_height - column_.speed * (t - g.arrival)};
  }
  Vec3 velocity() const { return {0, 0, -column_.speed}; }
  double density() const { return column_.density; }
  // The column enters through its plane whatever walls stand there.
  bool clear_of_walls(const Vec3&, double, std::span<const Wall>) const { return true; }
  // entry_neighbours for the grains `due` at t.
  SphereGrid neighbours(const Domain& domain, std::span<const Vec3> position, std::span<const double> radius,
                        const std::vector<NewGrain>& due, double t) const;

  // The mass limit has stopped the column and no grain is waiting.
  bool exhausted() const { return state_.limit_reached && state_.waiting.empty(); }
  // Grains generated and not yet released: at most one slab.
  std::size_t buffered() const { return slab_.size() - static_cast<std::size_t>(state_.next); }
  double slab_height() const { return slab_height_; }

  const State& state() const { return state_; }
  void restore(const State& s);

 private:
  struct Placed {
    double diameter, x, y, height;  // height above z_c in the column, m
    Vec3 omega;
  };
  InflowColumn column_;
  std::uint64_t seed_;
  double slab_height_, band_;  // H and h
  State state_;
  std::vector<Placed> slab_;   // the current slab, in order of arrival

  std::vector<Placed> slab(std::int64_t k) const;
  std::vector<Placed> band(std::int64_t k) const;
  void fill(std::uint64_t region, double lo, double hi, SphereGrid& grid, std::vector<Placed>& out) const;
};

// Named values for run.json and `tsubu check` (units in docs/sedimentation.md): the column's
// inflow_F (kg/s), inflow_grains_per_s, inflow_phi_0, inflow_Q, inflow_t_f (s), inflow_u_r
// (m/s) and inflow_z_c (m); and the stream's inflow_released, inflow_mass_released (kg),
// inflow_delays, inflow_delayed_grains and inflow_waiting.
std::vector<std::pair<std::string, double>> inflow_rates(const InflowColumn& c);
std::vector<std::pair<std::string, double>> inflow_counts(const InflowStream::State& s);

// The stream's state as bytes (native byte order, like the checkpoint) and back; decoding
// throws std::runtime_error on bytes that are not a whole state.
std::string encode_inflow_state(const InflowStream::State& s);
InflowStream::State decode_inflow_state(std::string_view bytes);

// The particles that an entering grain could overlap: those reaching above
// lowest - entering_radius, where `lowest` is the lowest centre height of the grains about to
// enter and `entering_radius` their largest radius. Ask overlaps(x, r) for each grain and
// add() each one inserted; the domain gives the periodic sides.
SphereGrid entry_neighbours(const Domain& domain, std::span<const Vec3> position, std::span<const double> radius,
                            double lowest, double entering_radius);

}  // namespace tsubu
