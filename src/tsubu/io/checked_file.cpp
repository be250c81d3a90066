#include "tsubu/io/checked_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "tsubu/core/error.hpp"

namespace tsubu {

namespace {

[[noreturn]] void fail_to(const std::string& what, const std::string& path, int err) {
  throw WriteError("cannot " + what + " " + path + ": " + std::strerror(err));
}

}  // namespace

void CheckedFile::Buffer::drain() {
  const char* p = pbase();
  std::size_t left = static_cast<std::size_t>(pptr() - pbase());
  setp(data, data + sizeof data);  // a failed write is not retried: the run stops
  while (left > 0) {
    const ssize_t k = ::write(fd, p, left);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) fail_to("write", path, k < 0 ? errno : ENOSPC);
    p += k;
    left -= static_cast<std::size_t>(k);
  }
}

CheckedFile::Buffer::int_type CheckedFile::Buffer::overflow(int_type c) {
  drain();
  if (!traits_type::eq_int_type(c, traits_type::eof())) {
    *pptr() = traits_type::to_char_type(c);
    pbump(1);
  }
  return traits_type::not_eof(c);
}

int CheckedFile::Buffer::sync() {
  if (fd >= 0) drain();
  return 0;
}

CheckedFile::CheckedFile() : std::ostream(&buffer_) { exceptions(std::ios::badbit); }

CheckedFile::CheckedFile(const std::filesystem::path& path, Mode mode) : CheckedFile() { open(path, mode); }

CheckedFile::~CheckedFile() {
  if (buffer_.fd < 0) return;
  try {
    buffer_.drain();
  } catch (const WriteError&) {  // reported by whoever needed the file complete (close())
  }
  ::close(buffer_.fd);
}

void CheckedFile::open(const std::filesystem::path& path, Mode mode) {
  close();
  const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (mode == Mode::append ? O_APPEND : O_TRUNC);
  buffer_.fd = ::open(path.c_str(), flags, 0644);
  if (buffer_.fd < 0) fail_to("create", path.string(), errno);
  buffer_.path = path.string();
  clear();
}

void CheckedFile::close() {
  if (buffer_.fd < 0) return;
  const int fd = buffer_.fd;
  try {
    buffer_.drain();
  } catch (...) {
    ::close(fd);
    buffer_.fd = -1;
    throw;
  }
  buffer_.fd = -1;
  if (::close(fd) != 0) fail_to("close", buffer_.path, errno);  // NFS reports some errors only here
}

}  // namespace tsubu
