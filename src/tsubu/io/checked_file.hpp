// An output file whose every write is checked (docs/reliability.md): a write(2) that fails
// (disk full, quota, I/O error) throws WriteError naming the file and the reason from the
// `<<`, flush or close that hit it, so no output can end short without the run knowing.
#pragma once
#include <filesystem>
#include <ostream>
#include <streambuf>
#include <string>

namespace tsubu {

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
