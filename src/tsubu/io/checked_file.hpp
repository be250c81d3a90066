// Output whose every write is checked (docs/reliability.md): a write(2) that fails (disk
// full, quota, I/O error) throws WriteError naming the file and the reason, so no output can
// end short without the run knowing. CheckedFile, a stream, throws from the `<<`, flush or
// close that hit it; write_file_atomically writes a whole file or leaves the old one.
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <ostream>
#include <streambuf>
#include <string>

namespace tsubu {

// Throws WriteError "cannot <what> <path>: <the reason of err>" (err an errno value).
[[noreturn]] void throw_write_error(const std::string& what, const std::filesystem::path& path, int err);

// Writes the n bytes at data to fd, retrying interrupted writes; a failure throws WriteError
// naming `path`.
void write_all(int fd, const char* data, std::size_t n, const std::filesystem::path& path);

// Writes `bytes` (or what `fill` writes to the open descriptor) to path.tmp, fsyncs it,
// renames it to `path` and fsyncs the folder. Failures throw WriteError (so does sync_file).
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);
void write_file_atomically(const std::filesystem::path& path, const std::function<void(int fd)>& fill);
// fsync of an existing file (data written through another handle).
void sync_file(const std::filesystem::path& path);

class CheckedFile : public std::ostream {
 public:
  enum class Mode { truncate, append };
  CheckedFile();
  explicit CheckedFile(const std::filesystem::path& path, Mode mode = Mode::truncate);
  // Writes what is buffered and closes, without throwing: call close() to know it worked.
  ~CheckedFile() override;
  CheckedFile(const CheckedFile&) = delete;
  CheckedFile& operator=(const CheckedFile&) = delete;

  void open(const std::filesystem::path& path, Mode mode = Mode::truncate);  // throws WriteError
  bool is_open() const { return buffer_.fd >= 0; }
  void close();  // writes what is buffered and closes; throws WriteError

 private:
  // A plain buffer in front of write(2); its failures throw, and the stream lets them
  // through (exceptions(badbit)).
  struct Buffer : std::streambuf {
    int fd = -1;
    std::string path;
    char data[8192];  // as std::filebuf: the files grow on disk as often as before
    Buffer() { setp(data, data + sizeof data); }
    void drain();  // throws WriteError
    int_type overflow(int_type c) override;
    int sync() override;
  };
  Buffer buffer_;
};

}  // namespace tsubu
