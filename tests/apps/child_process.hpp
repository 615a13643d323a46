// Runs the built `vlpground` in a child process with its stdout/stderr captured; waits on its
// output or exit with bounded timeouts (never sleeps).
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace vlpground::test {

class ChildProcess {
 public:
  explicit ChildProcess(const std::vector<std::string>& args);
  ~ChildProcess();  // kills the child if still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Reads output until stderr contains `text`; false on exit or timeout.
  bool wait_for_stderr(const std::string& text, int timeout_ms);
  /// Reads output until the child exits; returns the exit code, or -1 (timeout), or
  /// 128 + signal when it was killed by a signal.
  int wait_exit(int timeout_ms);
  void signal(int sig);

  std::string out, err;

 private:
  bool pump(int timeout_ms);  // one poll round; false when both pipes are closed
  pid_t pid_ = -1;
  int out_fd_ = -1, err_fd_ = -1;
  int status_ = -1;
};

/// Runs to completion (timeout 60 s).
struct RunResult {
  int code;
  std::string out, err;
};
RunResult run_cli(const std::vector<std::string>& args);

}  // namespace vlpground::test
