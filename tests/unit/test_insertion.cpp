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
#include <map>
#include <memory>

#include "mesh_plate.hpp"
#include "scenario_run.hpp"
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

// The distance of x from the nearest point of any of the mesh's triangles, by brute force.
double mesh_distance(const TriangleMesh& mesh, const Vec3& x) {
  double d = INFINITY;
  for (std::uint32_t t = 0; t < mesh.size(); ++t) d = std::min(d, norm(x - mesh.nearest(t, x).point));
  return d;
}

// A mesh's triangles where the wall has them now, in the box's frame (as vtk.cpp draws them).
TriangleMesh mesh_in_box(const Wall& w) {
  std::vector<Vec3> v;
  for (const Vec3& a : w.mesh->vertices()) v.push_back(w.from_mesh(a - w.axis_offset) + w.axis_offset + w.point);
  std::vector<std::array<std::uint32_t, 3>> t;
  for (std::size_t k = 0; k < w.mesh->size(); ++k) t.push_back(w.mesh->triangle(k));
  return TriangleMesh(v, t);
}

// A flat mesh of 800 triangles across the region (a plate of 80 mm, the region 40 mm wide),
// 0.05 kg due at once: the grains whose place is within their radius of a triangle wait and
// enter later, on both sides of the mesh (it is two-sided), and none stands within its
// radius of any triangle, by brute force over them all. Twice: the plate as read, and a plate
// that has moved (its `point`) and turns about a slanted axis (10 rad/s), kept clear of
// where it is at the time of each try.
TEST(Insertion, AMeshAcrossTheRegionIsKeptClearOfOnBothSides) {
  const Domain domain{{0, 0, -10}, {0.04, 0.04, 0.1}, {false, false, false}};
  const Vec3 middle{0.02, 0.02, 0.065};
  for (const bool turning : {false, true}) {
    InsertionStream s(box_insertion(0, 0.05), 17);
    Wall wall;
    wall.shape = WallShape::mesh;
    wall.mesh = std::make_shared<const TriangleMesh>(
        testing::plate(20, 0.004, [&](const Vec3& a) { return a - Vec3{0.04, 0.04, 0} + (turning ? Vec3{} : middle); }));
    if (turning) {
      wall.point = middle;
      wall.angular_velocity = Vec3{1, 2, 0} * (10 / std::sqrt(5.0));
      wall.axis_offset = {0.001, -0.002, 0};
    }
    Particles p;
    std::size_t entered = 0, delayed = 0, above = 0, below = 0;
    double closest = INFINITY;  // the smallest distance from the mesh over the radius
    int calls = 0;
    for (double t = 0.1; !s.exhausted() && calls < 2000; t += 1e-3, ++calls) {
      for (Vec3& x : p.position) x.z -= 0.1;  // out of the region, out of each other's way
      wall.turn_to(t);
      const Admission a = admit_due(s, t, domain, p, 0, 0, std::vector<Wall>{wall});
      entered += a.entered, delayed += a.delayed;
      if (calls == 0) {
        EXPECT_GT(a.delayed, 100u);
        EXPECT_GT(a.entered, 100u);
      }
      const TriangleMesh now = mesh_in_box(wall);  // flat: one plane
      for (std::size_t k = p.size() - a.entered; k < p.size(); ++k) {
        const double d = mesh_distance(now, p.position[k]);
        closest = std::min(closest, d / p.radius[k]);
        ASSERT_GE(d, p.radius[k]) << "grain " << p.id[k] << (turning ? ", turning mesh" : "");
        ++(dot(p.position[k] - now.vertices()[0], now.normal(0)) > 0 ? above : below);
      }
    }
    std::printf("%s: %zu grains entered in %d calls (%zu above, %zu below the mesh), %zu delays; closest %.4g radii from it\n",
                turning ? "moved and turning" : "as read", entered, calls, above, below, delayed, closest);
    EXPECT_TRUE(s.exhausted());
    EXPECT_EQ(entered, static_cast<std::size_t>(s.state().released));
    EXPECT_EQ(delayed, static_cast<std::size_t>(s.state().delays));
    EXPECT_GT(above, 100u);
    EXPECT_GT(below, 100u);
    EXPECT_LT(closest, 1.05);  // grains are placed right up to the mesh
  }
}

// The square hopper of tests/scenarios/insertion_mesh.toml filled from a region that reaches
// into its sloping faces: every grain placed at least its radius from every triangle (checked
// as it enters, by brute force), those that could not be placed at once placed later, and the
// run goes on past its start without an overlap; 1 and 2 threads give the same bits.
TEST(Insertion, TheMeshHopperFillsFromARegionAcrossItsFaces) {
  const Scenario sc = testing::test_scenario("insertion_mesh.toml", {"search.sort_every=100"});
  omp_set_num_threads(1);
  Simulation sim = new_simulation(sc);
  sim.start();
  const Wall& hopper = sim.world().walls[0];
  ASSERT_TRUE(hopper.mesh);
  std::size_t seen = 0;
  double closest = INFINITY;
  auto check_new = [&] {
    const Particles& p = sim.world().particles;
    for (std::size_t k = seen; k < p.size(); ++k) {
      const double d = mesh_distance(*hopper.mesh, hopper.to_mesh(p.position[k]));
      closest = std::min(closest, d / p.radius[k]);
      ASSERT_GE(d, p.radius[k]) << "grain " << p.id[k] << " at step " << sim.world().step;
    }
    seen = p.size();
  };
  check_new();
  const std::size_t at_once = seen;
  const std::int64_t steps = std::llround(sc.duration / sc.dt);
  while (sim.world().step < steps) {
    sim.step();
    check_new();
  }
  std::map<std::string, double> results;
  for (const auto& [name, value] : sim.inflow()->results(sim.world().time, sim.inflow_mass_entered())) results[name] = value;
  std::printf("%zu grains placed at once, %zu in all; %g delays of %g grains; closest %.4g radii from the mesh\n", at_once,
              seen, results["inflow_delays"], results["inflow_delayed_grains"], closest);
  EXPECT_GT(at_once, 300u);
  EXPECT_GT(seen, at_once);
  EXPECT_GT(results["inflow_delayed_grains"], 100);
  EXPECT_EQ(results["inflow_waiting"], 0);
  EXPECT_TRUE(sim.inflow()->ended());
  EXPECT_LT(closest, 1.05);
  const World two = testing::run_scenario(sc, 2);
  EXPECT_TRUE(testing::same_particle_bits(sim.world(), two));
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

}  // namespace
}  // namespace tsubu
