// A run owns its output folder (docs/reliability.md): a folder holding another run is
// refused unless --overwrite (which clears it), a folder in use is refused naming the
// holder, and `resume` continues only a checkpoint of the run whose outputs are there.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "tsubu/app/checkpoint.hpp"
#include "tsubu/io/output_dir.hpp"
#include "tsubu_process.hpp"

namespace fs = std::filesystem;
using namespace tsubu;
using namespace tsubu::testing;

namespace {

const std::string kScenario = (fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "valid_small.toml").string();

std::vector<std::string> run_args(const fs::path& out, const std::string& duration, std::vector<std::string> extra = {}) {
  std::vector<std::string> a = {"run", kScenario, "--out", out.string(), "--set", "simulation.duration=" + duration,
                                "--set", "output.checkpoint_every_steps=500"};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

std::size_t frames_in(const fs::path& out) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(out / "frames")) n += e.path().extension() == ".vtu";
  return n;
}

}  // namespace

// The path: an edited scenario run again into the same folder must not mix with the
// first run; with --overwrite it replaces it completely (no old frames beside the new .pvd).
TEST(OutputFolder, ARunIntoAFolderHoldingAnotherRunIsRefusedUnlessOverwrite) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(run(run_args(out, "0.01"), dir.path() / "a.log"), 0) << slurp(dir.path() / "a.log");
  const std::string series = slurp(out / "series.csv");
  const std::string first_id = slurp(out / kRunMarker);
  ASSERT_EQ(first_id.size(), 17u);
  EXPECT_NE(slurp(out / "run.json").find("\"run_id\": \"" + first_id.substr(0, 16) + "\""), std::string::npos);
  ASSERT_GT(frames_in(out), 10u);

  ASSERT_EQ(run(run_args(out, "0.005", {"--set", "output.vtk_interval=0"}), dir.path() / "b.log"), 2);
  EXPECT_NE(slurp(dir.path() / "b.log").find("holds the outputs of another run (run id " + first_id.substr(0, 16) + ")"),
            std::string::npos)
      << slurp(dir.path() / "b.log");
  EXPECT_EQ(slurp(out / "series.csv"), series) << "a refused run must not touch the folder";

  ASSERT_EQ(run(run_args(out, "0.005", {"--set", "output.vtk_interval=0", "--overwrite"}), dir.path() / "c.log"), 0)
      << slurp(dir.path() / "c.log");
  EXPECT_NE(slurp(out / kRunMarker), first_id);
  EXPECT_EQ(frames_in(out), 0u) << "the earlier run's frames must be gone";
  EXPECT_EQ(read_checkpoint(list_checkpoints(out / "checkpoint").front()).step, 1000);
  ASSERT_EQ(run({"resume", out.string()}, dir.path() / "d.log"), 0) << slurp(dir.path() / "d.log");
}

// --overwrite clears only a tsubu run's folder: anything else is never deleted.
TEST(OutputFolder, AFolderWithOtherFilesIsRefusedEvenWithOverwrite) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  fs::create_directories(out);
  std::ofstream(out / "thesis.tex") << "precious";
  ASSERT_EQ(run(run_args(out, "0.005", {"--overwrite"}), dir.path() / "log"), 2);
  EXPECT_NE(slurp(dir.path() / "log").find("holds no tsubu run"), std::string::npos) << slurp(dir.path() / "log");
  EXPECT_EQ(slurp(out / "thesis.tex"), "precious");
  EXPECT_EQ(run({"run", kScenario, "--out", ""}, dir.path() / "empty.log"), 2) << slurp(dir.path() / "empty.log");
}

// A checkpoint of another run placed in the folder (the mix of the issue) is not resumed.
TEST(OutputFolder, ResumeRefusesACheckpointOfAnotherRun) {
  TempDir dir;
  const fs::path a = dir.path() / "a", b = dir.path() / "b";
  ASSERT_EQ(run(run_args(a, "0.01", {"--set", "output.vtk_interval=0"}), dir.path() / "a.log"), 0);
  ASSERT_EQ(run(run_args(b, "0.005", {"--set", "output.vtk_interval=0"}), dir.path() / "b.log"), 0);
  const fs::path foreign = list_checkpoints(a / "checkpoint").front();
  fs::copy_file(foreign, b / "checkpoint" / foreign.filename());
  ASSERT_EQ(run({"resume", b.string()}, dir.path() / "resume.log"), 1);
  const std::string log = slurp(dir.path() / "resume.log");
  EXPECT_NE(log.find("belongs to run " + slurp(a / kRunMarker).substr(0, 16)), std::string::npos) << log;
  EXPECT_NE(log.find("holds the outputs of run " + slurp(b / kRunMarker).substr(0, 16)), std::string::npos) << log;
}

// Two processes in one folder: the second run (or resume) exits 2 naming the holder.
TEST(OutputFolder, ASecondRunOrResumeIntoAFolderInUseIsRefusedNamingTheHolder) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const pid_t first = spawn(run_args(out, "10"), dir.path() / "first.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(out / kRunMarker) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const int second = run(run_args(out, "0.005", {"--overwrite"}), dir.path() / "second.log");
  const int resume = run({"resume", out.string()}, dir.path() / "resume.log");
  kill(first, SIGKILL);
  wait_for(first);
  EXPECT_EQ(second, 2);
  EXPECT_EQ(resume, 2);
  for (const char* log : {"second.log", "resume.log"})
    EXPECT_NE(slurp(dir.path() / log).find("is in use by another tsubu (pid " + std::to_string(first) + " on "),
              std::string::npos)
        << slurp(dir.path() / log);
  // The lock dies with its holder.
  EXPECT_EQ(run(run_args(out, "0.005", {"--overwrite"}), dir.path() / "third.log"), 0) << slurp(dir.path() / "third.log");
}

// The frames up to the checkpoint are part of what a resume continues.
TEST(OutputFolder, ResumeAfterTheFramesWereDeletedIsAnError) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(run(run_args(out, "0.005"), dir.path() / "run.log"), 0) << slurp(dir.path() / "run.log");
  fs::remove_all(out / "frames");
  ASSERT_EQ(run({"resume", out.string()}, dir.path() / "resume.log"), 1);
  EXPECT_NE(slurp(dir.path() / "resume.log").find("frame_00000.vtu is missing"), std::string::npos)
      << slurp(dir.path() / "resume.log");
}

// An output interval longer than the run (1e300 meant as "never") writes the first and the
// last step only; the step count overflowed to "every step" before.
TEST(OutputIntervals, LongerThanTheRunWriteTheFirstAndLastStepOnly) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(run({"run", kScenario, "--out", out.string(), "--set", "simulation.duration=0.002", "--set",
                 "output.vtk_interval=1e300", "--set", "output.series_interval=1e300"},
                dir.path() / "log"),
            0)
      << slurp(dir.path() / "log");
  EXPECT_EQ(frames_in(out), 2u);
  const std::string series = slurp(out / "series.csv");
  EXPECT_EQ(std::count(series.begin(), series.end(), '\n'), 3) << series;  // header, step 0, the last step
}

namespace {

// Issue 25, item 6: rows reach series.csv within about a second, not only with a checkpoint
// (by default every 600 s): the first rows of a long run are on disk while it runs.
TEST(OutputIntervals, SeriesRowsReachTheDiskWithinSeconds) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const pid_t pid = spawn({"run", kScenario, "--out", out.string(), "--set", "simulation.duration=100", "--set",
                           "output.series_interval=1e300", "--set", "output.vtk_interval=0"},
                          dir.path() / "run.log");
  std::string series;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::count(series.begin(), series.end(), '\n') < 2 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    series = slurp(out / "series.csv");
  }
  int status = 0;
  const bool running = waitpid(pid, &status, WNOHANG) == 0;
  kill(pid, SIGKILL);
  wait_for(pid);
  EXPECT_TRUE(running) << "the run ended: make it longer";
  EXPECT_EQ(std::count(series.begin(), series.end(), '\n'), 2) << "the header and the row of t = 0:\n" << series;
}

}  // namespace
