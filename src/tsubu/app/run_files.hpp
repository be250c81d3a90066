// The files a run writes as it goes (docs/cli.md, output folder): series.csv, track.csv,
// outflow.csv, profiles/ and frames/. Opened fresh, or for a resume cut back to the sizes its checkpoint
// recorded (the rows after it are written again, the same bits); written row by row;
// flushed at least every second; synced before a checkpoint refers to them.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tsubu/analysis/measures.hpp"
#include "tsubu/analysis/profiles.hpp"
#include "tsubu/app/checkpoint.hpp"
#include "tsubu/io/checked_file.hpp"
#include "tsubu/io/frames.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/sim/simulation.hpp"

namespace tsubu {

class RunFiles {
 public:
  // `analyses`: the names of the analyses' series columns (AnalysisMonitor::names); `from`:
  // the checkpoint a resume continues from, or null for a fresh run.
  RunFiles(const Scenario& sc, const Simulation& sim, const std::filesystem::path& out_dir,
           const std::vector<std::string>& analyses, const Checkpoint* from);

  // A series.csv row of the state now (and a row in each profiles file): energies, contacts,
  // the moving walls' displacement and load, the block steps' levels, the inflow's grains and
  // mass, then the analyses' values.
  void series_row(const Simulation& sim, const Energies& e, const ContactTotals& c, const std::vector<double>& analyses);
  // track.csv rows of the tracked grains present now.
  void track_rows(const World& world);
  // outflow.csv rows: grains gone through an open face.
  void departure_rows(const std::vector<Departure>& departures);
  // The next VTK frame.
  void frame(const Simulation& sim) { frames_.write(sim.world(), sim.forces()); }
  // Rows reach the files (tail -f, a kill before the first checkpoint): flushed, not synced.
  void flush();
  // Everything written so far is on disk: before a checkpoint that refers to it.
  void sync();
  // What a checkpoint records of the files: their sizes and the frames so far.
  OutputState state() const;
  void close();

 private:
  const Scenario& sc_;
  std::filesystem::path series_path_, track_path_, outflow_path_;
  CheckedFile series_, track_, outflow_;
  std::optional<ProfileWriter> profiles_;
  FrameSeries frames_;
  std::vector<std::size_t> moving_walls_;  // walls with a motion: two series columns each
};

}  // namespace tsubu
