// Runs of the `tsubu` binary (TSUBU_BINARY) for tests of whole runs: a temporary folder per
// test, fork/exec with the output in a log file, and file contents.
#pragma once
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace tsubu::testing {

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A folder removed at the end unless the test failed (then its path is printed).
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("tsubu_ckpt_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" + std::to_string(getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    if (::testing::Test::HasFailure()) std::fprintf(stderr, "kept %s\n", path_.c_str());
    else std::filesystem::remove_all(path_);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// tsubu started with its stdout and stderr in `log`; `in_child` runs in the child before
// exec (limits, signal dispositions).
inline pid_t spawn(const std::vector<std::string>& args, const std::filesystem::path& log,
                   const std::function<void()>& in_child = {}) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) dup2(fd, 1), dup2(fd, 2);
    if (in_child) in_child();
    std::vector<char*> argv{const_cast<char*>(TSUBU_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(TSUBU_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

inline int wait_for(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

// Exit code of a run to completion; its output in `log`.
inline int run(const std::vector<std::string>& args, const std::filesystem::path& log,
               const std::function<void()>& in_child = {}) {
  const int status = wait_for(spawn(args, log, in_child));
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace tsubu::testing
