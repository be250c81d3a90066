// The progress report (app/progress.hpp): rate and ETA from the recent rate, physics at most
// every 2 s on a terminal, and the plain log line a run writes when stderr is not a terminal
// (every TSUBU_LOG_INTERVAL seconds), which changes no result.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>

#include "tsubu/app/progress.hpp"
#include "tsubu_process.hpp"

namespace fs = std::filesystem;
using namespace tsubu;
using namespace tsubu::testing;

namespace {

const std::string kValidSmall = (fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "valid_small.toml").string();

const std::regex kLogLine(
    R"(tsubu: progress: t = [0-9.e+-]+ s, step ([0-9]+) of 10000 \([0-9.]+%\), [0-9.e+]+ steps/s, ETA [0-9]+ s, )"
    R"(E_kin [0-9.e+-]+ J, [0-9]+ contacts)");

}  // namespace

// Slow at first (1 step/s for 10 s), then 500 steps/s for 20 s: the rate shown follows the
// recent one (the average since the start would be 333 steps/s).
TEST(Progress, RateAndEtaFollowTheRecentRate) {
  ::testing::internal::CaptureStderr();
  Progress p(Progress::Mode::log, 1, 0, 100000, 0);
  auto none = [] { return ProgressPhysics{}; };
  p.report(10, 1e-4, 10, none);
  p.report(10010, 0.1, 30, none);
  const std::string err = ::testing::internal::GetCapturedStderr();
  std::smatch m;
  const std::regex rate(R"(step 10010 of 100000 \(10\.0%\), ([0-9.e+]+) steps/s, ETA ([0-9]+) s)");
  ASSERT_TRUE(std::regex_search(err, m, rate)) << err;
  EXPECT_GT(std::stod(m[1]), 400) << err;
  EXPECT_LT(std::stod(m[2]), 90000.0 / 400) << err;
}

// On a terminal the line is rewritten every 0.5 s, the physics (a pass over the state) taken
// at most every 2 s; every log line takes it.
TEST(Progress, PhysicsIsTakenAtMostEveryTwoSecondsOnATerminal) {
  for (const auto mode : {Progress::Mode::terminal, Progress::Mode::log}) {
    ::testing::internal::CaptureStderr();
    Progress p(mode, 0.5, 0, 1000, 0);
    int passes = 0;
    for (int k = 1; k <= 10; ++k) {
      ASSERT_TRUE(p.due(0.5 * k));
      p.report(10 * k, 0.001 * k, 0.5 * k, [&] { return ProgressPhysics{1.5, static_cast<std::size_t>(++passes)}; });
      EXPECT_FALSE(p.due(0.5 * k + 0.25));
    }
    p.finish();
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(passes, mode == Progress::Mode::terminal ? 3 : 10);  // 0.5, 2.5, 4.5 s
    EXPECT_NE(err.find(mode == Progress::Mode::terminal ? "\r t = " : "tsubu: progress: t = "), std::string::npos) << err;
  }
}

// A run with stderr to a file writes plain log lines (no carriage returns) at the interval
// TSUBU_LOG_INTERVAL gives, and the same series.csv as a run without them.
TEST(Progress, ABatchRunLogsPlainLinesAtTheInterval) {
  TempDir dir;
  const fs::path quiet = dir.path() / "quiet", logged = dir.path() / "logged";
  ASSERT_EQ(run({"run", kValidSmall, "--out", quiet.string()}, dir.path() / "quiet.log"), 0) << slurp(dir.path() / "quiet.log");
  EXPECT_EQ(slurp(dir.path() / "quiet.log").find("tsubu: progress"), std::string::npos);  // runs shorter than 30 s
  ASSERT_EQ(run({"run", kValidSmall, "--out", logged.string()}, dir.path() / "logged.log",
                [] { setenv("TSUBU_LOG_INTERVAL", "0.05", 1); }),
            0)
      << slurp(dir.path() / "logged.log");
  const std::string log = slurp(dir.path() / "logged.log");
  EXPECT_EQ(log.find('\r'), std::string::npos);
  std::istringstream lines(log);
  int count = 0;
  long long previous = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("tsubu: progress", 0) != 0) continue;
    std::smatch m;
    ASSERT_TRUE(std::regex_match(line, m, kLogLine)) << line;
    EXPECT_GT(std::stoll(m[1]), previous) << line;
    previous = std::stoll(m[1]);
    ++count;
  }
  EXPECT_GE(count, 2) << log;
  EXPECT_EQ(slurp(logged / "series.csv"), slurp(quiet / "series.csv"));
}

// A TSUBU_LOG_INTERVAL that is not a number of seconds above 0 is refused before the run
// touches its folder (exit 2).
TEST(Progress, ABadLogIntervalIsRefused) {
  TempDir dir;
  for (const char* value : {"abc", "0", "-1", "5s", "nan"}) {
    const fs::path log = dir.path() / "log";
    EXPECT_EQ(run({"run", kValidSmall, "--out", (dir.path() / "out").string()}, log,
                  [value] { setenv("TSUBU_LOG_INTERVAL", value, 1); }),
              2)
        << slurp(log);
    EXPECT_NE(slurp(log).find(std::string("TSUBU_LOG_INTERVAL=") + value + ": must be a number of seconds above 0"),
              std::string::npos)
        << slurp(log);
    EXPECT_FALSE(fs::exists(dir.path() / "out")) << value;
  }
}

// A run that a [[stop]] condition may end shows where the condition stands, and says that
// the percentage and ETA count to the duration (a run that stopped at t = 0.53 s read "4.8 %,
// ETA 63143 s" and nothing else).
TEST(Progress, ARunWithAStopConditionShowsWhereItStands) {
  TempDir dir;
  const fs::path log = dir.path() / "log";
  ASSERT_EQ(run({"run", kValidSmall, "--out", (dir.path() / "out").string(), "--set",
                 "stop=[{when=\"solid_fraction\", at_least=0.9, after=0.03}]"},
                log, [] { setenv("TSUBU_LOG_INTERVAL", "0.05", 1); }),
            0)
      << slurp(log);
  const std::regex line(R"(tsubu: progress: t = ([0-9.e+-]+) s, step [0-9]+ of 10000 \([0-9.]+%\), [0-9.e+]+ steps/s, )"
                        R"(ETA [0-9]+ s to the duration, E_kin [0-9.e+-]+ J, [0-9]+ contacts; )"
                        R"(\[\[stop\]\] solid_fraction >= 0\.9: now [0-9.e-]+( \(checked from t = 0\.03 s\))?)");
  std::istringstream lines(slurp(log));
  int waiting = 0, checked = 0;
  for (std::string text; std::getline(lines, text);) {
    if (text.rfind("tsubu: progress", 0) != 0) continue;
    std::smatch m;
    ASSERT_TRUE(std::regex_match(text, m, line)) << text;
    // "checked from" while the last series row (every 0.00025 s) is before t = 0.03 s
    const double t = std::stod(m[1]);
    EXPECT_TRUE(m[2].matched ? t < 0.03 + 0.00025 : t >= 0.03 - 1e-9) << text;
    ++(m[2].matched ? waiting : checked);
  }
  EXPECT_GE(waiting + checked, 2) << slurp(log);
}
