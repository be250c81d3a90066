// No input can hang the loader or pass `check` and fail at step 0 (docs/reliability.md):
// bounded loops for any size, the initial overlap check on a grid (O(N) memory, stops at
// the first offence), the CSV dialects spreadsheets write. The refused scenarios themselves
// are in tests/bad_scenarios/.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "tsubu/core/error.hpp"
#include "tsubu/core/size_distribution.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/search/pair_search.hpp"
#include "tsubu/source/build_world.hpp"
#include "tsubu/source/sources.hpp"

namespace tsubu {
namespace {

namespace fs = std::filesystem;

// A scenario of one CSV source in a 1 m box, periodic in x and y.
Scenario csv_scenario(const fs::path& csv) {
  const std::string text = R"([simulation]
duration = 0.01
dt = 1e-5
[domain]
lower = [0, 0, 0]
upper = [1, 1, 1]
periodic = ["x", "y"]
[[materials]]
name = "glass"
density = 2500
youngs_modulus = 1e7
poisson = 0.3
[[particles]]
source = "csv"
material = "glass"
file = ")" + csv.string() + "\"\n";
  return load_scenario_text(text, "grid.toml", {}, true);
}

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".csv");
}

}  // namespace

// The sizing loop of the grid multiplied a cell size of 5e-324 by 1.25 forever.
TEST(GridCells, AnyCellSizeEndsTheSizingLoop) {
  const double extent[3] = {0.01, 0.01, 0.03};
  for (double size : {5e-324, 0.0, std::nan(""), 1e-300, 0.001}) {
    int cells[3];
    double length[3];
    grid_cells(extent, size, 1000, cells, length);
    EXPECT_LE(static_cast<double>(cells[0]) * cells[1] * cells[2], 4.0 * 1000 + 27) << size;
  }
}

// The rejection loop of a bounded lognormal ends even when (against the loader's check) the
// bounds keep almost nothing; the loader refuses such bounds with a reason.
TEST(SizeDistribution, LognormalRejectionIsBounded) {
  SizeDistribution d;
  d.kind = SizeDistribution::Kind::lognormal;
  d.median = 1.5;  // in mm by mistake
  d.sigma = 0.2;
  d.d_max = 0.003;
  EXPECT_LT(d.acceptance(), 1e-200);
  Random rng(1);
  EXPECT_THROW(d.sample(rng), std::runtime_error);
  d.median = 0.0015;
  EXPECT_NEAR(d.acceptance(), 1.0, 1e-3);
}

// The issue's unit slip: 50,000 rows in mm overlap each other; the first offence (row 2 of
// the data, line 3) is reported at once instead of after listing every pair (2.5e9 of them).
TEST(OverlapCheck, AUnitSlipIsReportedAtTheFirstOffence) {
  const fs::path csv = temp_file("tsubu_unit_slip");
  {
    std::ofstream f(csv);
    f << "x,y,z,d\n";
    for (int k = 0; k < 50000; ++k) f << 0.5 + 1e-6 * (k % 100) << ",0.5," << 0.1 + 1e-5 * k << ",0.1\n";
  }
  try {
    build_world(csv_scenario(csv));
    ADD_FAILURE() << "overlapping particles accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(csv.string() + ":3: particle overlaps the one from " + csv.string() + ":2"),
              std::string::npos)
        << e.what();
  }
  fs::remove(csv);
}

// 50,000 particles that only touch on a lattice: every one is checked against its
// neighbours in O(N) (a million take about 5 s, docs/reliability.md).
TEST(OverlapCheck, ALargeTouchingPackingIsAccepted) {
  const fs::path csv = temp_file("tsubu_lattice");
  {
    std::ofstream f(csv);
    f << std::setprecision(17);
    const int n = 37;  // 37^3 = 50,653
    const double d = 1.0 / n;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) f << (i + 0.5) * d << ',' << (j + 0.5) * d << ',' << (k + 0.5) * d << ',' << d << '\n';
  }
  const auto start = std::chrono::steady_clock::now();
  const World w = build_world(csv_scenario(csv));
  std::printf("%zu particles checked in %.2f s\n", w.particles.size(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  EXPECT_EQ(w.particles.size(), 37u * 37 * 37);
  fs::remove(csv);
}

// As spreadsheets write CSV: a byte-order mark, an upper-case header, tabs, a leading '+'.
TEST(CsvSource, SpreadsheetDialectsAreAccepted) {
  std::istringstream in("\xEF\xBB\xBFX,Y,Z,D\r\n+0.1,0.2,0.3,+1e-3\r\n0.4\t0.5\t0.6\t0.002\n 0.7 ,\t0.8, 0.9 ,0.003\n");
  const auto grains = parse_csv_grains(in, "sheet.csv");
  ASSERT_EQ(grains.size(), 3u);
  EXPECT_EQ(grains[0].position.x, 0.1);
  EXPECT_EQ(grains[0].diameter, 1e-3);
  EXPECT_EQ(grains[1].position.y, 0.5);
  EXPECT_EQ(grains[2].position.y, 0.8);
  std::istringstream twice("1,2,3,+-4\n");
  EXPECT_THROW(parse_csv_grains(twice, "bad.csv"), InputError);
}

}  // namespace tsubu
