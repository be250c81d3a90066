// Triangle-mesh files (src/tsubu/io/mesh_file.hpp, docs/scenario.md "Mesh files"): the unit
// cube of tests/meshes/ as ASCII STL, binary STL and OBJ gives the same 8 welded vertices and
// 12 triangles; every refusal names the file and line (or triangle) and what is wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "tsubu/io/mesh_file.hpp"
#include "tsubu_process.hpp"

namespace fs = std::filesystem;
using namespace tsubu;
using tsubu::testing::TempDir;

namespace {

const fs::path kMeshes = fs::path(TSUBU_SOURCE_DIR) / "tests" / "meshes";

using Point = std::array<double, 3>;
using Corners = std::array<Point, 3>;

// The mesh as a set of triangles of points, each turned to begin at its smallest corner (the
// orientation is kept): the geometry, whatever the numbering of vertices.
std::set<Corners> triangles_of(const MeshData& mesh) {
  std::set<Corners> out;
  for (const auto& t : mesh.triangles) {
    Corners c;
    for (int k = 0; k < 3; ++k) c[k] = {mesh.vertices[t[k]].x, mesh.vertices[t[k]].y, mesh.vertices[t[k]].z};
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    out.insert(c);
  }
  return out;
}

// The unit cube, each face split along the diagonal from its first corner as tests/meshes/
// has it, facing outwards.
std::set<Corners> unit_cube() {
  const Point v[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  MeshData mesh{{}, {}};
  for (const Point& p : v) mesh.vertices.push_back({p[0], p[1], p[2]});
  for (const auto& q : quads) {
    mesh.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])});
    mesh.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])});
  }
  return triangles_of(mesh);
}

void expect_unit_cube(const MeshData& mesh) {
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_EQ(triangles_of(mesh), unit_cube());
  // Every edge of a closed, welded surface is shared by exactly two triangles.
  std::multiset<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
  for (const auto& e : edges) EXPECT_EQ(edges.count(e), 2u);
}

void write(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>(v >> (8 * k) & 0xFF));
}

// A binary STL: the 80-byte header (padded), the count, each triangle's zero normal, corners
// and attribute.
std::string binary_stl(const std::string& header, const std::vector<std::array<Point, 3>>& triangles) {
  std::string out = header;
  out.resize(80, ' ');
  put_u32(out, static_cast<std::uint32_t>(triangles.size()));
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) put_u32(out, 0);
    for (const Point& p : t)
      for (double x : p) put_u32(out, std::bit_cast<std::uint32_t>(static_cast<float>(x)));
    out += std::string(2, '\0');
  }
  return out;
}

// The message of the MeshFileError that reading `path` throws.
std::string error_of(const fs::path& path) {
  try {
    read_mesh_file(path);
  } catch (const MeshFileError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " was read without an error";
  return "";
}

// The same for the file `name` written with `content` in `dir`.
std::string error_reading(const TempDir& dir, const std::string& name, const std::string& content) {
  write(dir.path() / name, content);
  return error_of(dir.path() / name);
}

// A bad file: the line its error names and a phrase of its message.
struct BadFile {
  std::string text, line, phrase;
};

// Each bad file, written as `name`: its message begins with "<path>:<line>: " and holds the phrase.
void expect_errors(const TempDir& dir, const std::string& name, const std::vector<BadFile>& files) {
  for (const BadFile& f : files) {
    const std::string message = error_reading(dir, name, f.text);
    EXPECT_EQ(message.rfind((dir.path() / name).string() + ":" + f.line + ": ", 0), 0u) << message << "\n" << f.text;
    EXPECT_NE(message.find(f.phrase), std::string::npos) << message << "\n" << f.text;
  }
}

// An ASCII STL facet.
std::string facet(const std::string& a, const std::string& b, const std::string& c) {
  return "facet normal 0 0 1\nouter loop\nvertex " + a + "\nvertex " + b + "\nvertex " + c + "\nendloop\nendfacet\n";
}

}  // namespace

TEST(MeshFile, TheCubeAsAsciiStlBinaryStlAndObjIsTheSameMesh) {
  expect_unit_cube(read_mesh_file(kMeshes / "cube.stl"));
  expect_unit_cube(read_mesh_file(kMeshes / "cube_binary.stl"));  // its header begins with "solid"
  expect_unit_cube(read_mesh_file(kMeshes / "cube.obj"));         // quads, v/vt/vn, v//vn and v/vt
}

TEST(MeshFile, ABinaryStlWrittenHereIsTheCube) {
  TempDir dir;
  const MeshData ascii = read_mesh_file(kMeshes / "cube.stl");
  std::vector<std::array<Point, 3>> triangles;
  for (const auto& t : ascii.triangles) {
    std::array<Point, 3> c;
    for (int k = 0; k < 3; ++k) c[k] = {ascii.vertices[t[k]].x, ascii.vertices[t[k]].y, ascii.vertices[t[k]].z};
    triangles.push_back(c);
  }
  for (const std::string header : {"cube", "solid cube", "  SOLID cube"}) {
    write(dir.path() / "cube.stl", binary_stl(header, triangles));
    const MeshData binary = read_mesh_file(dir.path() / "cube.stl");
    expect_unit_cube(binary);
    EXPECT_EQ(binary.triangles, ascii.triangles) << "the same order of first appearance";
  }
}

// Vertices are numbered by first appearance; the same coordinates (0 and -0 too) are one.
TEST(MeshFile, VerticesAtTheSameCoordinatesAreWelded) {
  TempDir dir;
  write(dir.path() / "two.stl", "solid two\n" + facet("0 0 0", "1 0 0", "1 1 0") + facet("-0 0 0", "1 1 0", "0 1 0") +
                                    "endsolid two\n");
  const MeshData stl = read_mesh_file(dir.path() / "two.stl");
  const std::vector<Vec3> corners = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_EQ(stl.vertices, corners);
  EXPECT_FALSE(std::signbit(stl.vertices[0].x)) << "the first occurrence's coordinates";
  EXPECT_EQ(stl.triangles, (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}}));

  // OBJ: repeated v lines are one vertex; a vertex no face names is not in the mesh.
  write(dir.path() / "two.obj", "v 5 5 5\nv 1 0 0\nv 0 0 0\nv 1 1 0\nv 0 0 0\nv 0 1 0\nf 3 2 4\nf 5 4 6\n");
  const MeshData obj = read_mesh_file(dir.path() / "two.obj");
  EXPECT_EQ(obj.vertices, corners);
  EXPECT_EQ(obj.triangles, stl.triangles);
}

TEST(MeshFile, SeveralSolidsKeywordsInAnyCaseBlankLinesAndCrLf) {
  TempDir dir;
  std::string text = "solid a\n" + facet("0 0 0", "1 0 0", "0 1 0") + "endsolid a\n\n  \nSOLID\n" +
                     "FACET Normal 1e0 +0 -0.0\n  Outer LOOP\nVertex 0 0 1\nVERTEX 1 0 1\nvertex 0 1 1\nEndLoop\nENDFACET\n" +
                     "EndSolid whatever\n";
  write(dir.path() / "two.stl", text);
  const MeshData lf = read_mesh_file(dir.path() / "two.stl");
  EXPECT_EQ(lf.vertices.size(), 6u);
  EXPECT_EQ(lf.triangles.size(), 2u);
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  write(dir.path() / "two.stl", crlf);
  EXPECT_EQ(read_mesh_file(dir.path() / "two.stl").vertices, lf.vertices);
}

TEST(MeshFile, ObjNegativeIndicesCountBackFromTheLastVertexAbove) {
  TempDir dir;
  write(dir.path() / "neg.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nf -4/1/1 -2//3 -1/7\n");
  const MeshData mesh = read_mesh_file(dir.path() / "neg.obj");
  EXPECT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.triangles, (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}}));
}

TEST(MeshFile, ExtensionsInAnyCaseAndOthersRefused) {
  TempDir dir;
  fs::copy_file(kMeshes / "cube.obj", dir.path() / "cube.OBJ");
  fs::copy_file(kMeshes / "cube.stl", dir.path() / "cube.Stl");
  expect_unit_cube(read_mesh_file(dir.path() / "cube.OBJ"));
  expect_unit_cube(read_mesh_file(dir.path() / "cube.Stl"));
  const std::string ply = error_reading(dir, "cube.ply", "ply\n");
  EXPECT_NE(ply.find("cube.ply: unknown extension \".ply\""), std::string::npos) << ply;
  EXPECT_NE(ply.find(".stl"), std::string::npos) << ply;
  EXPECT_NE(ply.find(".obj"), std::string::npos) << ply;
  const std::string none = error_reading(dir, "cube", "solid\n");
  EXPECT_NE(none.find("cube: no file extension"), std::string::npos) << none;
}

TEST(MeshFile, AFileThatCannotBeOpenedIsNamedWithTheReason) {
  TempDir dir;
  const fs::path missing = dir.path() / "missing.stl";
  EXPECT_EQ(error_of(missing), missing.string() + ": cannot open: No such file or directory");
  const fs::path folder = dir.path() / "folder.obj";
  fs::create_directory(folder);
  EXPECT_EQ(error_of(folder), folder.string() + ": cannot open: Is a directory");
}

TEST(MeshFile, AsciiStlErrorsNameTheLine) {
  TempDir dir;
  const std::string good = facet("0 0 0", "1 0 0", "0 1 0");
  const std::vector<BadFile> cases = {
      {"solid\n" + good + "facet normal 0 0 1\nouter loop\nvertex 0 0 1\nvertx 0 0 1\n", "12",
       "expected \"vertex x y z\", found \"vertx 0 0 1\""},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", "5", "the file ends inside a facet"},
      {"solid\n" + good, "8", "the file ends inside a solid (expected \"endsolid [name]\")"},
      {"solid\nfacet normal 0 0\n", "2", "expected \"facet normal nx ny nz\" or \"endsolid [name]\""},
      {"solid\nfacet normal 0 0 one\n", "2", "expected \"facet normal nx ny nz\""},
      {"solid\nfacet 0 0 1\n", "2", "found \"facet 0 0 1\""},
      {"solid\nfacet normal 0 0 1\nouter\n", "3", "expected \"outer loop\", found \"outer\""},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n", "4", "expected \"vertex x y z\""},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0 0\n", "4", "expected \"vertex x y z\""},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 x\n", "4", "\"x\" is not a number"},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 1.5.2\n", "4", "\"1.5.2\" is not a number"},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 nan 0\n", "4", "coordinate \"nan\" is not finite"},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 -inf 0\n", "4", "coordinate \"-inf\" is not finite"},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 1e999 0\n", "4", "\"1e999\" is beyond the range of a double"},
      {"solid\n" + good + "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 0 0\nendloop\n", "9",
       "the facet has two corners at the same point (1, 0, 0): it has no normal"},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 1\nvertex 2 2 2\n", "2",
       "the facet has zero area (its corners (0, 0, 0), (1, 1, 1), (2, 2, 2) are on one line)"},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e300 0 0\nvertex 0 1e300 0\n", "2",
       "the facet is too large for its normal to be computed in doubles"},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e154 0 0\nvertex 0 1e154 0\n", "2",
       "the facet is too large for its normal to be computed in doubles"},  // |n|, not n, overflows
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e-100 0 0\nvertex 0 1e-100 0\n", "2",
       "the facet is too small for its normal to be computed in doubles"},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendloop\n", "8",
       "expected \"endfacet\", found \"endloop\""},
      {"solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendfacet\n", "7",
       "expected \"endloop\", found \"endfacet\""},
      {"solid\n" + good + "endsolid\nsolid\n" + good + "endsolid\nfacet\n", "19", "expected \"solid [name]\", found \"facet\""},
  };
  expect_errors(dir, "bad.stl", cases);
}

TEST(MeshFile, AFileWithoutTrianglesIsRefused) {
  TempDir dir;
  const std::string stl = error_reading(dir, "empty.stl", "solid empty\nendsolid empty\n");
  EXPECT_EQ(stl, (dir.path() / "empty.stl").string() + ": the file holds no triangles");
  const std::string obj = error_reading(dir, "empty.obj", "# nothing\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_EQ(obj, (dir.path() / "empty.obj").string() + ": the file holds no triangles");
  const std::string binary = error_reading(dir, "empty_binary.stl", binary_stl("empty", {}));
  EXPECT_EQ(binary, (dir.path() / "empty_binary.stl").string() + ": the file holds no triangles");
}

TEST(MeshFile, ObjErrorsNameTheLine) {
  TempDir dir;
  const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  const std::vector<BadFile> cases = {
      {square + "f 1 2 0\n", "5", "vertex index 0 in \"0\": indices start at 1"},
      {square + "f 1 2 5\n", "5", "vertex index 5 is out of range: 4 vertices are defined above this face"},
      {square + "f 1 2 -5\n", "5", "vertex index -5 is out of range"},
      {square + "f 1 2 99999999999999999999999\n", "5", "is out of range"},
      {"v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", "3", "vertex index 3 is out of range: 2 vertices are defined above"},
      {square + "f 1 2\n", "5", "a face needs at least 3 vertices, found 2"},
      {square + "f\n", "5", "a face needs at least 3 vertices, found 0"},
      {square + "f 1 2 3/\n", "5", "malformed vertex reference \"3/\" (expected i, i/t, i//n or i/t/n)"},
      {square + "f 1 2 3/x/1\n", "5", "malformed vertex reference \"3/x/1\""},
      {square + "f 1 2 3/1/1/1\n", "5", "malformed vertex reference \"3/1/1/1\""},
      {square + "f 1 2 //3\n", "5", "malformed vertex reference \"//3\""},
      {square + "f 1 2 3.0\n", "5", "malformed vertex reference \"3.0\""},
      {"v 0 0 0\nv 1 0 O\n", "2", "expected \"v x y z [w]\", found \"v 1 0 O\" (\"O\" is not a number)"},
      {"v 0 0 0\nv 1 0\n", "2", "expected \"v x y z [w]\", found \"v 1 0\""},
      {"v 0 0 0\nv 1 0 0 1 1\n", "2", "expected \"v x y z [w]\""},
      {"v 0 0 0\nv 1 0 0 w\n", "2", "\"w\" is not a number"},
      {"# a comment\n\nv 0 inf 0\n", "3", "coordinate \"inf\" is not finite"},
      {square + "F 1 2 3\n", "5", "unknown statement \"F\""},
      {square + "f 1 2 2\n", "5", "the face has two corners at the same point (1, 0, 0): it has no normal"},
      {square + "v 0 0 0\nf 1 2 5\n", "6", "the face has two corners at the same point (0, 0, 0)"},
      {square + "v 2 0 0\nf 1 2 5\n", "6", "the face has zero area"},
      {square + "v 2 2 0\nf 1 2 3 5\n", "6", "triangle 2 of the face (its vertices 1, 3, 4) has zero area"},
  };
  expect_errors(dir, "bad.obj", cases);
}

TEST(MeshFile, ObjIgnoresWhatHoldsNoTriangles) {
  TempDir dir;
  write(dir.path() / "ignored.obj",
        "# comment\nmtllib a.mtl\no thing\ng group\ns 1\nusemtl red\nv 0 0 0 1 # w and a comment\nv 1 0 0\nv 0 1 0\n"
        "vt 0 0\nvn 0 0 1\nl 1 2\np 1\n\t\nf 1/1/1 2/1/1 3/1/1 # end\n");
  const MeshData mesh = read_mesh_file(dir.path() / "ignored.obj");
  EXPECT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.triangles.size(), 1u);
}

// Binary STL: the size must be 84 + 50 n for the header's n; without that the file is ASCII
// only when it begins with "solid".
TEST(MeshFile, BinaryStlWhoseSizeDoesNotMatchItsCountIsRefused) {
  TempDir dir;
  std::string part = binary_stl("part", {});
  part.replace(80, 4, std::string("\xE8\x03\x00\x00", 4));  // 1000 triangles
  part += std::string(30000, '\0');
  const std::string message = error_reading(dir, "part.stl", part);
  EXPECT_EQ(message.rfind((dir.path() / "part.stl").string() +
                              ": binary STL: the header says 1000 triangles (50084 bytes), the file has 30084 bytes",
                          0),
            0u)
      << message;
  const std::string short_file = error_reading(dir, "short.stl", "not an STL");
  EXPECT_NE(short_file.find("short.stl: binary STL: the file has 10 bytes, fewer than the 84 of the header"),
            std::string::npos)
      << short_file;
  const std::string empty = error_reading(dir, "empty.stl", "");
  EXPECT_NE(empty.find("binary STL: the file has 0 bytes"), std::string::npos) << empty;
  // One byte more than its one triangle: not binary, and as text it begins with "solid".
  const std::string one = binary_stl("solid one", {{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}});
  write(dir.path() / "one.stl", one);
  EXPECT_EQ(read_mesh_file(dir.path() / "one.stl").triangles.size(), 1u);
  const std::string longer = error_reading(dir, "longer.stl", one + " ");
  EXPECT_EQ(longer.rfind((dir.path() / "longer.stl").string() + ":1: ", 0), 0u) << longer;
}

TEST(MeshFile, BinaryStlErrorsNameTheTriangle) {
  TempDir dir;
  const Point o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::string path = (dir.path() / "b.stl").string();
  EXPECT_EQ(error_reading(dir, "b.stl", binary_stl("b", {{o, x, y}, {o, {nan, 0, 0}, y}})),
            path + ": binary STL: triangle 2 (at byte 134) has a coordinate that is not finite (nan)");
  EXPECT_EQ(error_reading(dir, "b.stl", binary_stl("b", {{o, x, y}, {o, x, {1e39, 0, 0}}})),  // float: inf
            path + ": binary STL: triangle 2 (at byte 134) has a coordinate that is not finite (inf)");
  EXPECT_EQ(error_reading(dir, "b.stl", binary_stl("b", {{o, x, x}})),
            path + ": binary STL: triangle 1 (at byte 84) has two corners at the same point (1, 0, 0): it has no normal");
  EXPECT_EQ(error_reading(dir, "b.stl", binary_stl("b", {{o, x, y}, {o, x, {2, 0, 0}}, {o, x, y}})).rfind(
                path + ": binary STL: triangle 2 (at byte 134) has zero area", 0),
            0u);
  // The facet normal is not read: NaN there is no error.
  std::string nan_normal = binary_stl("b", {{o, x, y}});
  nan_normal.replace(84, 4, std::string("\x00\x00\xC0\x7F", 4));
  write(dir.path() / "normal.stl", nan_normal);
  EXPECT_EQ(read_mesh_file(dir.path() / "normal.stl").triangles.size(), 1u);
}
