// Triangle meshes read from files: STL (ASCII or binary) and Wavefront OBJ (docs/scenario.md,
// "Mesh files"). The rules:
// - Welding: vertices with exactly the same coordinates (as doubles; -0 is 0) are one vertex,
//   numbered by first appearance in the triangles, so that triangles share their edges (STL
//   repeats every corner) and the result does not depend on hashing.
// - STL, ASCII: `solid [name]`, facets of `facet normal nx ny nz` / `outer loop` / three
//   `vertex x y z` / `endloop` / `endfacet`, then `endsolid [name]`; several solids; keywords
//   in any case; blank lines anywhere; the normal must be three numbers and is not used. Any
//   other line is an error naming it and what was expected.
// - STL, binary: 80-byte header, little-endian uint32 count n, 50 bytes per triangle (normal,
//   three float32 corners, 2-byte attribute); the file must hold exactly 84 + 50 n bytes,
//   which is checked before anything is allocated.
// - Which STL: binary when the size is 84 + 50 n for the n of bytes 80-83 (a binary header may
//   begin with "solid" too); else ASCII when it begins with "solid" after blanks; else the
//   binary size error.
// - OBJ: `v x y z [w]`; `f` with 3 or more references `i`, `i/t`, `i//n` or `i/t/n` (only i
//   is used: 1-based, negative counts back from the last vertex above the face), split into a
//   fan from its first vertex; `vt vn o g s usemtl mtllib l p` and `#` comments are ignored,
//   any other statement is an error.
// - Every file: finite coordinates; no triangle with a repeated vertex, zero area (cross
//   product exactly zero) or a cross product whose length a double cannot hold (0 or
//   infinite: a triangle far too small or too large): such a triangle has no normal; at
//   least one triangle. Text files are read a line at a time.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "tsubu/core/vec3.hpp"

namespace tsubu {

// A triangle mesh as a file gives it, in the file's units: vertices shared between triangles
// (a vertex is one point however many triangles name it), each triangle three vertex indices.
struct MeshData {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// A mesh file that cannot be read: what() is "<path>:<line>: <what is wrong>" for text files
// (line 1-based), "<path>: <what is wrong>" (naming the byte offset or triangle) for binary STL.
class MeshFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads an STL file (ASCII or binary, told apart by content: a binary STL may begin with
// "solid" too) or an OBJ file (chosen by the extension .obj, case-insensitive; .stl for STL;
// any other extension is an error naming the two allowed).
MeshData read_mesh_file(const std::filesystem::path& path);

}  // namespace tsubu
