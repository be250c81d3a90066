// Round trip of the ParaView output through the real VTK readers: particles are written with
// write_vtu / PvdIndex, the same values go to a %.17g reference text, and tests/vtk_readback.py
// (run with Debian's /usr/bin/python3, which has python3-vtk9 and numpy) reads the files with
// VTK and requires every value to come back bit for bit.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "tsubu/io/vtk.hpp"
#include "tsubu/world/particles.hpp"

namespace fs = std::filesystem;
using tsubu::Particles;

namespace {

constexpr const char* kPython = "/usr/bin/python3";

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool python_has_vtk() {
  static const bool ok = run(std::string(kPython) + " -c 'import vtk, numpy' >/dev/null 2>&1") == 0;
  return ok;
}

#define SKIP_WITHOUT_PYTHON_VTK()                                                                       \
  if (!python_has_vtk())                                                                                \
  GTEST_SKIP() << kPython << " cannot 'import vtk, numpy' (install python3-vtk9 and python3-numpy); " \
                             "the VTK read-back is not checked"

// Checks a file with tests/vtk_readback.py; returns its exit code (0 = everything matched).
int readback(const std::string& args) {
  return run(std::string(kPython) + " '" TSUBU_SOURCE_DIR "/tests/vtk_readback.py' " + args);
}

// A fresh directory per test, removed when the test passes (kept for inspection otherwise).
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("tsubu_vtk_readback_" + std::string(info->name()) + "_" + std::to_string(getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    if (!::testing::Test::HasFailure()) fs::remove_all(path_);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

// Values that a decimal or single-precision detour would change, spread over all arrays.
double value(int k) {
  static const double special[] = {1.0 / 3.0, -2.0 / 7.0, M_PI, std::nextafter(1.0, 2.0), 0.1, -0.0, 1e-300,
                                   std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::max()};
  constexpr int n = sizeof special / sizeof special[0];
  return k % 4 == 0 ? special[(k / 4) % n] : std::sin(k) * std::pow(10.0, k % 9 - 4);
}

Particles make_particles(int n) {
  Particles p;
  int k = 0;
  auto next = [&k] { return tsubu::Vec3{value(k++), value(k++), value(k++)}; };
  for (int i = 0; i < n; ++i) {
    const double diameter = (1.0 / 3.0 + i) * 1e-3;
    const tsubu::Vec3 x = next(), v = next();
    p.add((std::int64_t{1} << 53) + 1 + 3 * i, i % 3, diameter, 2500.0, x, v);  // 2^53 + 1: not a double
    p.omega[i] = next();
    p.force[i] = next();
    p.contact_count[i] = i + 1 == n ? INT_MAX : 5 * i;
  }
  return p;
}

// The reference for vtk_readback.py: "NAME TYPE COMPONENTS TUPLES", then one tuple per line.
void write_reference(const std::string& path, const Particles& p) {
  FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_NE(f, nullptr) << path;
  const std::size_t n = p.size();
  auto vec = [&](const char* name, const std::vector<tsubu::Vec3>& a) {
    std::fprintf(f, "%s Float64 3 %zu\n", name, n);
    for (const auto& v : a) std::fprintf(f, "%.17g %.17g %.17g\n", v.x, v.y, v.z);
  };
  vec("Points", p.position);
  std::fprintf(f, "id Int64 1 %zu\n", n);
  for (auto id : p.id) std::fprintf(f, "%lld\n", static_cast<long long>(id));
  std::fprintf(f, "material Int32 1 %zu\n", n);
  for (int m : p.material) std::fprintf(f, "%d\n", m);
  std::fprintf(f, "diameter Float64 1 %zu\n", n);
  for (double r : p.radius) std::fprintf(f, "%.17g\n", 2 * r);
  vec("velocity", p.velocity);
  vec("angular_velocity", p.omega);
  vec("force", p.force);
  std::fprintf(f, "contact_count Int32 1 %zu\n", n);
  for (int c : p.contact_count) std::fprintf(f, "%d\n", c);
  std::fclose(f);
}

void expect_round_trip(int n) {
  TempDir dir;
  const Particles p = make_particles(n);
  const std::string vtu = dir.file("frame.vtu"), ref = dir.file("frame.ref");
  tsubu::write_vtu(vtu, p, 0.25);
  write_reference(ref, p);
  EXPECT_EQ(readback(vtu + " " + ref), 0) << n << " particles: " << vtu << " does not read back as " << ref;
}

}  // namespace

TEST(VtkReadback, EveryArrayAndThePointsAreBitExact) {
  SKIP_WITHOUT_PYTHON_VTK();
  const Particles p = make_particles(7);
  ASSERT_EQ(2 * p.radius[0], 1e-3 / 3.0);  // the diameter in the file is the one given to add()
  expect_round_trip(7);
}

TEST(VtkReadback, EveryBase64PaddingLength) {
  SKIP_WITHOUT_PYTHON_VTK();
  for (int n : {1, 2, 3}) expect_round_trip(n);  // Int32/UInt8/Int64 arrays of n mod 3 = 1, 2, 0 triplets
}

TEST(VtkReadback, EmptyFrame) {
  SKIP_WITHOUT_PYTHON_VTK();
  expect_round_trip(0);
}

TEST(VtkReadback, PvdIndexNamesFramesAtExactTimes) {
  SKIP_WITHOUT_PYTHON_VTK();
  TempDir dir;
  const double times[] = {0.1, 1.0 / 3.0};
  const int sizes[] = {4, 5};
  tsubu::PvdIndex pvd(dir.file("particles.pvd"));
  FILE* ref = std::fopen(dir.file("particles.ref").c_str(), "w");
  ASSERT_NE(ref, nullptr);
  for (int k = 0; k < 2; ++k) {
    const std::string name = "frame_0000" + std::to_string(k) + ".vtu";
    tsubu::write_vtu(dir.file(name), make_particles(sizes[k]), times[k]);
    pvd.add(times[k], name);
    std::fprintf(ref, "%.17g %s %d\n", times[k], name.c_str(), sizes[k]);
  }
  std::fclose(ref);
  EXPECT_EQ(readback("--pvd " + dir.file("particles.pvd") + " " + dir.file("particles.ref")), 0);
}
