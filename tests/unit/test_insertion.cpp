// Insertion regions (source = "insertion", docs/scenario.md; source/insertion.hpp): grains
// due at the mass rate, or all at once up to the total; places inside the box or cylinder
// region, a radius in from its edge; reproducible, and a stream restored from another's
// state goes on as it; a crowded region delays grains and never drops or overlaps them, nor
// places one within its radius of a wall; the bin of tests/scenarios/insertion_bin.toml
// fills with the same bits on 1 and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scenario_run.hpp"
#include "tsubu/app/observed_run.hpp"
#include "tsubu/source/admission.hpp"
#include "tsubu/source/insertion.hpp"

namespace tsubu {
namespace {

constexpr double kDensity = 2500;

Insertion box_insertion(double mass_rate, double mass_limit) {
  Insertion i;
  i.region.shape = InsertionRegion::Shape::box;
  i.region.lower = {0, 0, 0.05};
  i.region.upper = {0.04, 0.04, 0.08};
  i.sizes.kind = SizeDistribution::Kind::uniform;
  i.sizes.d_min = 0.002;
  i.sizes.d_max = 0.004;
  i.density = kDensity;
  i.mass_rate = mass_rate;
  i.mass_limit = mass_limit;
  i.start = 0.1;
  i.velocity = {0, 0, -0.5};
  return i;
}

double mass_of(const NewGrain& g) { return kDensity * M_PI / 6 * std::pow(g.diameter, 3); }

// Grain j is due at start + (the mass before it) / rate: by time t the mass released is the
// rate times (t - start), less than one grain short of it.
TEST(Insertion, GrainsAreDueAtTheMassRate) {
  const double rate = 0.05, largest = kDensity * M_PI / 6 * std::pow(0.004, 3);
  InsertionStream s(box_insertion(rate, 0), 3);
  EXPECT_TRUE(s.due(0.0999).empty());  // nothing before start
  double mass = 0;
  for (double t = 0.1; t < 0.6; t += 0.01) {
    for (const NewGrain& g : s.due(t)) {
      EXPECT_LE(g.arrival, t);
      mass += mass_of(g);
    }
    EXPECT_LE(mass - rate * (t - 0.1), largest + 1e-15) << "t = " << t;
    EXPECT_GE(mass - rate * (t - 0.1), 0) << "t = " << t;
  }
  EXPECT_NEAR(mass, s.state().mass_released, 1e-15);
  EXPECT_FALSE(s.exhausted());  // no limit
}

// Without a rate the whole total is due at start: released mass within one grain of it,
// never above; then the source has ended.
TEST(Insertion, WithoutARateTheTotalIsDueAtOnce) {
  const double total = 0.01, largest = kDensity * M_PI / 6 * std::pow(0.004, 3);
  InsertionStream s(box_insertion(0, total), 5);
  EXPECT_TRUE(s.due(0.05).empty());
  const std::vector<NewGrain> all = s.due(0.1);
  double mass = 0;
  for (const NewGrain& g : all) mass += mass_of(g);
  std::printf("%zu grains due at start, %.6g kg of %.6g\n", all.size(), mass, total);
  EXPECT_LE(mass, total);
  EXPECT_GT(mass, total - largest);
  EXPECT_TRUE(s.due(1.0).empty());
  EXPECT_TRUE(s.exhausted());
}

// Every try's place is inside the region with the grain's radius to spare: a box, and a
// cylinder about a slanted axis; the places spread over the whole region.
TEST(Insertion, PlacesLieInsideTheRegionARadiusFromItsEdge) {
  Insertion box = box_insertion(0, 0.05), cylinder = box;
  cylinder.region.shape = InsertionRegion::Shape::cylinder;
  cylinder.region.point = {0.01, 0.02, 0.03};
  cylinder.region.axis = Vec3{1, 1, 2} / std::sqrt(6.0);
  cylinder.region.radius = 0.01;
  cylinder.region.length = 0.03;
  for (const Insertion& i : {box, cylinder}) {
    InsertionStream s(i, 9);
    double widest = 0;
    for (NewGrain g : s.due(0.1))
      for (int attempt = 0; attempt < 3; ++attempt, ++g.delays) {
        const Vec3 x = s.position(g, 0.1);
        const double r = 0.5 * g.diameter;
        if (i.region.shape == InsertionRegion::Shape::box) {
          for (int k = 0; k < 3; ++k) {
            EXPECT_GE(x[k] - r, i.region.lower[k]);
            EXPECT_LE(x[k] + r, i.region.upper[k]);
          }
          widest = std::max(widest, x.x - i.region.lower.x);
        } else {
          const Vec3 rel = x - i.region.point;
          const double along = dot(rel, i.region.axis), off = norm(rel - along * i.region.axis);
          EXPECT_GE(along, r);
          EXPECT_LE(along, i.region.length - r);
          EXPECT_LE(off, i.region.radius - r + 1e-15);
          widest = std::max(widest, off / i.region.radius);
        }
      }
    EXPECT_GT(widest, i.region.shape == InsertionRegion::Shape::box ? 0.035 : 0.75);
  }
}

// The same seed gives the same grains and places; a stream restored from another's state
// (encoded as a checkpoint holds it) goes on with the same grains, places and counts.
TEST(Insertion, IsReproducibleAndResumesFromItsState) {
  InsertionStream a(box_insertion(0.05, 0), 11), b(box_insertion(0.05, 0), 11);
  for (double t = 0.1; t < 0.2; t += 0.01) {
    const std::vector<NewGrain> ga = a.due(t), gb = b.due(t);
    ASSERT_EQ(ga.size(), gb.size());
    for (std::size_t k = 0; k < ga.size(); ++k) {
      EXPECT_EQ(ga[k].diameter, gb[k].diameter);
      EXPECT_EQ(a.position(ga[k], t), b.position(gb[k], t));
      if (k % 3 == 0) a.delay(ga[k]), b.delay(gb[k]);
    }
  }
  InsertionStream restored(box_insertion(0.05, 0), 11);
  restored.restore(decode_inflow_state(encode_inflow_state(a.state())));
  for (double t = 0.2; t < 0.3; t += 0.01) {
    const std::vector<NewGrain> ga = a.due(t), gr = restored.due(t);
    ASSERT_EQ(ga.size(), gr.size());
    for (std::size_t k = 0; k < ga.size(); ++k) {
      EXPECT_EQ(ga[k].serial, gr[k].serial);
      EXPECT_EQ(ga[k].diameter, gr[k].diameter);
      EXPECT_EQ(a.position(ga[k], t), restored.position(gr[k], t));
    }
  }
  EXPECT_EQ(encode_inflow_state(a.state()), encode_inflow_state(restored.state()));
  InsertionStream::State bad = a.state();
  bad.next = bad.released + 1;
  EXPECT_THROW(restored.restore(bad), std::runtime_error);
}

// More grains than the region holds at once, all due at start, with a wall cutting through
// the region: those whose place is taken wait, counted; as the grains already in are carried
// away (moved down out of the region, as falling grains are), the waiting ones enter. None is
// dropped, none overlaps another, none stands within its radius of the wall.
TEST(Insertion, ACrowdedRegionDelaysGrainsWithoutDroppingOrOverlapping) {
  Insertion i = box_insertion(0, 0.2);  // about 4000 grains into a region that holds some hundreds at a time
  InsertionStream s(i, 13);
  const Domain domain{{0, 0, -10}, {0.04, 0.04, 0.1}, {false, false, false}};
  Wall wall;  // a slanted plane through the region: the particles on the side of +x
  wall.point = {0.015, 0, 0.06};
  wall.normal = Vec3{1, 0, 0.5} / std::sqrt(1.25);
  const std::vector<Wall> walls = {wall};
  Particles p;
  std::size_t entered = 0, delayed = 0;
  int calls = 0;
  for (double t = 0.1; !s.exhausted() && calls < 2000; t += 1e-3, ++calls) {
    for (Vec3& x : p.position) x.z -= 0.1;  // out of the region, out of each other's way
    const Admission a = admit_due(s, t, domain, p, 0, 0, walls);
    entered += a.entered, delayed += a.delayed;
    if (calls == 0) EXPECT_GT(a.delayed, 100u);
    for (std::size_t k = p.size() - a.entered; k < p.size(); ++k)
      EXPECT_GE(wall.touch(p.position[k]).distance, p.radius[k]);
  }
  std::printf("%zu grains entered in %d calls, %zu delays (%lld grains delayed)\n", entered, calls, delayed,
              static_cast<long long>(s.state().delayed_grains));
  EXPECT_TRUE(s.exhausted());
  EXPECT_EQ(entered, static_cast<std::size_t>(s.state().released));
  EXPECT_EQ(delayed, static_cast<std::size_t>(s.state().delays));
  std::vector<std::int64_t> ids = p.id;
  std::sort(ids.begin(), ids.end());
  for (std::size_t k = 0; k < ids.size(); ++k) ASSERT_EQ(ids[k], static_cast<std::int64_t>(k));
  // Grains entered at one call stand side by side at the same height band: none overlaps.
  for (std::size_t a = 0; a < p.size(); ++a)
    for (std::size_t b = a + 1; b < p.size(); ++b)
      if (std::abs(p.position[a].z - p.position[b].z) < 0.01) ASSERT_GE(norm(p.position[a] - p.position[b]), p.radius[a] + p.radius[b]);
}

// The bin of tests/scenarios/insertion_bin.toml, filled for 0.15 s: 1 and 2 threads give the
// same bits (the spatial sort on).
TEST(Insertion, TheBinFillsWithTheSameBitsForOneAndTwoThreads) {
  const Scenario sc = testing::test_scenario("insertion_bin.toml", {"simulation.duration=0.15", "search.sort_every=100"});
  const World one = testing::run_scenario(sc, 1), two = testing::run_scenario(sc, 2);
  std::printf("%zu grains in the bin\n", one.particles.size());
  EXPECT_GT(one.particles.size(), 100u);
  EXPECT_TRUE(testing::same_particle_bits(one, two));
}

// Not yet in a run split among processes: refused before the split, naming the source.
TEST(Insertion, ASplitRunIsRefused) {
  const Scenario sc = testing::test_scenario("insertion_bin.toml");
  try {
    refuse_what_cannot_split(sc, 2);
    FAIL() << "a split insertion was not refused";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("particles[0].source = \"insertion\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tsubu
