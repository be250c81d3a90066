// The inflow stream (source/inflow.hpp): flux, no overlap in the virtual column (across slab
// boundaries and periodic sides), sizes, determinism, bit-identical save/restore, crowding.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "tsubu/source/admission.hpp"
#include "tsubu/source/inflow.hpp"
#include "tsubu/source/size_moments.hpp"

namespace tsubu {
namespace {

InflowColumn column(double phi0, const SizeDistribution& sizes) {
  InflowColumn c;
  c.x_low = -0.02;
  c.y_low = 0.01;
  c.length_x = c.length_y = 0.04;
  c.entry_height = 0.08;
  c.speed = 0.3;
  c.solid_fraction = phi0;
  c.sizes = sizes;
  c.density = 2650;
  c.gravity = 9.81;
  return c;
}

SizeDistribution single(double d) {
  SizeDistribution s;
  s.diameter = d;
  return s;
}

SizeDistribution talbot(double S, double Sigma) {
  SizeDistribution s;
  s.kind = SizeDistribution::Kind::talbot;
  s.exponent = S;
  s.d_max = 0.01;
  s.d_min = 0.01 * std::exp(-Sigma);
  return s;
}

// Every grain released up to time t, asking every dt.
std::vector<NewGrain> released(InflowStream& s, double t, double dt) {
  std::vector<NewGrain> all;
  for (double now = dt; now <= t; now += dt)
    for (const NewGrain& g : s.due(now)) all.push_back(g);
  return all;
}

bool same_bits(const NewGrain& a, const NewGrain& b) {
  return a.serial == b.serial && a.delays == b.delays &&
         std::memcmp(&a.diameter, &b.diameter, sizeof a.diameter) == 0 && std::memcmp(&a.x, &b.x, sizeof a.x) == 0 &&
         std::memcmp(&a.y, &b.y, sizeof a.y) == 0 && std::memcmp(&a.arrival, &b.arrival, sizeof a.arrival) == 0 &&
         std::memcmp(&a.omega, &b.omega, sizeof a.omega) == 0;
}

TEST(Inflow, ReportedRates) {
  const InflowColumn c = column(0.03, single(0.01));
  const double F = 2650 * 0.03 * 0.0016 * 0.3;  // rho_p phi_0 L^2 u_r
  EXPECT_NEAR(c.mass_flux(), F, 1e-15);
  EXPECT_NEAR(c.grains_per_second(), F / (2650 * M_PI / 6 * 1e-6), 1e-9);
  EXPECT_NEAR(c.flux_number(), F * std::sqrt(0.04 / 9.81), 1e-15);
  EXPECT_EQ(inflow_rates(c).front(), (std::pair<std::string, double>{"inflow_F", c.mass_flux()}));
}

TEST(Inflow, MeasuredMassFluxWithinTwoPercent) {
  for (const InflowColumn& c : {column(0.1, talbot(0, 2)), column(0.01, single(0.01))}) {
    InflowStream s(c, 5);
    const double window = 30000 / c.grains_per_second();  // about 30000 grains
    double mass = 0;
    for (const NewGrain& g : released(s, window, window / 1000)) mass += c.density * M_PI / 6 * std::pow(g.diameter, 3);
    EXPECT_NEAR(mass / window, c.mass_flux(), 0.02 * c.mass_flux()) << "phi_0 = " << c.solid_fraction;
    EXPECT_LT(s.buffered(), 2000u) << "the stream holds one slab, not the run's grains";
  }
}

TEST(Inflow, NoTwoGrainsOfTheColumnOverlap) {
  for (const InflowColumn& c : {column(0.3, single(0.01)), column(0.25, talbot(0, 2))}) {
    InflowStream s(c, 9);
    const double t = 6 * s.slab_height() / c.speed;  // six slabs: five boundaries
    const std::vector<NewGrain> g = released(s, t, t / 50);
    Domain frame{{c.x_low, c.y_low, 0}, {c.x_low + c.length_x, c.y_low + c.length_y, 1}, {true, true, false}};
    long across = 0;
    for (std::size_t i = 0; i < g.size(); ++i) {
      const Vec3 xi{g[i].x, g[i].y, g[i].arrival * c.speed};  // height above z_c
      ASSERT_GE(xi.z, 0);
      for (std::size_t j = i + 1; j < g.size(); ++j) {
        const Vec3 xj{g[j].x, g[j].y, g[j].arrival * c.speed};
        const double reach = 0.5 * (g[i].diameter + g[j].diameter);
        const double dist = norm(frame.separation(xi, xj));
        ASSERT_GE(dist, reach) << "grains " << i << " and " << j << " overlap";
        across += dist < 1.5 * reach && std::floor(xi.z / s.slab_height() + 0.5) != std::floor(xj.z / s.slab_height() + 0.5);
      }
    }
    EXPECT_GT(across, 10) << "near neighbours on both sides of the slab boundaries";
    // The column holds phi_0: the grains released by t fill t u_r L^2 to phi_0.
    double volume = 0;
    for (const NewGrain& x : g) volume += M_PI / 6 * std::pow(x.diameter, 3);
    EXPECT_NEAR(volume / (t * c.speed * c.area()), c.solid_fraction, 0.05 * c.solid_fraction);
  }
}

TEST(Inflow, SizesFollowTheRequestedDistribution) {
  const InflowColumn c = column(0.1, talbot(1, 2));
  InflowStream s(c, 3);
  const std::vector<NewGrain> g = released(s, 20000 / c.grains_per_second(), 0.01);
  double sum = 0;
  for (const NewGrain& x : g) sum += x.diameter;
  const double n = static_cast<double>(g.size());
  const double mean = mean_diameter_power(c.sizes, 1);
  const double sd = std::sqrt(mean_diameter_power(c.sizes, 2) - mean * mean);
  EXPECT_NEAR(sum / n, mean, 4 * sd / std::sqrt(n));
}

TEST(Inflow, InitialSpin) {
  InflowColumn c = column(0.1, single(0.01));
  c.omega_star_rms = 7.5e-3;
  InflowStream s(c, 4);
  const std::vector<NewGrain> g = released(s, 5000 / c.grains_per_second(), 0.01);
  double sum2 = 0;
  for (const NewGrain& x : g) sum2 += norm2(x.omega);
  const double rms = 2 * c.speed * c.omega_star_rms / 0.01;  // per component
  const double n = 3.0 * static_cast<double>(g.size());
  EXPECT_NEAR(std::sqrt(sum2 / n), rms, 4 * rms / std::sqrt(2 * n));
}

TEST(Inflow, SameSeedSameGrainsAndRestoredStreamContinuesBitIdentically) {
  const InflowColumn c = column(0.1, talbot(0, 2));
  InflowStream a(c, 21), b(c, 21), other(c, 22);
  const std::vector<NewGrain> first = released(a, 1.0, 0.003);
  const std::vector<NewGrain> again = released(b, 1.0, 0.003);
  ASSERT_EQ(first.size(), again.size());
  for (std::size_t k = 0; k < first.size(); ++k) ASSERT_TRUE(same_bits(first[k], again[k]));
  EXPECT_NE(released(other, 1.0, 0.003)[0].x, first[0].x);

  // Mid-slab, with a grain waiting at the entry plane: save, restore into a fresh stream.
  std::vector<NewGrain> due = a.due(1.001);
  ASSERT_FALSE(due.empty());
  a.delay(due.front());
  const std::string bytes = encode_inflow_state(a.state());
  InflowStream restored(c, 21);
  restored.restore(decode_inflow_state(bytes));
  EXPECT_EQ(encode_inflow_state(restored.state()), bytes);
  for (double t = 1.002; t < 3; t += 0.0037) {
    const std::vector<NewGrain> x = a.due(t), y = restored.due(t);
    ASSERT_EQ(x.size(), y.size()) << "t = " << t;
    for (std::size_t k = 0; k < x.size(); ++k) ASSERT_TRUE(same_bits(x[k], y[k])) << "t = " << t;
  }
  EXPECT_THROW(decode_inflow_state(bytes.substr(0, bytes.size() - 1)), std::runtime_error);
  InflowStream::State bad = restored.state();
  bad.next = 1 << 30;
  EXPECT_THROW(restored.restore(bad), std::runtime_error);
}

TEST(Inflow, MassLimitStopsTheColumn) {
  InflowColumn c = column(0.1, single(0.01));
  const double m = 2650 * M_PI / 6 * 1e-6;
  c.mass_limit = 10.5 * m;
  InflowStream s(c, 1);
  EXPECT_EQ(released(s, 100, 0.1).size(), 10u);
  EXPECT_TRUE(s.exhausted());
  EXPECT_LE(s.state().mass_released, c.mass_limit);
}

TEST(Inflow, EntryNeighboursAreWhatAnEnteringGrainCanTouch) {
  const Domain box{{0, 0, 0}, {0.04, 0.04, 0.1}, {true, true, false}};
  const std::vector<Vec3> x = {{0.001, 0.02, 0.075}, {0.02, 0.02, 0.02}};  // near the entry plane; deep in the box
  const std::vector<double> r = {0.005, 0.005};
  const SphereGrid near = entry_neighbours(box, x, r, 0.08, 0.005);
  EXPECT_EQ(near.size(), 1u);
  EXPECT_TRUE(near.overlaps({0.039, 0.02, 0.08}, 0.005));  // across the periodic x side
  EXPECT_FALSE(near.overlaps({0.02, 0.02, 0.08}, 0.005));
}

TEST(Inflow, CrowdedEntryDelaysGrainsWithoutDroppingOrOverlapping) {
  const InflowColumn c = column(0.1, single(0.01));
  InflowStream s(c, 8);
  Domain box{{c.x_low, c.y_low, 0}, {c.x_low + 0.04, c.y_low + 0.04, 0.1}, {true, true, false}};
  // Grains filling the box up to the entry plane: nothing can enter.
  Particles full;
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i)
        full.add(1000 + full.size(), 0, 0.01, 2650, {c.x_low + 0.005 + 0.01 * i, c.y_low + 0.005 + 0.01 * j, 0.005 + 0.01 * k}, {});
  const Admission blocked = admit_due(s, 0.1, box, full, 0, 0);
  ASSERT_GT(blocked.delayed, 3u);
  EXPECT_EQ(blocked.entered, 0u);
  EXPECT_EQ(s.state().delayed_grains, static_cast<std::int64_t>(blocked.delayed));
  EXPECT_EQ(s.state().waiting.size(), blocked.delayed);
  const Admission still = admit_due(s, 0.1005, box, full, 0, 0);  // the same grains, counted again
  EXPECT_EQ(s.state().delays, static_cast<std::int64_t>(blocked.delayed + still.delayed));
  EXPECT_EQ(inflow_counts(s.state())[2], (std::pair<std::string, double>{"inflow_delays", double(s.state().delays)}));
  // The box empties: the waiting grains enter at the entry plane as room appears (grains
  // inside fall at u_r), none lost, none overlapping.
  Particles p;
  const double dt = 0.002;
  std::size_t entered = 0;
  for (double t = 0.11; t < 0.3; t += dt) {
    for (Vec3& x : p.position) x.z -= c.speed * dt;
    entered += admit_due(s, t, box, p, 0, 0).entered;
  }
  EXPECT_TRUE(s.state().waiting.empty());
  EXPECT_EQ(entered, static_cast<std::size_t>(s.state().released));
  std::vector<std::int64_t> ids = p.id;  // first_id + serial: each grain once
  std::sort(ids.begin(), ids.end());
  for (std::size_t i = 0; i < ids.size(); ++i) EXPECT_EQ(ids[i], static_cast<std::int64_t>(i));
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(p.velocity[i].z, -c.speed);
    for (std::size_t j = i + 1; j < p.size(); ++j)
      EXPECT_GE(norm(box.separation(p.position[i], p.position[j])), p.radius[i] + p.radius[j]);
  }
}

}  // namespace
}  // namespace tsubu
