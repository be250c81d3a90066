// Profiles along z of an [[analyses]] entry of type "profiles" (docs/scenario.md,
// [[analyses]]): the range z_low < z < z_high cut into slices of equal thickness, and in each
// the solid fraction (exact sphere-slab volumes, whole and per size class), and over the
// grains whose centre lies in it the mean coordination, mean velocity, granular temperature
// and D10/D50/D90 by mass. ProfileWriter appends them to one CSV per quantity.
#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tsubu/analysis/grain_sizes.hpp"
#include "tsubu/io/checked_file.hpp"
#include "tsubu/scenario/scenario.hpp"
#include "tsubu/world/world.hpp"

namespace tsubu {

struct Profiles {
  std::vector<double> centre;          // m, of each slice
  std::vector<long> grains;            // centres in the slice
  std::vector<double> solid_fraction;  // solid volume / slice volume (full x-y cross-section)
  std::vector<std::vector<double>> class_fraction;  // [class][slice]: the same for one size class
  std::vector<double> coordination;    // mean particle-particle contacts per grain
  std::vector<Vec3> velocity;          // m/s, mean over the grains
  std::vector<double> temperature;     // m^2/s^2, (1/3) mean |v - mean v|^2
  std::vector<MassPercentiles> sizes;  // m
};

// The profiles of `a` (kind profiles) on w's state. Means over a slice without grains are
// NaN. A grain belongs to size class k when class_edges[k] <= d < class_edges[k+1]; grains
// below the first edge count in the first class, those at or above the last in the last.
Profiles measure_profiles(const AnalysisSpec& a, const World& w);

// Appends a row per series.csv row to folder/<quantity>.csv: rows are times, columns slice
// centres; the header names the quantity and its unit.
class ProfileWriter {
 public:
  // Fresh files with their headers, or (a resume) the files cut back to their header and
  // `rows` rows, those of the series.csv rows before the checkpoint.
  ProfileWriter(const AnalysisSpec& a, const std::filesystem::path& folder, std::optional<std::size_t> rows);
  void write(const World& w);
  void flush();
  void close();
  std::vector<std::filesystem::path> paths() const;

 private:
  struct Column {
    std::filesystem::path path;
    std::unique_ptr<CheckedFile> file;
  };
  AnalysisSpec spec_;
  std::vector<Column> files_;  // in the order of write()
};

}  // namespace tsubu
