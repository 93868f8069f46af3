#pragma once
// Starting and reaping supervised programs. Each child runs in its own process group (a signal to
// the group reaches any children it has, and a terminal's Ctrl-C reaches only hs-launch, which
// forwards it), with stdin from /dev/null, stdout and stderr appended to a log file, and SIGTERM
// sent to it should hs-launch itself die (PR_SET_PDEATHSIG), so no process is left unsupervised.
#include <sys/types.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hs {

struct SpawnRequest {
  std::string program;  // full path (resolve_program)
  std::vector<std::string> argv;
  std::string log_path;
  std::vector<std::pair<std::string, std::string>> env;  // set or replaced in the child
};

// argv0 as is when it contains a '/'; else the executable of that name in `first_dir` (the
// directory of hs-launch, so a build tree needs no PATH), else in $PATH. Empty when none.
std::string resolve_program(const std::string& argv0, const std::string& first_dir);

// The directory of the running executable (/proc/self/exe).
std::string self_directory();

// Throws std::runtime_error with the reason when the program cannot be started (exec failure
// is reported back through a close-on-exec pipe).
pid_t spawn_process(const SpawnRequest& request);

struct ExitStatus {
  int code = 0;    // exit code when exited normally
  int signal = 0;  // the terminating signal, 0 when exited normally
  bool success() const { return signal == 0 && code == 0; }
};

// "exit 0", "exit 3", "signal 11 (Segmentation fault)".
std::string describe(const ExitStatus& status);

// The child's status when it has ended (reaped), nullopt while it runs.
std::optional<ExitStatus> try_reap(pid_t pid);

// kill() to the child's process group.
void signal_group(pid_t pid, int sig);

}  // namespace hs
