// Shared by the recorders' crash tests: a forked child that is killed and reaped, and a pipe on which the
// child reports counts (how many records it has flushed) to the parent.
#pragma once

#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>

#include <catch2/catch.hpp>

namespace incise::devices::testing {

// A forked child, killed and reaped when the test leaves early.
class Child {
 public:
  explicit Child(pid_t pid) : pid_(pid) {}
  ~Child() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  void kill() const { ::kill(pid_, SIGKILL); }
  // The wait status.
  int wait() {
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    return status;
  }

 private:
  pid_t pid_;
};

struct Pipe {
  int read_fd = -1;
  int write_fd = -1;
  Pipe() {
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    read_fd = fds[0];
    write_fd = fds[1];
  }
  ~Pipe() {
    if (read_fd >= 0) ::close(read_fd);
    if (write_fd >= 0) ::close(write_fd);
  }
  Pipe(const Pipe&) = delete;
  Pipe& operator=(const Pipe&) = delete;
};

// Child side: report a count to the parent. 8 bytes < PIPE_BUF, so the write is atomic.
inline void report(int fd, std::size_t count) {
  while (::write(fd, &count, sizeof count) < 0 && errno == EINTR) {
  }
}

// Parent side: the next count, or false when the child has gone.
inline bool receive(int fd, std::size_t& count) {
  std::size_t got = 0;
  while (got < sizeof count) {
    const ssize_t n = ::read(fd, reinterpret_cast<char*>(&count) + got, sizeof count - got);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    got += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace incise::devices::testing
