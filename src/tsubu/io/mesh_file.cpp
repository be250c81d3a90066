#include "tsubu/io/mesh_file.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>

#include "tsubu/core/format.hpp"
#include "tsubu/core/random.hpp"

namespace tsubu {
namespace {

// ---- The mesh as it is read -------------------------------------------------------------

// "(x, y, z)". Appended piece by piece: GCC 12 at -O3 warns falsely (-Wrestrict) on
// "literal" + std::string&&.
std::string show(const Vec3& p) {
  std::string s = "(";
  for (int k = 0; k < 3; ++k) s.append(k ? ", " : "").append(format_number(p[k]));
  return s.append(")");
}

// A point's coordinates as bits, -0 as 0: equal keys are exactly the same point.
struct PointKey {
  std::array<std::uint64_t, 3> bits;
  bool operator==(const PointKey&) const = default;
};

PointKey key_of(const Vec3& p) {
  const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x == 0 ? 0.0 : x); };
  return {{bits(p.x), bits(p.y), bits(p.z)}};
}

struct PointHash {
  std::size_t operator()(const PointKey& k) const {
    return static_cast<std::size_t>(mix64(k.bits[0] ^ mix64(k.bits[1] ^ mix64(k.bits[2]))));
  }
};

// Welds the vertices (one index per point, in the order of first appearance) and refuses
// triangles the engine cannot give a normal.
class MeshBuilder {
 public:
  explicit MeshBuilder(std::string path) : path_(std::move(path)) {}

  // The index of the (finite) point p, new or the earlier vertex at the same coordinates.
  std::uint32_t vertex(const Vec3& p) {
    const auto [at, added] = index_.try_emplace(key_of(p), static_cast<std::uint32_t>(mesh_.vertices.size()));
    if (added) {
      // 32-bit indices: a file this large (some 100 GB) would wrap them around.
      if (mesh_.vertices.size() == std::numeric_limits<std::uint32_t>::max())
        throw MeshFileError(path_ + ": more than " + std::to_string(mesh_.vertices.size()) + " vertices");
      mesh_.vertices.push_back(p);
    }
    return at->second;
  }

  // Adds the triangle, or calls fail(what is wrong with it) when it has no normal.
  template <class Fail>
  void triangle(const std::array<std::uint32_t, 3>& t, Fail&& fail) {
    const Vec3& a = mesh_.vertices[t[0]];
    const Vec3& b = mesh_.vertices[t[1]];
    const Vec3& c = mesh_.vertices[t[2]];
    if (t[0] == t[1] || t[0] == t[2]) fail("has two corners at the same point " + show(a) + ": it has no normal");
    if (t[1] == t[2]) fail("has two corners at the same point " + show(b) + ": it has no normal");
    const Vec3 n = cross(b - a, c - a);
    const auto corners = [&] { return show(a) + ", " + show(b) + ", " + show(c); };  // for a message only
    if (n == Vec3{}) fail("has zero area (its corners " + corners() + " are on one line): it has no normal");
    // The normal is n / |n|: |n| must be a double above 0 (TriangleMesh refuses the others).
    const double length = norm(n);
    if (!std::isfinite(length)) fail("is too large for its normal to be computed in doubles (corners " + corners() + ")");
    if (!(length > 0)) fail("is too small for its normal to be computed in doubles (corners " + corners() + ")");
    mesh_.triangles.push_back(t);
  }

  void reserve_triangles(std::size_t n) { mesh_.triangles.reserve(n); }

  // The mesh read, which must have a triangle.
  MeshData finish() {
    if (mesh_.triangles.empty()) throw MeshFileError(path_ + ": the file holds no triangles");
    return std::move(mesh_);
  }

 private:
  std::string path_;
  MeshData mesh_;
  std::unordered_map<PointKey, std::uint32_t, PointHash> index_;
};

// ---- Files ------------------------------------------------------------------------------

struct CloseFile {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, CloseFile>;

// The file opened for reading and its size in bytes. A folder opens under Linux and fails only
// at the first read: it is refused here, with its reason.
File open_file(const std::filesystem::path& path, std::uint64_t& size) {
  File f(std::fopen(path.c_str(), "rb"));
  struct stat info {};
  if (f && ::fstat(::fileno(f.get()), &info) != 0) f.reset();
  if (!f) throw MeshFileError(path.string() + ": cannot open: " + std::strerror(errno));
  if (S_ISDIR(info.st_mode)) throw MeshFileError(path.string() + ": cannot open: " + std::strerror(EISDIR));
  size = static_cast<std::uint64_t>(info.st_size);
  return f;
}

[[noreturn]] void read_failed(const std::string& path) {
  throw MeshFileError(path + ": cannot read: " + std::strerror(errno));
}

// A text file read a line at a time (a line's length is the only memory it takes), each
// line split into words; its errors name the line.
class TextFile {
 public:
  // `comment`: a character that starts a comment running to the end of the line ('\0': none).
  TextFile(std::FILE* f, std::string path, char comment) : file_(f), path_(std::move(path)), comment_(comment) {}

  // Moves to the next line that holds a word; false at the end of the file.
  bool next() {
    do {
      if (!read_line()) return false;
      split();
    } while (words_.empty());
    return true;
  }
  // The next line that holds a word, which the file must have: its end is an error naming the
  // last line, `inside` what ("a facet") and the `form` expected there.
  void next_inside(std::string_view inside, std::string_view form) {
    if (!next()) fail("the file ends inside " + std::string(inside) + " (expected \"" + std::string(form) + "\")");
  }

  std::uint64_t line() const { return line_; }
  std::span<const std::string_view> words() const { return words_; }

  [[noreturn]] void fail(const std::string& what) const { fail_at(line_, what); }
  [[noreturn]] void fail_at(std::uint64_t line, const std::string& what) const {
    throw MeshFileError(path_ + ":" + std::to_string(line) + ": " + what);
  }
  // The line is not of the form expected; `why` (may be empty) says which word is wrong.
  [[noreturn]] void expected(std::string_view form, const std::string& why = "") const {
    fail("expected \"" + std::string(form) + "\", found \"" + shown() + "\"" + (why.empty() ? "" : " (" + why + ")"));
  }

 private:
  bool read_line() {
    text_.clear();
    int c = 0;
    while ((c = std::getc(file_)) != EOF && c != '\n') text_.push_back(static_cast<char>(c));
    if (std::ferror(file_)) read_failed(path_);
    if (c == EOF && text_.empty()) return false;
    ++line_;
    return true;
  }
  void split() {
    words_.clear();
    std::string_view rest(text_);
    if (comment_ != '\0') rest = rest.substr(0, rest.find(comment_));
    constexpr std::string_view blanks = " \t\r\f\v";
    for (std::size_t start = rest.find_first_not_of(blanks); start != std::string_view::npos;) {
      const std::size_t end = std::min(rest.find_first_of(blanks, start), rest.size());
      words_.push_back(rest.substr(start, end - start));
      start = rest.find_first_not_of(blanks, end);
    }
  }
  // The line's words as the message shows them: a long line is cut, bytes that are not
  // printable (a binary file read as text) are shown as '?'.
  std::string shown() const {
    std::string s;
    for (std::string_view w : words_) s.append(s.empty() ? "" : " ").append(w);
    if (s.size() > 80) s = s.substr(0, 77) + "...";
    std::ranges::replace_if(s, [](unsigned char c) { return !std::isprint(c); }, '?');
    return s;
  }

  std::FILE* file_;
  std::string path_;
  char comment_;
  std::uint64_t line_ = 0;
  std::string text_;
  std::vector<std::string_view> words_;
};

// ---- Numbers ----------------------------------------------------------------------------

enum class Number { ok, malformed, out_of_range };

// A decimal number as from_chars reads it (the same in every locale), also with a leading '+'.
Number read_number(std::string_view word, double& x) {
  if (word.size() > 1 && word[0] == '+' && word[1] != '-' && word[1] != '+') word.remove_prefix(1);
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), x);
  if (end != word.data() + word.size()) return Number::malformed;
  if (ec == std::errc::result_out_of_range) return Number::out_of_range;
  return ec == std::errc() ? Number::ok : Number::malformed;
}

// The point of three coordinate words, which must be finite numbers; a word that is no
// number is the line's `form` not met.
Vec3 read_point(const TextFile& file, std::span<const std::string_view> words, std::string_view form) {
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    const std::string word(words[static_cast<std::size_t>(k)]);
    switch (read_number(word, p[k])) {
      case Number::malformed: file.expected(form, "\"" + word + "\" is not a number");
      case Number::out_of_range: file.fail("coordinate \"" + word + "\" is beyond the range of a double");
      case Number::ok: break;
    }
    if (!std::isfinite(p[k])) file.fail("coordinate \"" + word + "\" is not finite");
  }
  return p;
}

// ---- STL, ASCII -------------------------------------------------------------------------

bool is_keyword(std::string_view word, std::string_view keyword) {
  return std::ranges::equal(word, keyword, [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

// True when the line is the keywords (any case) and nothing else.
bool line_is(std::span<const std::string_view> words, std::string_view first, std::string_view second = "") {
  const std::size_t n = second.empty() ? 1 : 2;
  return words.size() == n && is_keyword(words[0], first) && (n == 1 || is_keyword(words[1], second));
}

constexpr std::string_view kFacet = "facet normal nx ny nz";
constexpr std::string_view kVertex = "vertex x y z";

// A facet from its first line ("facet normal ...", the current line) to "endfacet".
void read_facet(TextFile& file, MeshBuilder& mesh) {
  const auto normal = file.words();
  double unused = 0;
  const auto is_number = [&](std::string_view w) { return read_number(w, unused) != Number::malformed; };
  if (normal.size() != 5 || !is_keyword(normal[0], "facet") || !is_keyword(normal[1], "normal") ||
      !std::all_of(normal.begin() + 2, normal.end(), is_number))
    file.expected(std::string(kFacet) + "\" or \"endsolid [name]");
  const std::uint64_t facet_line = file.line();  // the facet's errors name its first line
  file.next_inside("a facet", "outer loop");
  if (!line_is(file.words(), "outer", "loop")) file.expected("outer loop");
  std::array<std::uint32_t, 3> corners{};
  for (auto& corner : corners) {
    file.next_inside("a facet", kVertex);
    const auto w = file.words();
    if (w.size() != 4 || !is_keyword(w[0], "vertex")) file.expected(kVertex);
    corner = mesh.vertex(read_point(file, w.subspan(1), kVertex));
  }
  mesh.triangle(corners, [&](const std::string& what) { file.fail_at(facet_line, "the facet " + what); });
  file.next_inside("a facet", "endloop");
  if (!line_is(file.words(), "endloop")) file.expected("endloop");
  file.next_inside("a facet", "endfacet");
  if (!line_is(file.words(), "endfacet")) file.expected("endfacet");
}

MeshData read_ascii_stl(std::FILE* f, const std::string& path) {
  TextFile file(f, path, '\0');
  MeshBuilder mesh(path);
  while (file.next()) {
    if (!is_keyword(file.words()[0], "solid")) file.expected("solid [name]");
    for (;;) {
      file.next_inside("a solid", "endsolid [name]");
      if (is_keyword(file.words()[0], "endsolid")) break;
      read_facet(file, mesh);
    }
  }
  return mesh.finish();
}

// ---- STL, binary ------------------------------------------------------------------------

constexpr std::uint64_t kHeaderBytes = 84;    // 80 bytes of header, the uint32 count
constexpr std::uint64_t kTriangleBytes = 50;  // normal, three corners (float32), attribute

std::uint32_t little_endian_u32(const unsigned char* b) {
  return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 | std::uint32_t{b[3]} << 24;
}

// The triangle count of a binary STL of `size` bytes whose header is `header` (84 bytes), or
// nothing when the size does not match it.
std::optional<std::uint32_t> binary_count(const unsigned char* header, std::uint64_t size) {
  const std::uint32_t n = little_endian_u32(header + 80);
  if (size != kHeaderBytes + kTriangleBytes * n) return std::nullopt;
  return n;
}

MeshData read_binary_stl(std::FILE* f, const std::string& path, std::uint32_t count) {
  MeshBuilder mesh(path);
  mesh.reserve_triangles(count);  // the file holds them: its size was checked
  for (std::uint32_t k = 1; k <= count; ++k) {
    const std::uint64_t offset = kHeaderBytes + kTriangleBytes * (k - 1);
    const auto fail = [&](const std::string& what) {
      throw MeshFileError(path + ": binary STL: triangle " + std::to_string(k) + " (at byte " +
                          std::to_string(offset) + ") " + what);
    };
    unsigned char record[kTriangleBytes];
    if (std::fread(record, 1, sizeof record, f) != sizeof record) {
      if (std::ferror(f)) read_failed(path);
      fail("is cut short: the file shrank while it was read");
    }
    std::array<std::uint32_t, 3> corners{};
    for (std::size_t c = 0; c < 3; ++c) {
      Vec3 p;
      for (int i = 0; i < 3; ++i) {
        const auto bits = little_endian_u32(record + 12 * (c + 1) + 4 * static_cast<std::size_t>(i));
        p[i] = std::bit_cast<float>(bits);
        if (!std::isfinite(p[i])) fail("has a coordinate that is not finite (" + format_number(p[i]) + ")");
      }
      corners[c] = mesh.vertex(p);
    }
    mesh.triangle(corners, fail);
  }
  return mesh.finish();
}

// ---- STL: which one ---------------------------------------------------------------------

// True when the file, after blanks, begins with "solid" (any case), as an ASCII STL does.
bool begins_with_solid(std::FILE* f) {
  int c = 0;
  while ((c = std::getc(f)) != EOF && std::isspace(c)) {
  }
  for (char k : std::string_view("solid")) {
    if (c == EOF || std::tolower(c) != k) return false;
    c = std::getc(f);
  }
  return true;
}

MeshData read_stl(std::FILE* f, const std::string& path, std::uint64_t size) {
  unsigned char header[kHeaderBytes];
  const bool whole_header = std::fread(header, 1, sizeof header, f) == sizeof header;
  if (std::ferror(f)) read_failed(path);
  if (whole_header) {
    if (const auto count = binary_count(header, size)) return read_binary_stl(f, path, *count);
  }
  std::rewind(f);
  if (begins_with_solid(f)) {
    std::rewind(f);
    return read_ascii_stl(f, path);
  }
  if (std::ferror(f)) read_failed(path);
  const std::string not_ascii = " (nor is it an ASCII STL, which begins with \"solid\")";
  if (!whole_header)
    throw MeshFileError(path + ": binary STL: the file has " + std::to_string(size) + " bytes, fewer than the " +
                        std::to_string(kHeaderBytes) + " of the header" + not_ascii);
  const std::uint32_t n = little_endian_u32(header + 80);
  throw MeshFileError(path + ": binary STL: the header says " + std::to_string(n) + " triangles (" +
                      std::to_string(kHeaderBytes + kTriangleBytes * n) + " bytes), the file has " +
                      std::to_string(size) + " bytes" + not_ascii);
}

// ---- OBJ --------------------------------------------------------------------------------

// Statements that hold nothing of the triangles: texture coordinates, normals, names,
// groups, smoothing, materials, lines and points.
constexpr std::string_view kIgnored[] = {"vt", "vn", "o", "g", "s", "usemtl", "mtllib", "l", "p"};

// An integer index of a vertex reference ("3", "-1"), beyond any range when too long for a
// long long; nothing when it is no integer.
std::optional<long long> read_index(std::string_view word) {
  long long i = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), i);
  if (word.empty() || end != word.data() + word.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range)
    return word[0] == '-' ? -std::numeric_limits<long long>::max() : std::numeric_limits<long long>::max();
  if (ec != std::errc()) return std::nullopt;
  return i;
}

// A vertex reference's form: `i`, `i/t`, `i//n` or `i/t/n`, with integers i, t and n.
bool well_formed(std::string_view ref) {
  const std::size_t a = ref.find('/');
  if (!read_index(ref.substr(0, a))) return false;
  if (a == std::string_view::npos) return true;
  const std::size_t b = ref.find('/', a + 1);
  if (b == std::string_view::npos) return read_index(ref.substr(a + 1)).has_value();
  return (b == a + 1 || read_index(ref.substr(a + 1, b - a - 1))) && read_index(ref.substr(b + 1)) &&
         ref.find('/', b + 1) == std::string_view::npos;
}

// The OBJ file's vertices as the `v` lines give them, and the mesh's index of each once a
// face names it (so that unused vertices stay out of the mesh).
class ObjReader {
 public:
  ObjReader(std::FILE* f, const std::string& path) : file_(f, path, '#'), mesh_(path) {}

  MeshData read() {
    while (file_.next()) {
      const std::string_view keyword = file_.words()[0];
      if (keyword == "v") vertex();
      else if (keyword == "f") face();
      else if (std::ranges::find(kIgnored, keyword) == std::end(kIgnored))
        file_.fail("unknown statement \"" + std::string(keyword) +
                   "\" (read: v, f; ignored: vt, vn, o, g, s, usemtl, mtllib, l, p and # comments)");
    }
    return mesh_.finish();
  }

 private:
  static constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  static constexpr std::string_view kV = "v x y z [w]";

  void vertex() {
    const auto w = file_.words();
    if (w.size() != 4 && w.size() != 5) file_.expected(kV);
    double unused = 0;
    if (w.size() == 5 && read_number(w[4], unused) == Number::malformed)
      file_.expected(kV, "\"" + std::string(w[4]) + "\" is not a number");
    points_.push_back(read_point(file_, w.subspan(1, 3), kV));
    welded_.push_back(kUnused);
  }

  // The mesh's vertex named by a reference `i`, `i/t`, `i//n` or `i/t/n`.
  std::uint32_t reference(std::string_view ref) {
    if (!well_formed(ref))
      file_.fail("malformed vertex reference \"" + std::string(ref) + "\" (expected i, i/t, i//n or i/t/n)");
    const long long i = *read_index(ref.substr(0, ref.find('/')));
    const auto count = static_cast<long long>(points_.size());
    if (i == 0) file_.fail("vertex index 0 in \"" + std::string(ref) + "\": indices start at 1 (or at -1 from the last vertex)");
    const long long k = i > 0 ? i - 1 : count + i;
    if (k < 0 || k >= count)
      file_.fail("vertex index " + std::to_string(i) + " is out of range: " + std::to_string(count) +
                 " vertices are defined above this face");
    auto& welded = welded_[static_cast<std::size_t>(k)];
    if (welded == kUnused) welded = mesh_.vertex(points_[static_cast<std::size_t>(k)]);
    return welded;
  }

  // A face, split into a fan of triangles from its first vertex.
  void face() {
    const auto w = file_.words();
    if (w.size() < 4) file_.fail("a face needs at least 3 vertices, found " + std::to_string(w.size() - 1));
    std::vector<std::uint32_t> v;
    v.reserve(w.size() - 1);
    for (std::string_view ref : w.subspan(1)) v.push_back(reference(ref));
    for (std::size_t k = 1; k + 1 < v.size(); ++k) {
      mesh_.triangle({v[0], v[k], v[k + 1]}, [&](const std::string& what) {
        if (v.size() == 3) file_.fail("the face " + what);
        file_.fail("triangle " + std::to_string(k) + " of the face (its vertices 1, " + std::to_string(k + 1) + ", " +
                   std::to_string(k + 2) + ") " + what);
      });
    }
  }

  TextFile file_;
  MeshBuilder mesh_;
  std::vector<Vec3> points_;
  std::vector<std::uint32_t> welded_;
};

std::string lower(std::string s) {
  std::ranges::transform(s, s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

MeshData read_mesh_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::string extension = lower(path.extension().string());
  if (extension != ".stl" && extension != ".obj")
    throw MeshFileError(name + ": " +
                        (extension.empty() ? "no file extension" : "unknown extension \"" + path.extension().string() + "\"") +
                        ": a mesh file is .stl or .obj");
  std::uint64_t size = 0;
  const File f = open_file(path, size);
  if (extension == ".obj") return ObjReader(f.get(), name).read();
  return read_stl(f.get(), name, size);
}

}  // namespace tsubu
