// The fuzzers' sandbox (tests/unit/mesh/MeshReaderFuzzTest.cpp,
// tests/unit/scene/FuzzDriver.cpp): corrupted inputs are read in a forked
// child under an address-space limit, so that a reader that over-allocates
// fails there (bad_alloc, or a signal) instead of taking the machine, and a
// crash or hang is a finding about one case rather than the end of the run.
#pragma once

#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <functional>
#include <iostream>
#include <stdexcept>
#include <string>

namespace cms::fixtures {

/// A child started by forkLimited: its pid and the read end of its pipe.
struct LimitedChild {
  pid_t pid = -1;
  int fd = -1;
};

/// Forks; the child limits its address space to `bytes`, runs `body(fd)`
/// with `fd` the write end of a pipe to the parent, and leaves with
/// _exit(0) (no atexit handlers, no test-framework teardown in the child).
inline LimitedChild forkLimited(rlim_t bytes, const std::function<void(int fd)>& body) {
  int fd[2];
  if (pipe(fd) != 0) throw std::runtime_error("pipe failed");
  std::cout.flush();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    close(fd[0]);
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_AS, &limit);
    body(fd[1]);
    close(fd[1]);
    _exit(0);
  }
  close(fd[1]);
  return {pid, fd[0]};
}

/// Writes all of `s` to `fd`; false when the other end has gone.
inline bool writeAll(int fd, const std::string& s) {
  for (std::size_t done = 0; done < s.size();) {
    const ssize_t n = write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

/// Reads the child's pipe to its end, handing each chunk to `onData`, then
/// closes it and reaps the child; its wait status.
inline int finish(const LimitedChild& child, const std::function<void(const char*, std::size_t)>& onData) {
  char chunk[8192];
  for (ssize_t n; (n = read(child.fd, chunk, sizeof chunk)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    onData(chunk, static_cast<std::size_t>(n));
  }
  close(child.fd);
  int status = 0;
  while (waitpid(child.pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

}  // namespace cms::fixtures
