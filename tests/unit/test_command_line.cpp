// The command line (docs/cli.md): OMP_NUM_THREADS sets the threads when --threads is not
// given, a bad value is refused (exit 2), copies started by mpirun are refused where a run
// cannot be split among them, and a --set string written without quotes gets a hint that
// shows the quoting.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tsubu_process.hpp"

namespace fs = std::filesystem;
using namespace tsubu::testing;

namespace {

const std::string kValidSmall = (fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "valid_small.toml").string();

// The threads run.json records for a short run of valid_small with OMP_NUM_THREADS = `omp`
// and the extra arguments.
std::string recorded_threads(const TempDir& dir, const char* omp, std::vector<std::string> args = {}) {
  const fs::path out = dir.path() / (std::string("out") + omp), log = dir.path() / "log";
  std::vector<std::string> all{"run", kValidSmall, "--out", out.string(), "--set", "simulation.duration=1e-4"};
  all.insert(all.end(), args.begin(), args.end());
  EXPECT_EQ(run(all, log, [omp] { setenv("OMP_NUM_THREADS", omp, 1); }), 0) << slurp(log);
  const std::string json = slurp(out / "run.json");
  const auto at = json.find("\"threads\": ");
  return at == std::string::npos ? "" : json.substr(at + 11, json.find_first_of(",\n", at) - at - 11);
}

}  // namespace

TEST(CommandLine, OmpNumThreadsSetsTheThreadsWithoutTheOption) {
  TempDir dir;
  EXPECT_EQ(recorded_threads(dir, "2"), "2");
  EXPECT_EQ(recorded_threads(dir, "1"), "1");
  EXPECT_EQ(recorded_threads(dir, "3", {"--threads", "1"}), "1");  // the option wins
}

TEST(CommandLine, ABadOmpNumThreadsIsRefused) {
  TempDir dir;
  for (const char* value : {"abc", "0", "-2", "4,2", "", "2000"}) {
    const fs::path log = dir.path() / "log";
    EXPECT_EQ(run({"run", kValidSmall, "--out", (dir.path() / "out").string()}, log,
                  [value] { setenv("OMP_NUM_THREADS", value, 1); }),
              2)
        << value << ": " << slurp(log);
    EXPECT_NE(slurp(log).find(std::string("error: OMP_NUM_THREADS=") + value + ": must be a whole number of threads from 1 to 1024"),
              std::string::npos)
        << slurp(log);
    EXPECT_FALSE(fs::exists(dir.path() / "out")) << value;
  }
}

// Copies started by an MPI launcher split `run` and `resume` among them (tests/mpi/split_cli.py);
// `check` and `export` are one process's work, and [parallel] counts that fit no grid of their
// number, or a [parallel] table with block steps (which share out their active grains, not the
// box), are refused, before MPI starts and before the folder is touched. One copy says why.
TEST(CommandLine, SeveralCopiesStartedByMpirunAreRefused) {
  TempDir dir;
  const fs::path out = dir.path() / "out", log = dir.path() / "log";
  const std::string block = (fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios" / "block_threads.toml").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"check", kValidSmall}, "error: started as 3 processes (mpirun): `tsubu check` runs as one process"},
      {{"export", out.string()}, "error: started as 3 processes (mpirun): `tsubu export` runs as one process"},
      {{"run", block, "--out", out.string(), "--set", "parallel.counts=[1, 1, 3]"},
       "--set parallel.counts=[1, 1, 3]:1: parallel.counts: block steps share out the active particles among the "
       "processes, not the box into subdomains: [parallel] is read only with a fixed-step integrator"},
      {{"run", kValidSmall, "--out", out.string(), "--set", "parallel.counts=[2, 2, 1]"},
       "--set parallel.counts=[2, 2, 1]:1: parallel.counts: no grid of 3 subdomains (mpirun -np 3) has 2 x 2 x 1: "}};
  for (const auto& [size, rank] : {std::pair{"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"}, std::pair{"PMI_SIZE", "PMI_RANK"}})
    for (const auto& [args, message] : refused) {
      const auto copy = [&](const char* r) { return run(args, log, [&] { setenv(size, "3", 1), setenv(rank, r, 1); }); };
      EXPECT_EQ(copy("0"), 2) << slurp(log);
      EXPECT_NE(slurp(log).find(message), std::string::npos) << slurp(log);
      EXPECT_EQ(copy("2"), 2) << slurp(log);
      EXPECT_EQ(slurp(log), "");  // one copy says why
      EXPECT_FALSE(fs::exists(out)) << size;
    }
  // One process of a launcher runs.
  EXPECT_EQ(run({"run", kValidSmall, "--out", out.string(), "--set", "simulation.duration=1e-4"}, log,
                [] { setenv("OMPI_COMM_WORLD_SIZE", "1", 1); }),
            0)
      << slurp(log);
}

TEST(CommandLine, AnUnquotedSetStringGetsAQuotingHint) {
  TempDir dir;
  const fs::path log = dir.path() / "log";
  EXPECT_EQ(run({"check", kValidSmall, "--set", "simulation.integrator=block_hermite"}, log), 2) << slurp(log);
  EXPECT_NE(slurp(log).find("--set simulation.integrator=block_hermite:1: simulation.integrator: the value is not valid "
                            "TOML: "),
            std::string::npos)
      << slurp(log);
  EXPECT_NE(slurp(log).find("; a string value needs quotes: --set 'simulation.integrator=\"block_hermite\"'"),
            std::string::npos)
      << slurp(log);
  // A mistyped number is not a string: no hint.
  EXPECT_EQ(run({"check", kValidSmall, "--set", "simulation.dt=1e-3x"}, log), 2) << slurp(log);
  EXPECT_EQ(slurp(log).find("needs quotes"), std::string::npos) << slurp(log);
}
