// ParaView output: per frame one .vtu of the particles (XML UnstructuredGrid, one vertex per
// particle), one .vtp of the contact network (PolyData, a line per contact) and one of the
// walls (a quad per plane wall), all base64 binary inline and carrying their time as
// TimeValue field data; .pvd collections index the frames by time. Arrays and units:
// docs/cli.md. Writes are checked: a failure throws WriteError.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "tsubu/io/contact_network.hpp"
#include "tsubu/world/domain.hpp"
#include "tsubu/world/particles.hpp"

namespace tsubu {

void write_vtu(const std::string& path, const Particles& p, double time);
// A line from particle i's centre along the branch vector per contact (a pair across a
// periodic boundary is drawn at i's side, its far end outside the box), the quantities as
// cell data.
void write_contacts_vtp(const std::string& path, const std::vector<NetworkContact>& contacts, double time, bool rolling);
// Each wall as the rectangle of its plane that covers the domain's shadow on it (for a wall
// normal to an axis: the box face), at the wall's current position.
void write_walls_vtp(const std::string& path, const std::vector<Wall>& walls, const Domain& domain, double time);

class PvdIndex {
 public:
  explicit PvdIndex(std::string path) : path_(std::move(path)) {}
  // Adds a frame (file name relative to the .pvd) and rewrites the index.
  void add(double time, const std::string& file);
  // The frames so far, and setting them again when a run resumes (the file is rewritten at
  // the next add).
  const std::vector<std::pair<double, std::string>>& frames() const { return frames_; }
  void restore(std::vector<std::pair<double, std::string>> frames) { frames_ = std::move(frames); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<std::pair<double, std::string>> frames_;
};

}  // namespace tsubu
