// libFuzzer target: the mesh file readers must answer any bytes with a mesh or a MeshFileError
// (never crash, hang or allocate without bound). See docs/reliability.md.
// The first byte chooses the reader, odd .obj and even .stl (tools/fuzz.sh seeds "1" before
// an OBJ file and "0" before an STL); the rest is the file, written to a temporary file since
// read_mesh_file reads a path.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "tsubu/io/mesh_file.hpp"

namespace {

// The two files of this process, removed at its exit.
struct FuzzFiles {
  std::filesystem::path stl, obj;
  FuzzFiles() {
    const std::filesystem::path base = std::filesystem::temp_directory_path() / ("tsubu_fuzz_mesh_" + std::to_string(::getpid()));
    stl = base.string() + ".stl";
    obj = base.string() + ".obj";
  }
  ~FuzzFiles() {
    std::error_code ignored;
    std::filesystem::remove(stl, ignored);
    std::filesystem::remove(obj, ignored);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const FuzzFiles files;
  if (size == 0) return 0;
  const std::filesystem::path& path = (data[0] & 1) ? files.obj : files.stl;
  // A new file each time: ext4 flushes a file truncated and written again when it is closed
  // (auto_da_alloc), some 4 ms a run against 0.1 ms for a removed and created one.
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data + 1),
                                                                static_cast<std::streamsize>(size - 1));
  try {
    const tsubu::MeshData mesh = tsubu::read_mesh_file(path);
    // What is accepted is a mesh: at least one triangle, each naming three distinct vertices.
    if (mesh.triangles.empty()) __builtin_trap();
    for (const auto& t : mesh.triangles)
      for (std::uint32_t v : t)
        if (v >= mesh.vertices.size() || t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) __builtin_trap();
  } catch (const tsubu::MeshFileError&) {
  }
  return 0;
}
