#include "tools/bench_tracker/child_process.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace hs {
namespace {

double kb_to_mb(long kb) {
  return static_cast<double>(kb) / 1024.0;
}

double seconds(const timeval& t) {
  return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
}

bool write_all(int fd, const std::string& s) {
  size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

[[noreturn]] void child_main(const std::string& what, const std::function<std::string()>& fn,
                             int fd) {
  int code = 0;
  try {
    if (!write_all(fd, fn())) {
      std::fprintf(stderr, "%s: cannot send the result: %s\n", what.c_str(), std::strerror(errno));
      code = 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", what.c_str(), e.what());
    code = 1;
  }
  std::fflush(stderr);
  // _exit: the parent's atexit handlers and static destructors are not the child's to run.
  _exit(code);
}

}  // namespace

ChildResult run_in_child(const std::string& what, const std::function<std::string()>& fn) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error(what + ": pipe: " + std::strerror(errno));
  std::fflush(nullptr);  // nothing buffered may be written twice
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    throw std::runtime_error(what + ": fork: " + std::strerror(errno));
  }
  if (pid == 0) {
    close(fds[0]);
    child_main(what, fn, fds[1]);
  }
  close(fds[1]);
  ChildResult r;
  char buf[4096];
  for (;;) {
    const ssize_t n = read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    r.output.append(buf, static_cast<size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, 0, &usage) < 0) {
    if (errno != EINTR) throw std::runtime_error(what + ": wait4: " + std::strerror(errno));
  }
  if (WIFSIGNALED(status))
    throw std::runtime_error(what + ": killed by signal " + std::to_string(WTERMSIG(status)));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error(what + ": failed (exit status " + std::to_string(WEXITSTATUS(status)) +
                             ")");
  r.peak_rss_mb = kb_to_mb(usage.ru_maxrss);
  r.cpu_s = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  return r;
}

double self_peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return kb_to_mb(usage.ru_maxrss);
}

}  // namespace hs
