#include "tools/launch/spawn.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace hs {
namespace {

bool is_executable(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

std::vector<std::string> child_environment(
    const std::vector<std::pair<std::string, std::string>>& overrides) {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    const std::string entry = *e;
    bool replaced = false;
    for (const auto& [key, value] : overrides)
      replaced |= entry.compare(0, key.size() + 1, key + "=") == 0;
    if (!replaced) env.push_back(entry);
  }
  for (const auto& [key, value] : overrides) env.push_back(key + "=" + value);
  return env;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (std::string& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

// In the forked child: only async-signal-safe calls until exec.
[[noreturn]] void exec_child(const char* program, char* const* argv, char* const* envp, int log_fd,
                             int null_fd, int error_fd, pid_t parent) {
  ::setpgid(0, 0);
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) _exit(127);  // the supervisor died before prctl took effect
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  ::dup2(null_fd, 0);
  ::dup2(log_fd, 1);
  ::dup2(log_fd, 2);
  ::execve(program, argv, envp);
  const int err = errno;
  [[maybe_unused]] const ssize_t n = ::write(error_fd, &err, sizeof err);
  _exit(127);
}

}  // namespace

std::string resolve_program(const std::string& argv0, const std::string& first_dir) {
  if (argv0.find('/') != std::string::npos) return is_executable(argv0) ? argv0 : "";
  if (!first_dir.empty() && is_executable(first_dir + "/" + argv0)) return first_dir + "/" + argv0;
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::string dir = dirs.substr(start, end - start);
    if (!dir.empty() && is_executable(dir + "/" + argv0)) return dir + "/" + argv0;
    start = end + 1;
  }
  return "";
}

std::string self_directory() {
  char buf[4096];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return "";
  std::string path(buf, static_cast<size_t>(n));
  return path.substr(0, path.rfind('/'));
}

pid_t spawn_process(const SpawnRequest& request) {
  std::vector<std::string> argv = request.argv;
  std::vector<std::string> env = child_environment(request.env);
  std::vector<char*> argv_p = pointers(argv);
  std::vector<char*> env_p = pointers(env);
  const int log_fd =
      ::open(request.log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log_fd < 0)
    throw std::runtime_error("cannot open " + request.log_path + ": " + std::strerror(errno));
  const int null_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  int pipe_fds[2] = {-1, -1};
  if (null_fd < 0 || ::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    const std::string err = std::strerror(errno);
    ::close(log_fd);
    if (null_fd >= 0) ::close(null_fd);
    throw std::runtime_error("cannot prepare to start " + request.program + ": " + err);
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0)
    exec_child(request.program.c_str(), argv_p.data(), env_p.data(), log_fd, null_fd, pipe_fds[1],
               parent);
  const int fork_errno = errno;
  ::close(pipe_fds[1]);
  ::close(log_fd);
  ::close(null_fd);
  if (pid < 0) {
    ::close(pipe_fds[0]);
    throw std::runtime_error("fork: " + std::string(std::strerror(fork_errno)));
  }
  // Also places the child in its group from this side, so a signal_group() right after spawn
  // never races the child's own setpgid.
  ::setpgid(pid, pid);
  int exec_errno = 0;
  ssize_t n;
  do {
    n = ::read(pipe_fds[0], &exec_errno, sizeof exec_errno);
  } while (n < 0 && errno == EINTR);
  ::close(pipe_fds[0]);
  if (n > 0) {
    ::waitpid(pid, nullptr, 0);
    throw std::runtime_error("cannot run " + request.program + ": " + std::strerror(exec_errno));
  }
  return pid;
}

std::string describe(const ExitStatus& status) {
  if (status.signal == 0) return "exit " + std::to_string(status.code);
  const char* name = strsignal(status.signal);
  return "signal " + std::to_string(status.signal) + " (" + (name ? name : "?") + ")";
}

std::optional<ExitStatus> try_reap(pid_t pid) {
  int status = 0;
  pid_t r;
  do {
    r = ::waitpid(pid, &status, WNOHANG);
  } while (r < 0 && errno == EINTR);
  if (r == 0) return std::nullopt;
  ExitStatus s;
  if (r < 0) {  // not our child any more: nothing to wait for
    s.code = -1;
    return s;
  }
  if (WIFSIGNALED(status))
    s.signal = WTERMSIG(status);
  else
    s.code = WEXITSTATUS(status);
  return s;
}

void signal_group(pid_t pid, int sig) {
  if (pid > 0) ::kill(-pid, sig);
}

}  // namespace hs
