// The `tsubu` command line (docs/cli.md). Exit codes: 0 ok, 1 other error, 2 bad input
// (scenario, command line, output folder), 3 numerical failure, 4 stopped by SIGINT/SIGTERM
// (a checkpoint was written), 5 an output could not be written.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>

#include "tsubu/app/progress.hpp"
#include "tsubu/app/runner.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/source/build_world.hpp"
#include "tsubu/version.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

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
  int threads = 1;
  bool overwrite = false;

  auto* run = app.add_subcommand("run", "run a scenario");
  run->add_option("scenario", scenario_path, "scenario file (TOML)")->required();
  run->add_option("--out", out_dir, "output folder (default: out/<scenario name>)");
  run->add_option("--threads", threads, "OpenMP threads (default 1)")->check(CLI::Range(1, 1024));
  run->add_option("--set", overrides, "override a scenario value: key.path=value (TOML value)");
  run->add_flag("--overwrite", overwrite, "replace the outputs of an earlier run in the output folder (cleared first)");

  auto* check = app.add_subcommand("check", "validate a scenario and build its particles, without running");
  check->add_option("scenario", scenario_path, "scenario file (TOML)")->required();
  check->add_option("--set", overrides, "override a scenario value: key.path=value (TOML value)");

  std::string resume_dir;
  auto* resume = app.add_subcommand("resume", "continue an interrupted run from its newest valid checkpoint");
  resume->add_option("dir", resume_dir, "the run's output folder (holding checkpoint/)")->required();
  resume->add_option("--threads", threads, "OpenMP threads (default 1)")->check(CLI::Range(1, 1024));
  resume->add_option("--set", overrides,
                     "extend the run: simulation.duration, output.*_interval, output.checkpoint_every_* (TOML value)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here with 0; every mistake on the command line is bad input.
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (!check->parsed()) tsubu::progress_log_interval();  // a bad TSUBU_LOG_INTERVAL: refused before any work
    if (resume->parsed()) {
#ifdef _OPENMP
      omp_set_num_threads(threads);
#endif
      const tsubu::RunSummary s = tsubu::resume_run(resume_dir, threads, true, overrides);
      std::printf("resumed: %lld steps of %zu particles; output in %s\n", static_cast<long long>(s.steps), s.particles,
                  resume_dir.c_str());
      print_results(s);
      return 0;
    }
    const tsubu::Scenario sc = tsubu::load_scenario(scenario_path, overrides);
    if (check->parsed()) {
      const tsubu::World w = tsubu::build_world(sc);
      std::printf("%s: ok (%zu particles, %zu walls, %zu materials)\n", scenario_path.c_str(), w.particles.size(),
                  w.walls.size(), w.materials.size());
      print_sources(tsubu::source_sizes(w));
      if (const tsubu::ParticleSource* src = tsubu::inflow_source(sc))
        for (const auto& [k, v] : tsubu::inflow_rates(tsubu::inflow_column(sc, *src))) std::printf("  %s = %.6g\n", k.c_str(), v);
      return 0;
    }
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    if (run->count("--out") > 0 && out_dir.empty()) throw tsubu::UsageError("--out is empty; give a folder name");
    if (out_dir.empty()) out_dir = sc.output.dir.empty() ? "out/" + sc.name : sc.output.dir;
    const tsubu::RunSummary s = tsubu::run_scenario(sc, out_dir, threads, true, overwrite);
    std::printf("%s: %lld steps of %zu particles in %.3f s (%.4g particle-steps/s); output in %s\n", sc.name.c_str(),
                static_cast<long long>(s.steps), s.particles, s.wall_seconds,
                s.particle_steps_per_second(),
                out_dir.c_str());
    print_results(s);
    return 0;
  } catch (const tsubu::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const tsubu::UsageError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const tsubu::WriteError& e) {
    std::fprintf(stderr, "\nwrite failure: %s\n", e.what());
    return 5;
  } catch (const tsubu::NumericalError& e) {
    std::fprintf(stderr, "numerical failure: %s\n", e.what());
    return 3;
  } catch (const tsubu::Interrupted& e) {
    std::fprintf(stderr, "\ninterrupted: %s\n", e.what());
    return 4;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
