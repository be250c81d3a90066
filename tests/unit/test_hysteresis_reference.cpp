// Model HH against LIGGGHTS 3.8 step by step: every case of validation/hysteresis/cases.csv
// is run through the full engine (contact search, force field, velocity Verlet, moving walls)
// with the same kinematics as make_reference.py gave LIGGGHTS, and the per-step overlap,
// normal force and state of sphere 1 are compared with reference/<case>.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "world_builder.hpp"

namespace tsubu {
namespace {

namespace fs = std::filesystem;
const fs::path kDir = fs::path(TSUBU_SOURCE_DIR) / "validation" / "hysteresis";

using Row = std::map<std::string, std::string>;

// Reads a CSV with a header line; lines starting with '#' are skipped. Empty trailing
// fields are kept as empty strings.
std::vector<Row> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::vector<Row> rows;
  std::vector<std::string> header;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    if (header.empty()) {
      header = cells;
      continue;
    }
    Row r;
    for (std::size_t k = 0; k < header.size(); ++k) r[header[k]] = k < cells.size() ? cells[k] : "";
    rows.push_back(r);
  }
  return rows;
}

double num(const Row& r, const std::string& key) { return std::stod(r.at(key)); }

std::vector<WallMotion> motion_of(const std::string& text, double dt) {
  std::vector<WallMotion> out;
  std::stringstream ss(text);
  for (std::string part; ss >> part;) {
    const auto colon = part.find(':');
    out.push_back({std::stod(part.substr(0, colon)) * dt, {0, 0, std::stod(part.substr(colon + 1))}});
  }
  return out;
}

// What one step of tsubu gives, in the columns of the reference files.
struct Sample {
  double overlap = 0, overlap2 = 0, fn = 0;
  Vec3 x, v, f, w;
};

// Largest differences of one quantity over a case: relative where the reference is at least
// 1e-3 of its peak, and relative to the peak everywhere (zero crossings).
struct Diff {
  double peak = 0, rel = 0, scaled = 0;
  std::vector<std::pair<double, double>> pairs;
  void add(double ours, double ref) { pairs.emplace_back(ours, ref), peak = std::max(peak, std::abs(ref)); }
  void finish() {
    for (auto [a, b] : pairs) {
      if (peak == 0) break;
      scaled = std::max(scaled, std::abs(a - b) / peak);
      if (std::abs(b) >= 1e-3 * peak) rel = std::max(rel, std::abs(a - b) / std::abs(b));
    }
  }
};

struct CaseResult {
  Diff overlap, fn, position, velocity, force, omega;
  std::set<HookeHysteresis::Branch> branches;
  bool same_contact_state = true;
  std::size_t steps = 0;
};

CaseResult run_case(const Row& c) {
  const std::string geometry = c.at("geometry");
  const double dt = num(c, "dt"), d = num(c, "diameter"), r = 0.5 * d, rho = num(c, "density");
  const double gap = num(c, "gap"), vn = num(c, "vn"), vt = num(c, "vt");
  const Material m{"grain", rho, num(c, "youngs_modulus"), num(c, "poisson")};
  ContactSpec spec = testing::spec_of("hooke_hysteresis", "linear_coulomb", num(c, "restitution"), num(c, "friction"));
  for (const char* key : {"characteristic_velocity", "max_stiffness_ratio", "adhesion_stiffness_ratio", "plasticity_depth"})
    spec.values.set(key, num(c, key));
  spec.values.set("tangential_damping", c.at("tangential_damping") == "1");
  auto [w, model] = testing::make_world(m, spec, dt);
  Particles& p = w.particles;
  const std::vector<WallMotion> motion = motion_of(c.at("motion"), dt);
  if (geometry == "pair") {
    p.add(1, 0, d, rho, {-(r + gap / 2), 0, 0}, {vn / 2, vt / 2, 0});
    p.add(2, 0, d, rho, {r + gap / 2, 0, 0}, {-vn / 2, -vt / 2, 0});
  } else if (geometry == "wall") {
    p.add(1, 0, d, rho, {0, 0, r + gap}, {vt, 0, -vn});
    w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0});
  } else if (geometry == "driven") {
    p.add(1, 0, d, rho, {-(2 * r + gap), 0, 0}, {});
    p.add(2, 0, d, rho, {0, 0, 0}, {});
  } else {  // piston
    p.add(1, 0, d, rho, {0.002, -0.003, r + gap / 2}, {});
    w.walls.push_back({{0, 0, 0}, {0, 0, 1}, 0});
    Wall plate{{0, 0, 2 * r + gap}, {0, 0, -1}, 0};
    plate.motion = motion;
    w.walls.push_back(plate);
  }
  const auto& hh = std::get<HookeHysteresis>(model.laws.at(0, 0).normal);

  CaseResult res;
  ForceField f(model);
  f.compute(w);
  auto sample = [&] {
    Sample s;
    s.x = p.position[0], s.v = p.velocity[0], s.f = p.force[0], s.w = p.omega[0];
    if (geometry == "pair" || geometry == "driven") {
      const Vec3 dx = p.position[0] - p.position[1];
      s.overlap = 2 * r - norm(dx);
      s.fn = dot(p.force[0], dx / norm(dx));
    } else {
      s.overlap = r - p.position[0].z;
      s.fn = p.force[0].z;
      if (geometry == "piston") s.overlap2 = r - (w.walls[1].point.z - p.position[0].z);
    }
    return s;
  };
  // The branch each touching contact takes in this step, from its history before the step.
  auto record_branches = [&](const std::vector<Contact>& before, const std::vector<Contact>& after, bool wall) {
    for (std::size_t k = 0; k < after.size() && k < before.size(); ++k) {
      if (!after[k].touching) continue;
      const std::size_t i = after[k].i;
      double delta = 0, r_eff = 0, m_eff = 0;
      if (wall) {
        delta = r - w.walls[after[k].j].distance(p.position[i]);
        r_eff = r, m_eff = p.mass[i];
      } else {
        delta = 2 * r - norm(p.position[after[k].i] - p.position[after[k].j]);
        r_eff = r / 2, m_eff = p.mass[0] / 2;
      }
      double h = before[k].touching ? before[k].history.normal[0] : 0.0;
      HookeHysteresis::Branch b;
      hh.hysteresis(hh.k_n(r_eff, m_eff), r_eff, delta, h, &b);
      res.branches.insert(b);
    }
  };

  const std::vector<Row> ref = read_csv(kDir / "reference" / (c.at("name") + ".csv"));
  for (const Row& row : ref) {
    const auto step = static_cast<std::int64_t>(num(row, "step"));
    if (step > 0) {
      const auto pairs_before = w.contacts.pairs();
      const auto walls_before = w.contacts.walls();
      if (geometry == "driven") {
        // Both spheres are moved, not integrated (LIGGGHTS fix move): x += v dt with the
        // prescribed velocity of this step; sphere 2 is held at rest.
        const double t_mid = (static_cast<double>(step) - 0.5) * dt;
        double v = 0;
        for (const WallMotion& s : motion)
          if (t_mid < s.until) {
            v = s.velocity.z;
            break;
          }
        p.velocity[0] = {v, 0, 0};
        p.position[0] += p.velocity[0] * dt;
        ++w.step;
        w.time = static_cast<double>(w.step) * dt;
        f.compute(w);
      } else {
        velocity_verlet_step(w, testing::evaluation(f, w));
      }
      // The lists are rebuilt only between steps of the same contacts here (one or two
      // spheres never move a skin apart within a case), so entry k is the same contact.
      if (pairs_before.size() == w.contacts.pairs().size()) record_branches(pairs_before, w.contacts.pairs(), false);
      if (walls_before.size() == w.contacts.walls().size()) record_branches(walls_before, w.contacts.walls(), true);
    }
    const Sample s = sample();
    res.overlap.add(s.overlap, num(row, "overlap"));
    if (geometry == "piston") res.overlap.add(s.overlap2, num(row, "overlap2"));
    res.fn.add(s.fn, num(row, "fn"));
    const Vec3 x{num(row, "x"), num(row, "y"), num(row, "z")}, v{num(row, "vx"), num(row, "vy"), num(row, "vz")};
    const Vec3 fo{num(row, "fx"), num(row, "fy"), num(row, "fz")}, om{num(row, "wx"), num(row, "wy"), num(row, "wz")};
    for (int k = 0; k < 3; ++k) {
      res.position.add(s.x[k], x[k]);
      res.velocity.add(s.v[k], v[k]);
      res.force.add(s.f[k], fo[k]);
      res.omega.add(s.w[k], om[k]);
    }
    if ((s.overlap > 0) != (num(row, "overlap") > 0)) res.same_contact_state = false;
    ++res.steps;
  }
  for (Diff* dd : {&res.overlap, &res.fn, &res.position, &res.velocity, &res.force, &res.omega}) dd->finish();
  return res;
}

class HysteresisReference : public ::testing::TestWithParam<std::string> {};

Row case_named(const std::string& name) {
  for (const Row& r : read_csv(kDir / "cases.csv"))
    if (r.at("name") == name) return r;
  ADD_FAILURE() << "no case " << name;
  return {};
}

TEST_P(HysteresisReference, MatchesLiggghtsStepByStep) {
  const Row c = case_named(GetParam());
  const CaseResult res = run_case(c);
  ASSERT_GT(res.steps, 100u);
  EXPECT_TRUE(res.same_contact_state);
  std::printf("%-22s overlap rel %.2e (scaled %.2e)  fn rel %.2e (scaled %.2e)  x %.1e v %.1e f %.1e w %.1e\n",
              GetParam().c_str(), res.overlap.rel, res.overlap.scaled, res.fn.rel, res.fn.scaled, res.position.scaled,
              res.velocity.scaled, res.force.scaled, res.omega.scaled);
  EXPECT_LE(res.overlap.rel, 1e-6);
  EXPECT_LE(res.overlap.scaled, 1e-6);
  EXPECT_LE(res.fn.rel, 1e-6);
  EXPECT_LE(res.fn.scaled, 1e-6);
  EXPECT_LE(res.position.scaled, 1e-9);
  EXPECT_LE(res.velocity.scaled, 1e-6);
  EXPECT_LE(res.force.scaled, 1e-6);
  EXPECT_LE(res.omega.scaled, 1e-6);
}

std::vector<std::string> case_names() {
  std::vector<std::string> names;
  for (const Row& r : read_csv(kDir / "cases.csv")) names.push_back(r.at("name"));
  return names;
}

INSTANTIATE_TEST_SUITE_P(Cases, HysteresisReference, ::testing::ValuesIn(case_names()),
                         [](const auto& info) { return info.param; });

// Together the cases visit every branch of the law, and the ones the issue names.
TEST(HysteresisReferenceCoverage, EveryBranchIsVisited) {
  using B = HookeHysteresis::Branch;
  std::set<B> all;
  bool reload_after_adhesion = false;
  for (const std::string& name : case_names()) {
    const CaseResult res = run_case(case_named(name));
    all.insert(res.branches.begin(), res.branches.end());
    if (name == "driven_reload") reload_after_adhesion = res.branches.count(B::adhesive) && res.branches.count(B::virgin);
  }
  EXPECT_TRUE(all.count(B::virgin));
  EXPECT_TRUE(all.count(B::unload_reload));
  EXPECT_TRUE(all.count(B::beyond_limit));
  EXPECT_TRUE(all.count(B::adhesive));
  EXPECT_TRUE(reload_after_adhesion);
}

}  // namespace
}  // namespace tsubu
