// ParaView output: one .vtu (XML UnstructuredGrid, one vertex per particle, base64 binary
// inline) per frame, and a .pvd collection indexing the frames by time. Writes are checked:
// a failure throws WriteError.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "tsubu/world/particles.hpp"

namespace tsubu {

void write_vtu(const std::string& path, const Particles& p);

class PvdIndex {
 public:
  explicit PvdIndex(std::string path) : path_(std::move(path)) {}
  // Adds a frame (file name relative to the .pvd) and rewrites the index.
  void add(double time, const std::string& file);
  // The frames so far, and setting them again when a run resumes (the file is rewritten at
  // the next add).
  const std::vector<std::pair<double, std::string>>& frames() const { return frames_; }
  void restore(std::vector<std::pair<double, std::string>> frames) { frames_ = std::move(frames); }

 private:
  std::string path_;
  std::vector<std::pair<double, std::string>> frames_;
};

}  // namespace tsubu
