// The `tsubu` command line (docs/cli.md). Exit codes: 0 ok, 1 other error, 2 bad input
// (scenario, command line, output folder), 3 numerical failure, 4 stopped by SIGINT/SIGTERM
// (a checkpoint was written), 5 an output could not be written.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <utility>

#include "tsubu/app/export.hpp"
#include "tsubu/app/progress.hpp"
#include "tsubu/app/runner.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/ranks/communicator.hpp"
#include "tsubu/sim/inflow_feed.hpp"
#include "tsubu/sim/time_scales.hpp"
#include "tsubu/source/build_world.hpp"
#include "tsubu/version.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

constexpr int kMaxThreads = 1024;

// The threads of a run when --threads is not given: OMP_NUM_THREADS, as OpenMP programs
// read it, else 1. A value that is not one whole number from 1 to kMaxThreads is refused.
int threads_from_environment() {
  const char* text = std::getenv("OMP_NUM_THREADS");
  if (!text) return 1;
  char* end = nullptr;
  const long n = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || n < 1 || n > kMaxThreads)
    throw tsubu::UsageError(std::string("OMP_NUM_THREADS=") + text + ": must be a whole number of threads from 1 to " +
                            std::to_string(kMaxThreads) + " (or unset it, or give --threads N)");
  return static_cast<int>(n);
}

// The copies of this command an MPI launcher started (Open MPI's mpirun, or one that speaks
// PMI: MPICH's mpiexec, srun --mpi=pmi2), from the variables it sets for its processes:
// one when none did. Read before MPI starts (a run of one process never starts it).
tsubu::Processes launcher_processes() {
  tsubu::Processes processes;
  for (const auto& [size, rank_of] : {std::pair{"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"},
                                      std::pair{"PMI_SIZE", "PMI_RANK"}}) {
    const char* n = std::getenv(size);
    if (!n || std::atol(n) <= processes.count) continue;
    processes.count = static_cast<int>(std::atol(n));
    const char* r = std::getenv(rank_of);
    processes.rank = r ? static_cast<int>(std::atol(r)) : 0;
  }
  return processes;
}

// `tsubu check` and `tsubu export` are one process's work: N copies would each do it whole
// (into one folder), so they are refused (only process 0 says why, before MPI starts).
void refuse_several_processes(const tsubu::Processes& processes, const char* command) {
  if (processes.count == 1) return;
  if (processes.rank != 0) std::exit(2);
  throw tsubu::UsageError("started as " + std::to_string(processes.count) + " processes (mpirun): `tsubu " + command +
                          "` runs as one process; only `tsubu run` and `tsubu resume` split among processes "
                          "(docs/parallel.md)");
}

// Says a split run's failure on process `rank` and ends the whole job with `code`.
[[noreturn]] void ended_job(int rank, int code, const std::string& kind, const std::string& message) {
  std::fprintf(stderr, "tsubu: process %d: %s%s\n", rank, kind.c_str(), message.c_str());
  std::fflush(stderr);
  tsubu::Communicator::end_job(code);
}

// How an error ends the command: `kind` and `message` on stderr and exit code `code`. In a
// run split among processes, before MPI started every process met the same error (the same
// input) and only process 0 says it; afterwards a failing process other than 0 reports it to
// process 0 (Communicator::report_failure), which records it in run.json, says it naming the
// failing process and ends the whole job (Communicator::end_job), so that none waits for ever.
// Process 0's own error ends the job the same way. A stop by a signal is agreed by all
// processes, which end by themselves.
int ended(const tsubu::Processes& processes, int code, const std::string& kind, const std::string& message,
          bool agreed = false) {
  if (processes.count == 1 || agreed || !tsubu::Communicator::started()) {
    if (processes.rank == 0) std::fprintf(stderr, "%s%s\n", kind.c_str(), message.c_str());
    return code;
  }
  std::string line = kind;
  line.erase(0, line.find_first_not_of('\n'));  // no progress line to break here
  if (processes.rank != 0) tsubu::Communicator::world().report_failure(code, line, message);
  ended_job(processes.rank, code, line, message);
}

// What `tsubu check` prints about the time step (docs/cli.md, "Time scales and the time step").
void print_time_scales(const tsubu::Scenario& sc, tsubu::World world, int threads) {
  const tsubu::TimeScales ts = tsubu::time_scales(sc, world);
  std::printf("time scales (impact speed %.3g m/s: %s):\n", ts.impact_speed, ts.impact_reason.c_str());
  for (const tsubu::GrainTimes& g : ts.grains) {
    std::printf("  %s d = %.4g m: contact %.3g s, Rayleigh %.3g s", sc.materials[g.material].name.c_str(), g.diameter,
                g.contact_time, g.rayleigh_time);
    if (std::isfinite(g.relaxation_time))
      std::printf(", fluid relaxation %.3g s (at its terminal speed %.3g m/s)", g.relaxation_time, g.terminal_speed);
    std::printf("\n");
  }
  if (std::isfinite(ts.shortest_contact))
    std::printf("  shortest contact: %.3g s (%s)\n", ts.shortest_contact, ts.shortest_contact_what.c_str());
  if (ts.deepest_overlap > 0)
    std::printf("  deepest overlap: %.3g of the smaller diameter (%s; simulation.overlap_limit = %.3g)\n",
                ts.deepest_overlap, ts.deepest_overlap_what.c_str(), sc.overlap_limit);
  const char* verdict = ts.safe ? "safe" : ts.warnings.empty() ? "above the suggestion" : "NOT safe (see the warning)";
  std::printf("dt = %.3g s (%s): suggested dt <= %.3g s (%s); %s\n", sc.dt, tsubu::integrator_name(sc.integrator),
              ts.suggested_dt, ts.suggestion.c_str(), verdict);
  if (std::isfinite(ts.shortest_contact) && sc.integrator != tsubu::Integrator::block_hermite)
    std::printf("  %.3g steps per shortest contact\n", ts.shortest_contact / sc.dt);
  if (std::isfinite(ts.shortest_contact) && sc.integrator == tsubu::Integrator::block_hermite)
    std::printf("  block steps pay off while most grains fly free; where they rest in contact (a deposit, a packing) "
                "velocity Verlet was several times faster on the workloads measured (docs/integrators.md, \"Cost "
                "against velocity Verlet\"): check with --set 'simulation.integrator=\"velocity_verlet\"' for its dt\n");
  std::printf("steps: %lld\n", static_cast<long long>(ts.steps));
  const tsubu::WallTimeEstimate e = tsubu::estimate_wall_time(sc, std::move(world), 300, 1.0);
  const char* stop = sc.stops.empty() ? "" : "; to the duration: a [[stop]] may end the run sooner";
  if (!e.failure.empty())
    std::printf("estimated wall time: none, the timing sample failed after %lld steps: %s\n",
                static_cast<long long>(e.sampled_steps), e.failure.c_str());
  else if (!e.cannot.empty() && e.particles == 0)
    std::printf("estimated wall time: cannot estimate: %s\n", e.cannot.c_str());
  else if (!e.cannot.empty())
    std::printf("estimated wall time: cannot estimate: %s; the start's cost, %lld steps timed in %.3g s on %d thread%s, "
                "gives at least %.3g s%s\n",
                e.cannot.c_str(), static_cast<long long>(e.sampled_steps), e.sample_seconds, threads,
                threads == 1 ? "" : "s", e.run_seconds, stop);
  else
    std::printf("estimated wall time: %.3g s (%lld steps of the start timed in %.3g s on %d thread%s, %.2g contacts a "
                "grain: within about 2x while the grains stay as packed as at the start%s)\n",
                e.run_seconds, static_cast<long long>(e.sampled_steps), e.sample_seconds, threads, threads == 1 ? "" : "s",
                e.contacts_per_grain, stop);
  for (const std::string& w : ts.warnings) std::fprintf(stderr, "tsubu: WARNING: %s\n", w.c_str());
}

// The results in the order of the scenario, with their units.
void print_results(const tsubu::RunSummary& s) {
  for (std::size_t k = 0; k < s.result_order.size(); ++k)
    std::printf("  %s = %.6g%s%s\n", s.result_order[k].c_str(), s.results.at(s.result_order[k]),
                s.result_units[k].empty() ? "" : " ", s.result_units[k].c_str());
}

// Grains and sizes by mass of each [[particles]] source (an inflow: none before the run).
void print_sources(const std::vector<tsubu::SourceSizes>& sources) {
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const tsubu::SourceSizes& g = sources[k];
    std::printf("  particles.%zu: %ld grains", k, g.grains);
    if (g.grains > 0) std::printf(", D10 = %.6g m, D50 = %.6g m, D90 = %.6g m (by mass)", g.sizes.d10, g.sizes.d50, g.sizes.d90);
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tsubu: discrete element method engine for spherical grains"};
  app.set_version_flag("--version", std::string("tsubu ") + tsubu::kVersion);
  app.require_subcommand(1);

  std::string scenario_path, out_dir;
  std::vector<std::string> overrides;
  int threads = 0;  // 0: not given (OMP_NUM_THREADS, else 1)
  bool overwrite = false;

  auto* run = app.add_subcommand("run", "run a scenario");
  run->add_option("scenario", scenario_path, "scenario file (TOML)")->required();
  run->add_option("--out", out_dir, "output folder (default: out/<scenario name>)");
  run->add_option("--threads", threads, "OpenMP threads (default OMP_NUM_THREADS, else 1)")->check(CLI::Range(1, kMaxThreads));
  run->add_option("--set", overrides, "override a scenario value: key.path=value (TOML value)");
  run->add_flag("--overwrite", overwrite, "replace the outputs of an earlier run in the output folder (cleared first)");

  auto* check = app.add_subcommand("check", "validate a scenario and build its particles, without running");
  check->add_option("scenario", scenario_path, "scenario file (TOML)")->required();
  check->add_option("--set", overrides, "override a scenario value: key.path=value (TOML value)");
  check->add_option("--threads", threads, "OpenMP threads of the timing sample (default OMP_NUM_THREADS, else 1)")
      ->check(CLI::Range(1, kMaxThreads));

  std::string resume_dir;
  auto* resume = app.add_subcommand("resume", "continue an interrupted run from its newest valid checkpoint");
  resume->add_option("dir", resume_dir, "the run's output folder (holding checkpoint/)")->required();
  resume->add_option("--threads", threads, "OpenMP threads (default OMP_NUM_THREADS, else 1)")->check(CLI::Range(1, kMaxThreads));
  resume->add_option("--set", overrides,
                     "extend the run: simulation.duration, output.*_interval, output.checkpoint_every_* (TOML value)");

  std::string export_dir, export_to;
  double export_at = 0;
  auto* exporter = app.add_subcommand("export", "write a run's checkpoint as particle and contact CSV files");
  exporter->add_option("dir", export_dir, "the run's output folder (holding checkpoint/)")->required();
  auto* at = exporter->add_option("--at", export_at, "the checkpoint at or just before this time, s (default: the newest)");
  exporter->add_option("--to", export_to, "folder for the CSV files (default: DIR/export)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here with 0; every mistake on the command line is bad input.
    return app.exit(e) == 0 ? 0 : 2;
  }
  const tsubu::Processes processes = launcher_processes();
  try {
    if (check->parsed() || exporter->parsed()) refuse_several_processes(processes, check->parsed() ? "check" : "export");
    if (run->parsed() || resume->parsed()) tsubu::progress_log_interval();  // a bad TSUBU_LOG_INTERVAL: refused before any work
    if (exporter->parsed()) {
      if (at->count() && !std::isfinite(export_at))
        throw tsubu::UsageError("--at " + at->as<std::string>() + ": must be a time in seconds, a finite number");
      const tsubu::ExportedState e = tsubu::export_checkpoint(
          export_dir, at->count() ? std::optional<double>(export_at) : std::nullopt,
          export_to.empty() ? std::filesystem::path(export_dir) / "export" : std::filesystem::path(export_to));
      std::printf("exported %s (step %lld, t = %.9g s):\n  %s\n  %s\n", e.checkpoint.string().c_str(),
                  static_cast<long long>(e.step), e.time, e.particles.string().c_str(), e.contacts.string().c_str());
      return 0;
    }
    if (threads == 0) threads = threads_from_environment();
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    if (resume->parsed()) {
      const tsubu::RunSummary s = tsubu::resume_run(resume_dir, threads, processes.rank == 0, overrides, processes);
      if (processes.rank != 0) return 0;
      std::printf("resumed: %lld steps of %zu particles; output in %s\n", static_cast<long long>(s.steps), s.particles,
                  resume_dir.c_str());
      print_results(s);
      return 0;
    }
    const tsubu::Scenario sc = tsubu::load_scenario(scenario_path, overrides);
    if (check->parsed()) {
      tsubu::World w = tsubu::build_world(sc);
      std::printf("%s: ok (%zu particles, %zu walls, %zu materials)\n", scenario_path.c_str(), w.particles.size(),
                  w.walls.size(), sc.materials.size());
      print_sources(tsubu::source_sizes(w));
      if (const tsubu::ParticleSource* src = tsubu::inflow_source(sc))
        for (const auto& [k, v] : tsubu::InflowFeed(sc, *src, 0).rates()) std::printf("  %s = %.6g\n", k.c_str(), v);
      print_time_scales(sc, std::move(w), threads);
      return 0;
    }
    if (run->count("--out") > 0 && out_dir.empty()) throw tsubu::UsageError("--out is empty; give a folder name");
    if (out_dir.empty()) out_dir = sc.output.dir.empty() ? "out/" + sc.name : sc.output.dir;
    const tsubu::RunSummary s = tsubu::run_scenario(sc, out_dir, threads, processes.rank == 0, overwrite, processes);
    if (processes.rank != 0) return 0;
    std::printf("%s: %lld steps of %zu particles in %.3f s (%.4g particle-steps/s); output in %s\n", sc.name.c_str(),
                static_cast<long long>(s.steps), s.particles, s.wall_seconds,
                s.particle_steps_per_second(),
                out_dir.c_str());
    print_results(s);
    return 0;
  } catch (const tsubu::InputError& e) {
    return ended(processes, 2, "", e.what());
  } catch (const tsubu::UsageError& e) {
    return ended(processes, 2, "error: ", e.what());
  } catch (const tsubu::WriteError& e) {
    return ended(processes, 5, "\nwrite failure: ", e.what());
  } catch (const tsubu::NumericalError& e) {
    return ended(processes, 3, "numerical failure: ", e.what());
  } catch (const tsubu::Interrupted& e) {
    return ended(processes, 4, "\ninterrupted: ", e.what(), true);
  } catch (const tsubu::ProcessFailed& e) {  // on process 0: another process's failure
    ended_job(e.process, e.code, e.kind, e.what());
  } catch (const std::exception& e) {
    return ended(processes, 1, "error: ", e.what());
  }
}
