// The frames of a run in OUT/frames/ (docs/cli.md, output folder): per frame the particles
// (frame_N.vtu), the contact network (contacts_N.vtp and contacts_N.csv) and the walls
// (walls_N.vtp), each kind indexed by time in its own .pvd. The folder is not called `vtk`:
// Python started in the output folder would import it in place of the vtk module.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tsubu/forces/force_field.hpp"
#include "tsubu/io/vtk.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

inline constexpr const char* kFramesDir = "frames";

class FrameSeries {
 public:
  // contacts: write the contact network with each frame; walls: the walls (when there are any).
  FrameSeries(const std::filesystem::path& out_dir, bool contacts, bool walls);
  // Continues a resumed run's frames (the particles' .pvd entries, frame k being entry k);
  // throws std::runtime_error naming a file of them that is missing.
  void restore(const std::vector<std::pair<double, std::string>>& frames);
  // Writes the next frame of `world`, whose contacts are those of forces' last evaluation.
  void write(const World& world, const ForceField& forces);
  const std::vector<std::pair<double, std::string>>& frames() const { return particles_.frames(); }
  std::int64_t count() const { return static_cast<std::int64_t>(frames().size()); }
  // The files written since the last mark_synced() (frames and indexes), to sync before a
  // checkpoint.
  const std::vector<std::filesystem::path>& unsynced() const { return unsynced_; }
  void mark_synced() { unsynced_.clear(); }

 private:
  std::filesystem::path dir_;
  bool contacts_, walls_;
  PvdIndex particles_, contact_index_, wall_index_;
  std::vector<std::filesystem::path> unsynced_;
  // The file names of frame k, e.g. contacts_00003.vtp.
  static std::string name(const char* stem, std::size_t k, const char* ext);
};

}  // namespace tsubu
