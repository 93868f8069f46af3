#pragma once
// Runs a function in a forked child process and returns what it produced together with the
// child's own peak resident set size, so each measured run starts from the same small parent
// and its memory figure is not mixed with another run's. Linux only (wait4).
#include <functional>
#include <string>

namespace hs {

struct ChildResult {
  std::string output;        // what the function returned, sent back through a pipe
  double peak_rss_mb = 0.0;  // ru_maxrss of the child (includes the parent's pages at fork)
  double cpu_s = 0.0;        // user + system CPU time of the child
};

// `fn` runs in the child; an exception there is printed on stderr as "<what>: <error>" and
// makes this throw std::runtime_error in the parent, as does any abnormal exit.
ChildResult run_in_child(const std::string& what, const std::function<std::string()>& fn);

// Peak resident set size of this process so far, MB.
double self_peak_rss_mb();

}  // namespace hs
