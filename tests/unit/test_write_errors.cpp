// Every write of a run is checked (docs/reliability.md): a failed write stops the run with
// exit code 5 and a message naming the file, keeps the last good checkpoint, and run.json is
// never left empty or cut short. Faults come from a file-size limit (RLIMIT_FSIZE: writes
// beyond it fail with EFBIG), /dev/full (ENOSPC) and, when the test may mount, a tiny tmpfs.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tsubu/app/checkpoint.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/io/checked_file.hpp"
#include "tsubu_process.hpp"

namespace fs = std::filesystem;
using namespace tsubu;
using namespace tsubu::testing;

namespace {

const std::string kScenario = (fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "valid_small.toml").string();

// In the child: files may not grow beyond `bytes`; a write past it fails (EFBIG) instead of
// killing the process (SIGXFSZ ignored).
std::function<void()> file_size_limit(rlim_t bytes) {
  return [bytes] {
    signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_FSIZE, &limit);
  };
}

// run.json is whole: absent (never written) or ending with its closing brace.
void expect_whole_run_json(const fs::path& out) {
  if (!fs::exists(out / "run.json")) return;
  const std::string json = slurp(out / "run.json");
  ASSERT_GE(json.size(), 2u);
  EXPECT_EQ(json.substr(json.size() - 2), "}\n");
}

}  // namespace

TEST(CheckedFile, AFailedWriteThrowsNamingTheFileAndTheReason) {
  CheckedFile f("/dev/full");
  try {
    for (int k = 0; k < 100000; ++k) f << "a row of the series, " << k << '\n';
    f.close();
    ADD_FAILURE() << "writes to /dev/full succeeded";
  } catch (const WriteError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write /dev/full: No space left on device"), std::string::npos) << e.what();
  }
}

// series.csv outgrows the limit after the checkpoint of step 2000: exit 5, the message names
// the file and the kept checkpoint, run.json says "failed".
TEST(WriteErrors, AFailedSeriesWriteStopsTheRunAndKeepsTheLastCheckpoint) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const int code = run({"run", kScenario, "--out", out.string(), "--set", "output.series_interval=0", "--set",
                        "output.vtk_interval=0", "--set", "output.checkpoint_every_steps=500"},
                       dir.path() / "log", file_size_limit(256 * 1024));
  const std::string log = slurp(dir.path() / "log");
  ASSERT_EQ(code, 5) << log;
  EXPECT_NE(log.find("cannot write " + (out / "series.csv").string() + ": File too large"), std::string::npos) << log;
  const auto kept = list_checkpoints(out / "checkpoint");
  ASSERT_FALSE(kept.empty());
  const std::int64_t step = read_checkpoint(kept.front()).step;
  EXPECT_NE(log.find("the last good checkpoint (step " + std::to_string(step) + ") is kept"), std::string::npos) << log;
  EXPECT_NE(slurp(out / "run.json").find("\"status\": \"failed\""), std::string::npos);
  expect_whole_run_json(out);
}

// A frame larger than the limit (459 particles): the first frame's write fails.
TEST(WriteErrors, AFailedFrameWriteStopsTheRun) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const int code = run({"run", kScenario, "--out", out.string(), "--set", "simulation.duration=0.005"}, dir.path() / "log",
                       file_size_limit(32 * 1024));
  const std::string log = slurp(dir.path() / "log");
  ASSERT_EQ(code, 5) << log;
  EXPECT_NE(log.find("cannot write " + (out / "frames" / "frame_00000.vtu").string()), std::string::npos) << log;
  expect_whole_run_json(out);
}

// The full disk: a 200 KiB tmpfs as the output folder, checkpoints off. Needs the
// right to mount (root); skipped otherwise.
TEST(WriteErrors, AFullTmpfsStopsTheRunWithExit5) {
  TempDir dir;
  const fs::path out = dir.path() / "tiny";
  fs::create_directories(out);
  if (mount("tmpfs", out.c_str(), "tmpfs", 0, "size=200k") != 0) GTEST_SKIP() << "cannot mount a tmpfs here";
  const int code = run({"run", kScenario, "--out", out.string(), "--set", "output.checkpoint_every_seconds=0"},
                       dir.path() / "log");
  const std::string log = slurp(dir.path() / "log");
  EXPECT_EQ(code, 5) << log;
  EXPECT_NE(log.find("No space left on device"), std::string::npos) << log;
  expect_whole_run_json(out);
  EXPECT_FALSE(fs::exists(out / "run.json.tmp")) << "a failed atomic write must not leave its .tmp";
  umount(out.c_str());
}
