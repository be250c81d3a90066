#include "tsubu/io/checked_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "tsubu/core/error.hpp"

namespace tsubu {

void throw_write_error(const std::string& what, const std::filesystem::path& path, int err) {
  throw WriteError("cannot " + what + " " + path.string() + ": " + std::strerror(err));
}

void write_all(int fd, const char* data, std::size_t n, const std::filesystem::path& path) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t k = ::write(fd, data + done, n - done);
    if (k < 0) {
      if (errno == EINTR) continue;
      throw_write_error("write", path, errno);
    }
    done += static_cast<std::size_t>(k);
  }
}

void write_file_atomically(const std::filesystem::path& path, const std::function<void(int fd)>& fill) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) throw_write_error("create", tmp, errno);
  // A failed write leaves no half-written .tmp behind (on a full disk it holds space).
  try {
    fill(fd);
    if (::fsync(fd) != 0) throw_write_error("fsync", tmp, errno);
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw_write_error("close", tmp, err);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw_write_error("rename to", path, errno);
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : ".";
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
  write_file_atomically(path, [&](int fd) { write_all(fd, bytes.data(), bytes.size(), path); });
}

void sync_file(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw_write_error("open", path, errno);
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw_write_error("fsync", path, errno);
}

void CheckedFile::Buffer::drain() {
  const char* p = pbase();
  std::size_t left = static_cast<std::size_t>(pptr() - pbase());
  setp(data, data + sizeof data);  // a failed write is not retried: the run stops
  while (left > 0) {
    const ssize_t k = ::write(fd, p, left);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) throw_write_error("write", path, k < 0 ? errno : ENOSPC);
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
  if (buffer_.fd < 0) throw_write_error("create", path.string(), errno);
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
  if (::close(fd) != 0) throw_write_error("close", buffer_.path, errno);  // NFS reports some errors only here
}

}  // namespace tsubu
