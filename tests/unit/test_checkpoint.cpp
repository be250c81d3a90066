// Checkpoints and `tsubu resume` (docs/reliability.md): the format detects damage, and a run
// killed at a random step (SIGKILL: no chance to clean up) or stopped by SIGTERM, then
// resumed, ends with the same bits as the uninterrupted run: series.csv, track.csv, every
// VTK frame, the .pvd index and the final checkpoint (particles, forces, contact histories).
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "tsubu/app/checkpoint.hpp"
#include "tsubu/core/hash.hpp"
#include "final_state.hpp"
#include "tsubu_process.hpp"

namespace fs = std::filesystem;
using namespace tsubu;
using namespace tsubu::testing;

namespace {

const fs::path kScenarios = fs::path(TSUBU_SOURCE_DIR) / "tests" / "scenarios";

// Waits until the run has written `checkpoints` checkpoints (or ended), then a random time
// more, and sends `sig`. Returns the wait status.
int interrupt_after_checkpoints(pid_t pid, const fs::path& out, int sig, int max_delay_ms, std::size_t checkpoints = 1) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (list_checkpoints(out / "checkpoint").size() < checkpoints && std::chrono::steady_clock::now() < deadline) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  std::random_device rd;
  const int delay = std::uniform_int_distribution<int>(0, max_delay_ms)(rd);
  std::printf("sending signal %d %d ms after checkpoint %zu\n", sig, delay, checkpoints);
  std::this_thread::sleep_for(std::chrono::milliseconds(delay));
  kill(pid, sig);
  return wait_for(pid);
}


// Every output file of `ref` is in `out` with the same bytes, and the final states agree.
void expect_same_outputs(const fs::path& ref, const fs::path& out, bool extended = false) {
  std::vector<fs::path> files = {"series.csv"};
  if (fs::exists(ref / "track.csv")) files.push_back("track.csv");
  if (fs::exists(ref / "outflow.csv")) files.push_back("outflow.csv");
  std::size_t frames = 0;  // every file of frames/: particles, contact network, walls, indexes
  for (const auto& e : fs::directory_iterator(ref / "frames"))
    files.push_back(fs::path("frames") / e.path().filename()), frames += e.path().extension() == ".vtu";
  std::size_t frames_out = 0;
  for (const auto& e : fs::directory_iterator(out / "frames")) frames_out += e.path().extension() == ".vtu";
  EXPECT_EQ(frames_out, frames) << "number of VTK frames";
  EXPECT_GT(frames, 2u);
  for (const auto& f : files) EXPECT_TRUE(slurp(ref / f) == slurp(out / f)) << f << " differs";
  ASSERT_FALSE(list_checkpoints(ref / "checkpoint").empty());
  EXPECT_TRUE(final_state(ref, extended) == final_state(out, extended)) << "final checkpoints differ";
  EXPECT_NE(slurp(out / "run.json").find("\"status\": \"ok\""), std::string::npos);
}

std::int64_t newest_step(const fs::path& out) { return read_checkpoint(list_checkpoints(out / "checkpoint").front()).step; }

// `tsubu run scenario --out <dir> sets...` to the end (ref) and again killed by SIGKILL up to
// `max_delay_ms` after its first checkpoint (cut); the resumed cut ends as ref.
void expect_sigkill_resume_identical(const fs::path& dir, const fs::path& scenario, const std::vector<std::string>& sets,
                                     int max_delay_ms) {
  const fs::path ref = dir / "ref", cut = dir / "cut";
  auto args = [&](const fs::path& out) {
    std::vector<std::string> a = {"run", scenario.string(), "--out", out.string()};
    a.insert(a.end(), sets.begin(), sets.end());
    return a;
  };
  ASSERT_EQ(run(args(ref), dir / "ref.log"), 0) << slurp(dir / "ref.log");
  const int status = interrupt_after_checkpoints(spawn(args(cut), dir / "cut.log"), cut, SIGKILL, max_delay_ms);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed; make it longer\n" << slurp(dir / "cut.log");
  std::printf("newest checkpoint before the kill: step %lld\n", static_cast<long long>(newest_step(cut)));
  ASSERT_EQ(run({"resume", cut.string()}, dir / "resume.log"), 0) << slurp(dir / "resume.log");
  expect_same_outputs(ref, cut);
}

Checkpoint sample_checkpoint() {
  Checkpoint c;
  c.engine_version = "0.1.0";
  c.run_id = "0123456789abcdef";
  c.scenario_path = "/somewhere/bed.toml";
  c.scenario_text = "[simulation]\nduration = 1\n";
  c.overrides = {"simulation.dt=1e-6", "output.track=[0, 1]"};
  c.scenario_hash = 0x1234567890abcdefULL;
  c.step = 4242;
  c.time = 4242 * 1e-6;
  c.dt = 1e-6;
  c.counters = {99, 2999, 7};
  c.wall_seconds = 1.5;
  c.output = {3, {{0.0, "frame_00000.vtu"}, {0.1, "frame_00001.vtu"}}, 1234, 567};
  for (int k = 0; k < 3; ++k) {
    c.particles.add(7000 + k, k % 2, 0.001 * (k + 1), 2500, {0.1 * k, 0.2, 0.3}, {1, 2, 3.0 + k});
    c.particles.omega[k] = {0.5, -0.25, 1.0 / 3.0};
    c.particles.force[k] = {1e-3, 2e-3, -9.81};
    c.particles.torque[k] = {std::nextafter(1.0, 2.0), 0, -1e-300};
    c.particles.contact_count[k] = k;
  }
  c.wall_points = {{0, 0, 0}, {0, 0, 0.026 - 1e-5 / 3}};
  c.wall_velocities = {{}, {0, 0, -0.1}};
  Contact a{0, 2, true, {{1e-7, -2e-7, 3e-7}, {0.25, -0.5}, {2e-9, 0, -1e-9}}};
  Contact b{1, 0, true, {{-4e-8, 0, 5e-8}, {0.125, 0}}};
  c.pair_contacts = {a};
  c.wall_contacts = {b};
  return c;
}

}  // namespace

TEST(CheckpointFormat, RoundTripsEveryFieldBitForBit) {
  const Checkpoint c = sample_checkpoint();
  const std::string bytes = encode_checkpoint(c);
  const Checkpoint d = decode_checkpoint(bytes);
  EXPECT_EQ(encode_checkpoint(d), bytes);
  EXPECT_EQ(d.overrides, c.overrides);
  EXPECT_EQ(d.run_id, c.run_id);
  EXPECT_EQ(d.step, c.step);
  EXPECT_EQ(d.counters.particle_evaluations, 2999u);
  EXPECT_EQ(d.output.pvd, c.output.pvd);
  EXPECT_EQ(d.particles.torque[1], c.particles.torque[1]);
  EXPECT_EQ(d.pair_contacts[0].history.rolling, c.pair_contacts[0].history.rolling);
  EXPECT_EQ(d.pair_contacts[0].history.normal[1], -0.5);
  EXPECT_TRUE(d.pair_contacts[0].touching);
  EXPECT_EQ(d.wall_points[1], c.wall_points[1]);
  EXPECT_EQ(d.wall_velocities[1], c.wall_velocities[1]);
}

// The file lists the particles by id and only the touching contacts, each pair from its
// smaller id: a run numbered otherwise (a spatial sort) or whose lists hold more entries
// (built at another step) writes the same bytes, and reads back in id order.
TEST(CheckpointFormat, TheBytesDoNotDependOnTheNumberingOrOnEntriesThatDoNotTouch) {
  const Checkpoint c = sample_checkpoint();
  Checkpoint r = sample_checkpoint();  // particles 7000, 7001, 7002 at indices 2, 0, 1
  const std::size_t at[3] = {2, 0, 1};
  r.particles.for_each_array([&](auto& array) {
    auto copy = array;
    for (std::size_t k = 0; k < 3; ++k) array[at[k]] = copy[k];
  });
  r.pair_contacts = {{0, 1, false, {}}, {1, 2, true, c.pair_contacts[0].history}};  // ids (7002, 7000)
  r.wall_contacts = {{0, 0, true, c.wall_contacts[0].history}, {1, 1, false, {}}};
  const std::string bytes = encode_checkpoint(c);
  EXPECT_TRUE(encode_checkpoint(r) == bytes);
  const Checkpoint d = decode_checkpoint(encode_checkpoint(r));
  EXPECT_EQ(d.particles.id, (std::vector<std::int64_t>{7000, 7001, 7002}));
  ASSERT_EQ(d.pair_contacts.size(), 1u);
  EXPECT_EQ(d.pair_contacts[0].i, 0u);
  EXPECT_EQ(d.pair_contacts[0].j, 2u);
  EXPECT_TRUE(d.pair_contacts[0].touching);
  EXPECT_EQ(d.pair_contacts[0].history.xi, c.pair_contacts[0].history.xi) << "stored by id: no turn";
  ASSERT_EQ(d.wall_contacts.size(), 1u);
  EXPECT_EQ(d.wall_contacts[0].i, 1u);
}

// A payload out of the file's order is refused (its checksum made to match): particles not
// by id, a pair listed from its second particle, contacts out of (i, j) order.
TEST(CheckpointFormat, APayloadOutOfTheFilesOrderIsRefused) {
  const auto patched = [](std::string bytes, const std::string& from, const std::string& to) {
    const std::size_t at = bytes.find(from);
    EXPECT_NE(at, std::string::npos);
    EXPECT_EQ(bytes.find(from, at + 1), std::string::npos);
    bytes.replace(at, from.size(), to);
    const std::uint64_t sum = fnv1a64({bytes.data() + 32, bytes.size() - 32});
    std::memcpy(bytes.data() + 24, &sum, 8);
    return bytes;
  };
  const auto raw = [](auto... values) {
    std::string s;
    ((s.append(reinterpret_cast<const char*>(&values), sizeof values)), ...);
    return s;
  };
  auto refused = [](const std::string& b, const std::string& phrase) {
    try {
      decode_checkpoint(b);
      ADD_FAILURE() << "accepted; expected: " << phrase;
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
    }
  };
  Checkpoint c = sample_checkpoint();
  const std::string bytes = encode_checkpoint(c);
  ASSERT_NO_THROW(decode_checkpoint(bytes));
  refused(patched(bytes, raw(std::int64_t{7000}, std::int64_t{7001}), raw(std::int64_t{7001}, std::int64_t{7000})),
          "not in the order of their ids");
  refused(patched(bytes, raw(std::uint32_t{0}, std::uint32_t{2}, c.pair_contacts[0].history.xi),
                  raw(std::uint32_t{2}, std::uint32_t{0}, c.pair_contacts[0].history.xi)),
          "not listed from its first particle");
  c.pair_contacts.push_back({1, 2, true, {{7e-9, 0, 0}, {0, 0}}});
  refused(patched(encode_checkpoint(c), raw(std::uint32_t{1}, std::uint32_t{2}, Vec3{7e-9, 0, 0}),
                  raw(std::uint32_t{0}, std::uint32_t{1}, Vec3{7e-9, 0, 0})),
          "not sorted by (i, j)");
}

TEST(CheckpointFormat, ParticlesWithLittleElseAfterThemRoundTrip) {
  // The particle count is checked against the bytes left: with few contacts and no inflow
  // after them (a cloud of falling grains, a run stopped early by SIGINT), the check must use
  // a particle's true size. It took 176 bytes for the 168 a particle has, and refused every
  // checkpoint whose contacts and inflow state came to fewer than 8 bytes a particle with "a
  // count exceeds the file size": resume found "no valid checkpoint".
  Checkpoint c = sample_checkpoint();
  c.pair_contacts.clear();
  c.wall_contacts.clear();
  c.particles = Particles{};
  for (int i = 0; i < 100; ++i) c.particles.add(i, 0, 1e-3, 2500, {0, 0, 1e-3 * i}, {});
  const std::string bytes = encode_checkpoint(c);
  EXPECT_EQ(decode_checkpoint(bytes).particles.size(), 100u);
}

TEST(CheckpointFormat, TheInflowSectionRoundTripsAndIsAbsentWithoutAnInflow) {
  Checkpoint c = sample_checkpoint();
  const std::string without = encode_checkpoint(c);
  EXPECT_FALSE(decode_checkpoint(without).inflow.present);
  c.inflow = {true, 3, std::string("state\0bytes", 11)};
  const std::string with = encode_checkpoint(c);
  EXPECT_EQ(with.size(), without.size() + 1 + 8 + 8 + 11);  // tag, first id, length, bytes
  const Checkpoint d = decode_checkpoint(with);
  EXPECT_TRUE(d.inflow.present);
  EXPECT_EQ(d.inflow.first_id, 3);
  EXPECT_EQ(d.inflow.state, c.inflow.state);
  EXPECT_EQ(encode_checkpoint(d), with);
}

// The record of the run's sessions (its sources' ids, its loops' totals) follows the inflow's
// section; a checkpoint without it (an older tsubu's) still reads.
TEST(CheckpointFormat, TheRecordSectionRoundTripsAfterTheInflowsAndMayBeAbsent) {
  Checkpoint c = sample_checkpoint();
  c.inflow = {true, 3, "state"};
  const std::string without = encode_checkpoint(c);
  EXPECT_FALSE(decode_checkpoint(without).record.present);
  c.record = {true, {{0, 3}, {3, INT64_MAX}}, 12.5, 4000, 2};
  const std::string with = encode_checkpoint(c);
  EXPECT_EQ(with.size(), without.size() + 1 + 8 + 2 * 16 + 8 + 8 + 8);  // tag, count, pairs, seconds, steps, sessions
  const Checkpoint d = decode_checkpoint(with);
  EXPECT_TRUE(d.record.present && d.inflow.present);
  EXPECT_EQ(d.record.source_ids, c.record.source_ids);
  EXPECT_EQ(d.record.loop_seconds, 12.5);
  EXPECT_EQ(d.record.loop_steps, 4000);
  EXPECT_EQ(d.record.loop_sessions, 2);
  EXPECT_EQ(encode_checkpoint(d), with);
}

TEST(CheckpointFormat, TruncationCorruptionAndOtherVersionsAreRefused) {
  const std::string bytes = encode_checkpoint(sample_checkpoint());
  auto refused = [](const std::string& b, const std::string& phrase) {
    try {
      decode_checkpoint(b);
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted a damaged checkpoint; expected: " << phrase;
  };
  refused(bytes.substr(0, 20), "truncated");
  refused(bytes.substr(0, bytes.size() - 1), "truncated");
  refused(bytes + "x", "payload bytes");
  for (std::size_t at : {std::size_t{40}, bytes.size() / 2, bytes.size() - 1}) {
    std::string flipped = bytes;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x10);
    refused(flipped, "checksum");
  }
  std::string other = bytes;
  other[8] = static_cast<char>(kCheckpointVersion + 1);
  refused(other, "format version " + std::to_string(kCheckpointVersion + 1));
  refused("XSUBUCKP" + bytes.substr(8), "magic");
}

// An older version's files are refused, saying that an older tsubu wrote them (version 2
// stored a pair's spring as seen from its smaller index: the same bytes with another meaning;
// version 3 lacks the block steps' counts of steps by rule; version 4 has a touching flag
// per contact; version 5 lacks the rolling spring; version 6 lacks the count of particle
// force evaluations).
TEST(CheckpointFormat, AnOlderVersionIsRefusedAsOlder) {
  ASSERT_EQ(kCheckpointVersion, 7u);
  for (char version : {2, 3, 4, 5, 6}) {
    std::string old = encode_checkpoint(sample_checkpoint());
    old[8] = version;
    try {
      decode_checkpoint(old);
      ADD_FAILURE() << "accepted a version " << int(version) << " checkpoint";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("format version " + std::to_string(version) +
                                           ", this tsubu reads version 7 (an older tsubu wrote it"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(CheckpointFiles, TheLastTwoAreKeptNewestFirst) {
  TempDir dir;
  Checkpoint c = sample_checkpoint();
  for (std::int64_t step : {10, 30, 20, 40}) {
    c.step = step;
    write_checkpoint(dir.path(), c);
  }
  std::ofstream(dir.path() / "step_000000000050.tsbk.tmp") << "a write cut short";
  const auto files = list_checkpoints(dir.path());
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].filename(), "step_000000000040.tsbk");
  EXPECT_EQ(files[1].filename(), "step_000000000030.tsbk");
  EXPECT_EQ(read_checkpoint(files[0]).step, 40);
}

// Velocity Verlet, Hertz + Mindlin: SIGKILL at a random step, resume; then the same from
// copies whose newest checkpoint is corrupted or truncated (the previous one is used).
TEST(Resume, AfterSigkillTheRunEndsBitIdentical_VelocityVerlet) {
  TempDir dir;
  const fs::path ref = dir.path() / "ref", cut = dir.path() / "cut";
  const std::vector<std::string> sets = {"--set", "simulation.duration=0.12",        "--set",
                                         "output.checkpoint_every_steps=1000", "--set", "output.track=[0, 5, 300]",
                                         "--set", "output.vtk_interval=0.01"};
  auto args = [&](const fs::path& out) {
    std::vector<std::string> a = {"run", (kScenarios / "valid_small.toml").string(), "--out", out.string()};
    a.insert(a.end(), sets.begin(), sets.end());
    return a;
  };
  ASSERT_EQ(run(args(ref), dir.path() / "ref.log"), 0) << slurp(dir.path() / "ref.log");

  // Killed once two checkpoints are kept (the damaged-checkpoint cases below need two; a
  // kill between the first two left the test without them under a sanitizer's slowness).
  const int status = interrupt_after_checkpoints(spawn(args(cut), dir.path() / "cut.log"), cut, SIGKILL, 300, 2);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed; make it longer\n" << slurp(dir.path() / "cut.log");
  ASSERT_GE(list_checkpoints(cut / "checkpoint").size(), 2u);
  const std::int64_t killed_after = newest_step(cut);
  std::printf("newest checkpoint before the kill: step %lld\n", static_cast<long long>(killed_after));

  // Damaged copies, made before the intact folder is resumed.
  const fs::path corrupt = dir.path() / "corrupt", truncated = dir.path() / "truncated";
  fs::copy(cut, corrupt, fs::copy_options::recursive);
  fs::copy(cut, truncated, fs::copy_options::recursive);

  ASSERT_EQ(run({"resume", cut.string()}, dir.path() / "resume.log"), 0) << slurp(dir.path() / "resume.log");
  EXPECT_NE(slurp(dir.path() / "resume.log").find("step " + std::to_string(killed_after)), std::string::npos)
      << slurp(dir.path() / "resume.log");
  expect_same_outputs(ref, cut);

  const fs::path bad1 = list_checkpoints(corrupt / "checkpoint").front();
  {
    std::fstream f(bad1, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(bad1) / 2));
    f.put('\x5a');
  }
  ASSERT_EQ(run({"resume", corrupt.string()}, dir.path() / "corrupt.log"), 0) << slurp(dir.path() / "corrupt.log");
  const std::string corrupt_log = slurp(dir.path() / "corrupt.log");
  EXPECT_NE(corrupt_log.find("checksum"), std::string::npos) << corrupt_log;
  EXPECT_NE(corrupt_log.find("trying the previous one"), std::string::npos) << corrupt_log;
  expect_same_outputs(ref, corrupt);

  const fs::path bad2 = list_checkpoints(truncated / "checkpoint").front();
  fs::resize_file(bad2, fs::file_size(bad2) - 100);
  ASSERT_EQ(run({"resume", truncated.string()}, dir.path() / "truncated.log"), 0) << slurp(dir.path() / "truncated.log");
  EXPECT_NE(slurp(dir.path() / "truncated.log").find("truncated"), std::string::npos) << slurp(dir.path() / "truncated.log");
  expect_same_outputs(ref, truncated);
}

// Symplectic Euler with model P (position correction on the contact step) and Coulomb
// springs: the stored forces are used as they are, never recomputed, at the resume.
TEST(Resume, AfterSigkillTheRunEndsBitIdentical_SymplecticEulerModelP) {
  TempDir dir;
  expect_sigkill_resume_identical(dir.path(), kScenarios / "checkpoint_model_p.toml", {}, 600);
}

// Rolling resistance, model EPSD (its spring torque is a history slot of every contact):
// the springs survive the kill as the tangential ones do.
TEST(Resume, AfterSigkillTheRunEndsBitIdentical_RollingResistance) {
  TempDir dir;
  expect_sigkill_resume_identical(dir.path(), kScenarios / "valid_small.toml",
                                  {"--set", "simulation.duration=0.12", "--set", "output.checkpoint_every_steps=1000", "--set",
                                   "contact.default.rolling=\"epsd\"", "--set", "contact.default.rolling_friction=0.1", "--set",
                                   "contact.default.rolling_damping=0.3"},
                                  300);
}

// The same with block steps (grains settling onto a floor, as in _BlockHermite below): the
// rolling springs survive the kill beside the per-particle Hermite state.
TEST(Resume, AfterSigkillTheRunEndsBitIdentical_RollingResistanceBlockSteps) {
  TempDir dir;
  expect_sigkill_resume_identical(dir.path(), kScenarios / "block_sediment.toml",
                                  {"--set", "simulation.duration=0.06", "--set", "contact.default.rolling=\"epsd\"", "--set",
                                   "contact.default.rolling_friction=0.1", "--set", "contact.default.rolling_damping=0.3"},
                                  600);
}

// A moving wall (the piston of the Hooke/Hysteresis demonstration, loading the bed): its
// plane and velocity are part of the state, and the wall columns of series.csv continue.
TEST(Resume, AfterSigkillTheRunEndsBitIdentical_MovingWall) {
  TempDir dir;
  expect_sigkill_resume_identical(dir.path(), fs::path(TSUBU_SOURCE_DIR) / "examples" / "piston-hysteresis.toml",
                                  {"--set", "simulation.duration=0.14", "--set", "output.checkpoint_every_steps=2000",
                                   "--set", "output.vtk_interval=0.02"},
                                  600);
}

// Block-step Hermite (tests/scenarios/block_sediment.toml: grains settling in water onto a
// floor, Hertz + Mindlin): the per-particle times, levels, accelerations and jerks, and the
// neighbour lists as they were built, survive the kill; contacts begin during the run.
TEST(Resume, AfterSigkillTheRunEndsBitIdentical_BlockHermite) {
  TempDir dir;
  // 0.06 s (about 1.2 s of wall time, 600 steps): longer than the latest kill.
  expect_sigkill_resume_identical(dir.path(), kScenarios / "block_sediment.toml", {"--set", "simulation.duration=0.06"}, 600);
  // The stepper's counts (block times, wakes, evaluations per level, steps by rule) too.
  const auto block_steps = [&](const char* run) {
    const std::string json = slurp(dir.path() / run / "run.json");
    const std::size_t from = json.find("\"block_steps\"");
    return from == std::string::npos ? std::string() : json.substr(from, json.find("\"results\"") - from);
  };
  EXPECT_NE(block_steps("ref").find("\"steps_set_by_cluster\""), std::string::npos) << block_steps("ref");
  EXPECT_EQ(block_steps("ref"), block_steps("cut"));
}

// An inflow (grains entering during the run, docs/sedimentation.md): the stream's state is
// in the checkpoint, and the grains that enter after the resume are the same, to the bit, for
// fixed steps and for block steps (whose per-particle state grows with the grains).
void expect_inflow_resume_bit_identical(const std::vector<std::string>& sets) {
  TempDir dir;
  const fs::path ref = dir.path() / "ref", cut = dir.path() / "cut";
  auto args = [&](const fs::path& out) {
    std::vector<std::string> a = {"run", (kScenarios / "inflow_small.toml").string(), "--out", out.string()};
    for (const auto& s : sets) a.insert(a.end(), {"--set", s});
    return a;
  };
  ASSERT_EQ(run(args(ref), dir.path() / "ref.log"), 0) << slurp(dir.path() / "ref.log");
  const int status = interrupt_after_checkpoints(spawn(args(cut), dir.path() / "cut.log"), cut, SIGKILL, 100);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed; make it longer\n" << slurp(dir.path() / "cut.log");
  const Checkpoint c = read_checkpoint(list_checkpoints(cut / "checkpoint").front());
  std::printf("newest checkpoint before the kill: step %lld, %zu grains\n", static_cast<long long>(c.step), c.particles.size());
  EXPECT_TRUE(c.inflow.present);
  EXPECT_GT(c.particles.size(), 0u) << "killed before any grain entered";
  ASSERT_EQ(run({"resume", cut.string()}, dir.path() / "resume.log"), 0) << slurp(dir.path() / "resume.log");
  expect_same_outputs(ref, cut);
  EXPECT_EQ(slurp(ref / "run.json").substr(slurp(ref / "run.json").find("\"results\"")),
            slurp(cut / "run.json").substr(slurp(cut / "run.json").find("\"results\"")));
}

// Open faces (tests/scenarios/chute_open.toml, grains leaving a chute's open end): a run ended
// in mid-discharge (at `cut_at`), its newest checkpoint lost, resumes from the one before to
// `duration`: outflow.csv is cut back to its rows at the checkpoint and written again, the
// totals go on from the checkpoint's, and every output ends as the uninterrupted run's.
void expect_discharge_resume_bit_identical(std::vector<std::string> sets, const std::string& duration,
                                           const std::string& cut_at, const std::string& checkpoint_every) {
  TempDir dir;
  const fs::path ref = dir.path() / "ref", cut = dir.path() / "cut";
  auto args = [&](const fs::path& out, const std::string& until) {
    std::vector<std::string> a = {"run", (kScenarios / "chute_open.toml").string(), "--out", out.string(), "--set",
                                  "output.checkpoint_every_steps=" + checkpoint_every, "--set", "output.vtk_interval=0.04",
                                  "--set", "simulation.duration=" + until};
    for (const std::string& s : sets) a.insert(a.end(), {"--set", s});
    return a;
  };
  ASSERT_EQ(run(args(ref, duration), dir.path() / "ref.log"), 0) << slurp(dir.path() / "ref.log");
  ASSERT_EQ(run(args(cut, cut_at), dir.path() / "cut.log"), 0) << slurp(dir.path() / "cut.log");
  const auto checkpoints = list_checkpoints(cut / "checkpoint");
  ASSERT_EQ(checkpoints.size(), 2u);
  fs::remove(checkpoints.front());
  const Checkpoint c = read_checkpoint(checkpoints.back());
  ASSERT_TRUE(c.departed.present);
  const std::string rows = slurp(cut / "outflow.csv");
  std::printf("checkpoint at t = %g s: %lld grains gone, outflow.csv %llu of %zu bytes\n", c.time,
              static_cast<long long>(c.departed.totals.count), static_cast<unsigned long long>(c.output.outflow_bytes),
              rows.size());
  EXPECT_GT(c.departed.totals.count, 0);                  // some left before the checkpoint
  EXPECT_LT(c.output.outflow_bytes + 100, rows.size());  // and more after it, rows the resume cuts
  ASSERT_EQ(run({"resume", cut.string(), "--set", "simulation.duration=" + duration}, dir.path() / "resume.log"), 0)
      << slurp(dir.path() / "resume.log");
  expect_same_outputs(ref, cut, true);  // the state's record of the --set values differs
  const auto results = [](const fs::path& out) {
    const std::string json = slurp(out / "run.json");
    return json.substr(json.find("\"results\""));
  };
  EXPECT_NE(results(ref).find("\"outflow_count\""), std::string::npos) << results(ref);
  EXPECT_EQ(results(ref), results(cut));
}

// Velocity Verlet: ended at 0.15 s, resumed from 0.1 s to 0.2 s.
TEST(Resume, DuringADischargeFromAnEarlierCheckpointTheRunEndsBitIdentical) {
  expect_discharge_resume_bit_identical({}, "0.2", "0.15", "10000");
}

// Block steps (1 ms; a grain gone through the face is removed at the end of the step in
// which it crossed): ended at 0.12 s, resumed from 0.08 s to 0.15 s.
TEST(Resume, DuringADischargeFromAnEarlierCheckpointTheRunEndsBitIdentical_BlockSteps) {
  expect_discharge_resume_bit_identical({"simulation.integrator=\"block_hermite\"", "simulation.dt=1e-3"}, "0.15", "0.12",
                                        "40");
}

// An insertion region (tests/scenarios/insertion_bin.toml, a bin filled from above): a run
// ended at t = 0.15 s while grains are still inserted, its newest checkpoint lost, resumes
// from t = 0.1 s to 0.3 s: the insertion's stream (its next grain, its waiting grains, its
// counts) goes on from the checkpoint's, and every output ends as the uninterrupted run's.
TEST(Resume, DuringAnInsertionFromAnEarlierCheckpointTheRunEndsBitIdentical) {
  TempDir dir;
  const fs::path ref = dir.path() / "ref", cut = dir.path() / "cut";
  auto args = [&](const fs::path& out, const char* duration) {
    return std::vector<std::string>{"run", (kScenarios / "insertion_bin.toml").string(), "--out", out.string(), "--set",
                                    "output.checkpoint_every_steps=5000", "--set", "output.vtk_interval=0.05", "--set",
                                    std::string("simulation.duration=") + duration};
  };
  ASSERT_EQ(run(args(ref, "0.3"), dir.path() / "ref.log"), 0) << slurp(dir.path() / "ref.log");
  ASSERT_EQ(run(args(cut, "0.15"), dir.path() / "cut.log"), 0) << slurp(dir.path() / "cut.log");
  auto checkpoints = list_checkpoints(cut / "checkpoint");
  ASSERT_GE(checkpoints.size(), 2u);
  while (checkpoints.size() > 1 && read_checkpoint(checkpoints.back()).time > 0.1 + 1e-9) {
    fs::remove(checkpoints.back());
    checkpoints.pop_back();
  }
  const Checkpoint c = read_checkpoint(checkpoints.back());
  ASSERT_TRUE(c.inflow.present);
  std::printf("checkpoint at t = %g s: %zu grains in the bin\n", c.time, c.particles.size());
  EXPECT_GT(c.particles.size(), 50u);
  ASSERT_EQ(run({"resume", cut.string(), "--set", "simulation.duration=0.3"}, dir.path() / "resume.log"), 0)
      << slurp(dir.path() / "resume.log");
  expect_same_outputs(ref, cut, true);  // the state's record of the --set values differs
  const auto results = [](const fs::path& out) {
    const std::string json = slurp(out / "run.json");
    return json.substr(json.find("\"results\""));
  };
  EXPECT_NE(results(ref).find("\"inflow_released\""), std::string::npos) << results(ref);
  EXPECT_EQ(results(ref), results(cut));
}

// A run of `scenario` to 0.2 s against one ended at 0.16 s, its checkpoints after 0.12 s lost,
// and resumed from 0.12 s: the same outputs.
void resume_bit_identical(const char* scenario, const std::vector<std::string>& settings = {}) {
  TempDir dir;
  const fs::path ref = dir.path() / "ref", cut = dir.path() / "cut";
  auto args = [&](const fs::path& out, const char* duration) {
    std::vector<std::string> a{"run", (kScenarios / scenario).string(), "--out", out.string(), "--set",
                               "output.checkpoint_every_steps=4000", std::string("--set"),
                               std::string("simulation.duration=") + duration};
    for (const std::string& s : settings) a.push_back("--set"), a.push_back(s);
    return a;
  };
  ASSERT_EQ(run(args(ref, "0.2"), dir.path() / "ref.log"), 0) << slurp(dir.path() / "ref.log");
  ASSERT_EQ(run(args(cut, "0.16"), dir.path() / "cut.log"), 0) << slurp(dir.path() / "cut.log");
  auto checkpoints = list_checkpoints(cut / "checkpoint");
  while (checkpoints.size() > 1 && read_checkpoint(checkpoints.back()).time > 0.12 + 1e-9) {
    fs::remove(checkpoints.back());
    checkpoints.pop_back();
  }
  const Checkpoint c = read_checkpoint(checkpoints.back());
  std::size_t with_spring = 0;
  for (const Contact& k : c.wall_contacts) with_spring += k.touching && !(k.history.xi == Vec3{});
  std::printf("checkpoint at t = %g s: %zu wall contacts with a spring\n", c.time, with_spring);
  EXPECT_GT(with_spring, 50u);
  ASSERT_EQ(run({"resume", cut.string(), "--set", "simulation.duration=0.2"}, dir.path() / "resume.log"), 0)
      << slurp(dir.path() / "resume.log");
  expect_same_outputs(ref, cut, true);
}

// Beads settling in a triangle-mesh hopper (tests/scenarios/mesh_hopper.toml) and a bed stirred
// by a turning paddle (mesh_mixer.toml; mesh_mixer_reverses.toml turns it back from 0.1 s and
// stops it at 0.15 s), each ended at t = 0.16 s and resumed from 0.12 s: the contacts with the
// meshes' triangles keep their springs, a turning mesh stands where its closed form puts it,
// and every output ends as the uninterrupted run's.
TEST(Resume, WithMeshContactsTheRunEndsBitIdentical) {
  for (const char* scenario : {"mesh_hopper.toml", "mesh_mixer.toml", "mesh_mixer_reverses.toml"})
    resume_bit_identical(scenario);
}
// The mixer with block steps: the particles' own times and Hermite state, and the contacts
// with the turning paddle, resume as the uninterrupted run.
TEST(Resume, WithMeshContactsTheRunEndsBitIdentical_BlockSteps) {
  resume_bit_identical("mesh_mixer.toml", {"simulation.integrator=\"block_hermite\""});
}

// A belt that stops (tests/scenarios/belt_stops.toml, surface_motion in stretches): a run
// ended at 0.045 s, after the belt stopped at 0.03 s, resumes to 0.06 s as the uninterrupted
// run: the surface's motion is that of the stretch holding the last step, not the first.
TEST(Resume, AfterASurfaceStretchEndedTheRunEndsBitIdentical) {
  TempDir dir;
  const fs::path ref = dir.path() / "ref", cut = dir.path() / "cut";
  auto args = [&](const fs::path& out, const char* duration) {
    return std::vector<std::string>{"run", (kScenarios / "belt_stops.toml").string(), "--out", out.string(), "--set",
                                    "output.checkpoint_every_steps=7500", "--set", "output.series_interval=5e-4", "--set",
                                    "output.vtk_interval=0.005", "--set", std::string("simulation.duration=") + duration};
  };
  ASSERT_EQ(run(args(ref, "0.06"), dir.path() / "ref.log"), 0) << slurp(dir.path() / "ref.log");
  ASSERT_EQ(run(args(cut, "0.045"), dir.path() / "cut.log"), 0) << slurp(dir.path() / "cut.log");
  // The world read back holds the belt standing still, as the run left it.
  const fs::path newest = list_checkpoints(cut / "checkpoint").front();
  Checkpoint c = read_checkpoint(newest);
  const World restored = world_of_checkpoint(load_scenario((kScenarios / "belt_stops.toml").string()), c, newest);
  EXPECT_EQ(restored.walls[0].surface_velocity, Vec3{});
  ASSERT_EQ(run({"resume", cut.string(), "--set", "simulation.duration=0.06"}, dir.path() / "resume.log"), 0)
      << slurp(dir.path() / "resume.log");
  expect_same_outputs(ref, cut, true);  // the state's record of the --set values differs
}

TEST(Resume, AfterSigkillDuringInflowTheRunEndsBitIdentical_VelocityVerlet) {
  // A smaller step than the scenario's: the run lasts a few seconds, long enough to be killed.
  expect_inflow_resume_bit_identical({"simulation.dt=5e-6", "output.checkpoint_every_steps=4000"});
}

TEST(Resume, AfterSigkillDuringInflowTheRunEndsBitIdentical_SymplecticEuler) {
  expect_inflow_resume_bit_identical(
      {"simulation.dt=5e-6", "output.checkpoint_every_steps=4000", "simulation.integrator=\"symplectic_euler\""});
}

TEST(Resume, AfterSigkillDuringInflowTheRunEndsBitIdentical_BlockHermite) {
  expect_inflow_resume_bit_identical({"simulation.integrator=\"block_hermite\""});
}

// Grains in touch on levels of their own within a spread (no state of its own: the levels are
// the stepper's).
TEST(Resume, AfterSigkillDuringInflowTheRunEndsBitIdentical_BlockHermiteLevelSpread) {
  expect_inflow_resume_bit_identical({"simulation.integrator=\"block_hermite\"", "simulation.block_steps.level_spread=2"});
}

// Hindered settling: the crowding is rebuilt from the state, never stored.
TEST(Resume, AfterSigkillDuringInflowTheRunEndsBitIdentical_HinderedVelocityVerlet) {
  expect_inflow_resume_bit_identical(
      {"simulation.dt=5e-6", "output.checkpoint_every_steps=4000", "fluid.hindered_settling=true"});
}

TEST(Resume, AfterSigkillDuringInflowTheRunEndsBitIdentical_HinderedBlockHermite) {
  expect_inflow_resume_bit_identical({"simulation.integrator=\"block_hermite\"", "fluid.hindered_settling=true"});
}

// SIGTERM (as SIGINT): a checkpoint of the step reached, run.json "interrupted", exit code 4;
// the resumed run ends as the uninterrupted one. Checkpoints here come from the signal and
// the end of the run only (every_steps beyond the run, none by wall time).
TEST(Resume, SigtermWritesAFinalCheckpointAndExitsWith4) {
  TempDir dir;
  const fs::path ref = dir.path() / "ref", cut = dir.path() / "cut";
  auto args = [&](const fs::path& out, const std::string& every) {
    return std::vector<std::string>{"run", (kScenarios / "checkpoint_model_p.toml").string(), "--out", out.string(),
                                    "--set", "output.checkpoint_every_steps=" + every,
                                    "--set", "output.checkpoint_every_seconds=0"};
  };
  ASSERT_EQ(run(args(ref, "1000000"), dir.path() / "ref.log"), 0) << slurp(dir.path() / "ref.log");
  const pid_t pid = spawn(args(cut, "1000000"), dir.path() / "cut.log");
  // No checkpoint to wait for: wait for the first rows of series.csv instead.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while ((!fs::exists(cut / "series.csv") || fs::file_size(cut / "series.csv") < 2000) &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  // A random moment within the first tenth of a second after that (the run lasts ~1 s).
  std::this_thread::sleep_for(std::chrono::milliseconds(std::random_device{}() % 100));
  kill(pid, SIGTERM);
  const int status = wait_for(pid);
  const std::string log = slurp(dir.path() / "cut.log");
  ASSERT_TRUE(WIFEXITED(status)) << log;
  ASSERT_EQ(WEXITSTATUS(status), 4) << log;
  EXPECT_NE(log.find("stopped by SIGTERM"), std::string::npos) << log;
  EXPECT_NE(slurp(cut / "run.json").find("\"status\": \"interrupted\""), std::string::npos);
  ASSERT_EQ(list_checkpoints(cut / "checkpoint").size(), 1u);
  const std::int64_t step = newest_step(cut);
  EXPECT_NE(log.find("after step " + std::to_string(step)), std::string::npos) << log;
  ASSERT_EQ(run({"resume", cut.string()}, dir.path() / "resume.log"), 0) << slurp(dir.path() / "resume.log");
  expect_same_outputs(ref, cut);
}

// A numerical failure writes no checkpoint of the failing state: the last good one is kept
// and named in the diagnostic; resuming from it fails again at the same step (determinism).
TEST(Resume, NumericalFailureKeepsTheLastGoodCheckpoint) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const std::vector<std::string> args = {"run", (kScenarios / "valid_small.toml").string(), "--out", out.string(),
                                         "--set", "simulation.dt=5e-5", "--set", "output.checkpoint_every_steps=20"};
  ASSERT_EQ(run(args, dir.path() / "run.log"), 3) << slurp(dir.path() / "run.log");
  const std::string log = slurp(dir.path() / "run.log");
  const auto files = list_checkpoints(out / "checkpoint");
  ASSERT_EQ(files.size(), 2u);
  const Checkpoint last = read_checkpoint(files[0]);
  EXPECT_NE(log.find("the last good checkpoint (step " + std::to_string(last.step) + ") is kept"), std::string::npos) << log;
  const auto at = log.find("step ");
  ASSERT_NE(at, std::string::npos);
  const long failed_at = std::stol(log.substr(at + 5));
  EXPECT_GT(failed_at, last.step);
  EXPECT_LE(failed_at, last.step + 20);
  EXPECT_NE(slurp(out / "run.json").find("last good checkpoint"), std::string::npos);

  ASSERT_EQ(run({"resume", out.string()}, dir.path() / "resume.log"), 3) << slurp(dir.path() / "resume.log");
  EXPECT_NE(slurp(dir.path() / "resume.log").find("step " + std::to_string(failed_at) + ","), std::string::npos)
      << slurp(dir.path() / "resume.log");
  EXPECT_EQ(list_checkpoints(out / "checkpoint").front(), files[0]) << "the failing state must not be checkpointed";
}

// Without frames (vtk_interval = 0) or tracked particles there is no .pvd or track.csv:
// checkpoints must still be written, and a finished run resumes to the same result.
TEST(Resume, WithoutFramesOrTrackAndOfAFinishedRun) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(run({"run", (kScenarios / "valid_small.toml").string(), "--out", out.string(), "--set",
                 "simulation.duration=0.005", "--set", "output.vtk_interval=0", "--set", "output.checkpoint_every_steps=300"},
                dir.path() / "run.log"),
            0)
      << slurp(dir.path() / "run.log");
  EXPECT_EQ(slurp(dir.path() / "run.log").find("warning"), std::string::npos) << slurp(dir.path() / "run.log");
  const auto files = list_checkpoints(out / "checkpoint");
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(read_checkpoint(files[0]).step, 1000);
  EXPECT_EQ(read_checkpoint(files[1]).step, 900);
  const std::string series = slurp(out / "series.csv");
  ASSERT_EQ(run({"resume", out.string()}, dir.path() / "resume.log"), 0) << slurp(dir.path() / "resume.log");
  EXPECT_EQ(slurp(out / "series.csv"), series);
  EXPECT_NE(slurp(out / "run.json").find("\"status\": \"ok\""), std::string::npos);
}

TEST(Resume, AFolderWithoutCheckpointsIsAnError) {
  TempDir dir;
  ASSERT_EQ(run({"resume", dir.path().string()}, dir.path() / "log"), 1);
  EXPECT_NE(slurp(dir.path() / "log").find("no checkpoint"), std::string::npos) << slurp(dir.path() / "log");
}

// `tsubu run valid_small.toml --out OUT --set sets...` to its end, its output in OUT.log.
void run_valid_small(const fs::path& out, const std::vector<std::string>& sets) {
  std::vector<std::string> args = {"run", (kScenarios / "valid_small.toml").string(), "--out", out.string()};
  for (const auto& set : sets) args.insert(args.end(), {"--set", set});
  const fs::path log = out.string() + ".log";
  ASSERT_EQ(run(args, log), 0) << slurp(log);
}

// `tsubu resume DIR --set simulation.duration=T2` extends a run that ended at T1: its outputs
// continue to the same bytes as those of a run of T2 from the start (T1 a multiple of the
// output intervals), the results and the sources' sizes in run.json agree, its loop time
// covers both sessions, and a later resume keeps the new duration.
TEST(Resume, SetDurationExtendsAFinishedRunBitIdentically) {
  TempDir dir;
  const fs::path ref = dir.path() / "ref", out = dir.path() / "out";
  const std::vector<std::string> sets = {"output.series_interval=0.0005", "output.vtk_interval=0.001", "output.track=[0, 5]",
                                         "output.track_interval=0.00025", "output.checkpoint_every_steps=700"};
  auto with = [&](const char* duration) {
    auto all = sets;
    all.push_back(std::string("simulation.duration=") + duration);
    return all;
  };
  ASSERT_NO_FATAL_FAILURE(run_valid_small(ref, with("0.01")));
  ASSERT_NO_FATAL_FAILURE(run_valid_small(out, with("0.005")));
  EXPECT_EQ(newest_step(out), 1000);
  const double first_loop = nlohmann::json::parse(slurp(out / "run.json"))["loop_time_s"].get<double>();
  ASSERT_EQ(run({"resume", out.string(), "--set", "simulation.duration=0.01"}, dir.path() / "resume.log"), 0)
      << slurp(dir.path() / "resume.log");
  expect_same_outputs(ref, out, true);
  const nlohmann::json extended = nlohmann::json::parse(slurp(out / "run.json"));
  const nlohmann::json whole = nlohmann::json::parse(slurp(ref / "run.json"));
  EXPECT_EQ(extended["results"], whole["results"]);
  EXPECT_TRUE(whole["results"].contains("solid_fraction"));
  // What the run measured is kept across the sessions: the sizes of its sources (they were
  // left out after a resume) and the stepping loops of both sessions.
  ASSERT_TRUE(extended.contains("sources")) << extended.dump();
  EXPECT_EQ(extended["sources"], whole["sources"]);
  EXPECT_EQ(whole["loop_sessions"], 1);
  EXPECT_EQ(extended["loop_sessions"], 2);
  EXPECT_GT(extended["loop_time_s"].get<double>(), first_loop);
  const Checkpoint c = read_checkpoint(list_checkpoints(out / "checkpoint").front());
  EXPECT_EQ(c.overrides.back(), "simulation.duration=0.01");
  EXPECT_NE(slurp(out / "checkpoint" / "overrides.txt").find("simulation.duration=0.01\n"), std::string::npos);
  // A later resume reads the extended run (its stored hash matches): nothing more to do.
  const std::string series = slurp(out / "series.csv");
  ASSERT_EQ(run({"resume", out.string()}, dir.path() / "again.log"), 0) << slurp(dir.path() / "again.log");
  EXPECT_EQ(slurp(out / "series.csv"), series);
}

// Block steps resumed at every checkpoint of the stretch in which grains reach the floor
// and each other: each run to T1, extended to T2, ends with the same bytes as the run of T2.
// The SIGKILL test above resumes at one random checkpoint; this one at each of eight, so
// that the state a contact event reads (a contact's touching flag and its evaluation at
// the step's end) is checked whatever the contact does at the cut. A first version of the
// corrector's release mark read the overlap of the evaluation before, which a checkpoint
// does not keep, and the run resumed at t = 0.016 s ended with other bits.
TEST(Resume, BlockStepsResumedAtEachCheckpointEndBitIdentical) {
  TempDir dir;
  const std::vector<std::string> common = {"--set", "output.vtk_interval=0.002", "--set", "output.series_interval=0.001",
                                           "--set", "output.track_interval=0.0005"};
  auto run_to = [&](const fs::path& out, const std::string& duration) {
    std::vector<std::string> args = {"run", (kScenarios / "block_sediment.toml").string(), "--out", out.string(), "--set",
                                     "simulation.duration=" + duration};
    args.insert(args.end(), common.begin(), common.end());
    ASSERT_EQ(run(args, out.string() + ".log"), 0) << slurp(out.string() + ".log");
  };
  const fs::path ref = dir.path() / "ref";
  ASSERT_NO_FATAL_FAILURE(run_to(ref, "0.03"));
  for (int k = 5; k <= 12; ++k) {  // t = 0.010 ... 0.024 s, every 20 steps
    const fs::path out = dir.path() / ("cut" + std::to_string(k));
    std::ostringstream t1;
    t1 << 0.002 * k;
    ASSERT_NO_FATAL_FAILURE(run_to(out, t1.str()));
    ASSERT_EQ(run({"resume", out.string(), "--set", "simulation.duration=0.03"}, out.string() + ".resume.log"), 0)
        << slurp(out.string() + ".resume.log");
    SCOPED_TRACE("resumed at t = " + t1.str() + " s");
    expect_same_outputs(ref, out, true);
  }
}

// Output intervals that follow from the duration (series_interval = duration/200) keep the
// run's values when a resume changes the duration: an override pins them for later resumes.
TEST(Resume, SetDurationKeepsIntervalsThatFollowFromTheDuration) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_NO_FATAL_FAILURE(
      run_valid_small(out, {"simulation.duration=0.002", "output.vtk_interval=0", "output.checkpoint_every_steps=300"}));
  ASSERT_EQ(run({"resume", out.string(), "--set", "simulation.duration=0.003"}, dir.path() / "resume.log"), 0)
      << slurp(dir.path() / "resume.log");
  const std::string series = slurp(out / "series.csv");
  EXPECT_EQ(std::count(series.begin(), series.end(), '\n'), 1 + 301);  // header, t = 0 and every 1e-5 s
  const Checkpoint c = read_checkpoint(list_checkpoints(out / "checkpoint").front());
  EXPECT_EQ(c.step, 600);
  char pinned[64];
  std::snprintf(pinned, sizeof pinned, "output.series_interval=%.17g", 0.002 / 200);
  EXPECT_NE(std::find(c.overrides.begin(), c.overrides.end(), pinned), c.overrides.end());
}

// Keys that could change the past are refused, naming the --set (exit 2); so is a duration
// the run has already passed and a value that is not one, and a key the scenario does not know
// is named unknown; the run's folder is left as it was.
TEST(Resume, SetRefusesKeysThatChangeThePast) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_NO_FATAL_FAILURE(run_valid_small(out, {"simulation.duration=0.002", "output.checkpoint_every_steps=300"}));
  const std::string series = slurp(out / "series.csv");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"simulation.dt=1e-6", "--set simulation.dt=1e-6:1: simulation.dt: cannot change on resume: "},
      {"contact.default.friction=0.1", "--set contact.default.friction=0.1:1: contact.default.friction: cannot change on resume: "},
      {"simulation.seed=4", "--set simulation.seed=4:1: simulation.seed: cannot change on resume: "},
      {"simulation.duration=0.001",
       "--set simulation.duration=0.001:1: simulation.duration: cannot change on resume: the run is already at step 400"},
      {"simulation.duration=\"long\"", "--set simulation.duration=\"long\":1: simulation.duration: "},
      // A key the scenario does not know is unknown, not one that cannot change.
      {"simulation.bogus=1", "--set simulation.bogus=1:1: simulation.bogus: unknown key; allowed here: "},
      {"simulation.duraton=1", "--set simulation.duraton=1:1: simulation.duraton: unknown key (did you mean 'duration'?)"},
  };
  for (const auto& [set, message] : cases) {
    const fs::path log = dir.path() / "resume.log";
    EXPECT_EQ(run({"resume", out.string(), "--set", set}, log), 2) << slurp(log);
    EXPECT_NE(slurp(log).find(message), std::string::npos) << slurp(log);
  }
  EXPECT_EQ(slurp(out / "series.csv"), series);
  EXPECT_EQ(newest_step(out), 400);
}

// A run without checkpoints cannot be resumed or extended, and resume says why.
TEST(Resume, ARunWithoutCheckpointsSaysSo) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_NO_FATAL_FAILURE(run_valid_small(out, {"simulation.duration=0.0005", "output.checkpoint_every_seconds=0"}));
  ASSERT_EQ(run({"resume", out.string(), "--set", "simulation.duration=0.001"}, dir.path() / "log"), 1);
  EXPECT_NE(slurp(dir.path() / "log").find("checkpoint_every_steps or checkpoint_every_seconds is above 0"), std::string::npos)
      << slurp(dir.path() / "log");
}

// Issue 25, item 1. A resume whose --set turns checkpoints off still ends with a checkpoint of
// its end, so that a plain resume afterwards has nothing to do (it used to resume from the
// older checkpoint, cutting series.csv and track.csv back and rolling run.json back). A resume
// that would delete rows past the end of the run it continues (left by a session without a
// checkpoint of its end) is refused, exit 2, naming them and the --set that keeps them.
TEST(Resume, ARunEndsWithACheckpointAndResumeNeverDeletesRowsPastItsEnd) {
  TempDir dir;
  const fs::path out = dir.path() / "out", old = dir.path() / "old";
  const fs::path log = dir.path() / "log";
  ASSERT_EQ(run({"run", (kScenarios / "inflow_small.toml").string(), "--out", out.string(), "--set",
                 "simulation.duration=0.05", "--set", "output.checkpoint_every_steps=500", "--set", "output.vtk_interval=0"},
                log),
            0)
      << slurp(log);
  fs::copy(out / "checkpoint", old);
  ASSERT_EQ(run({"resume", out.string(), "--set", "simulation.duration=0.1", "--set", "output.checkpoint_every_steps=0",
                 "--set", "output.checkpoint_every_seconds=0"},
                log),
            0)
      << slurp(log);
  EXPECT_EQ(newest_step(out), 5000) << "a resumed run ends with a checkpoint of its end";
  const std::string series = slurp(out / "series.csv"), track = slurp(out / "track.csv");
  ASSERT_EQ(run({"resume", out.string()}, log), 0) << slurp(log);
  EXPECT_EQ(slurp(out / "series.csv"), series);
  EXPECT_EQ(slurp(out / "track.csv"), track);
  EXPECT_NE(slurp(out / "run.json").find("\"steps\": 5000"), std::string::npos) << slurp(out / "run.json");

  // Only the checkpoints of the first run left: its end is t = 0.05 s, the outputs reach 0.1 s.
  fs::remove_all(out / "checkpoint");
  fs::copy(old, out / "checkpoint");
  ASSERT_EQ(run({"resume", out.string()}, log), 2) << slurp(log);
  const std::string message = slurp(log);
  EXPECT_NE(message.find(out.string() + " holds 10 rows of series.csv and "), std::string::npos) << message;
  EXPECT_NE(message.find("past t = 0.05 s, up to t = 0.1 s"), std::string::npos) << message;
  EXPECT_NE(message.find("resume with --set simulation.duration=0.1 to write them again"), std::string::npos) << message;
  EXPECT_EQ(slurp(out / "series.csv"), series);
  EXPECT_EQ(slurp(out / "track.csv"), track);
  ASSERT_EQ(run({"resume", out.string(), "--set", "simulation.duration=0.1"}, log), 0) << slurp(log);
  EXPECT_EQ(slurp(out / "series.csv"), series);
  EXPECT_EQ(slurp(out / "track.csv"), track);
}

// Issue 25, item 10: SIGTERM during long analyses (eight porosity analyses of 10^7 points:
// seconds per row) ends them a second later, between points, instead of waiting for the row:
// exit 4 naming the step whose outputs are not written; the outputs hold whole rows only.
TEST(Resume, SigtermInterruptsLongAnalyses) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  std::string analyses = "analyses=[";
  for (int k = 0; k < 8; ++k)
    analyses += (k ? ", " : "") + std::string("{type=\"porosity\", name=\"p") + std::to_string(k) +
                "\", points=10000000, z_range=[0.001, 0.02]}";
  analyses += "]";
  const pid_t pid = spawn({"run", (kScenarios / "valid_small.toml").string(), "--out", out.string(), "--set", analyses,
                           "--set", "output.vtk_interval=0"},
                          dir.path() / "run.log");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(pid, SIGTERM);
  const auto sent = std::chrono::steady_clock::now();
  const int status = wait_for(pid);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  const std::string log = slurp(dir.path() / "run.log");
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 4) << log;
  EXPECT_NE(log.find("stopped by SIGTERM during the analyses of step 0 (t = 0 s), whose outputs are not written; no "
                     "checkpoint was written before: run again"),
            std::string::npos)
      << log;
  EXPECT_LT(waited, 5.0) << "the row's analyses take longer: they were not interrupted";
  const std::string series = slurp(out / "series.csv");
  EXPECT_EQ(std::count(series.begin(), series.end(), '\n'), 1) << series;  // the header alone
  EXPECT_NE(slurp(out / "run.json").find("\"status\": \"interrupted\""), std::string::npos);
}
