#pragma once
// The signals hs-launch acts on: SIGINT and SIGTERM stop everything, passed on as they are (a
// second one kills at once); SIGHUP (the terminal closed) and SIGQUIT stop everything with
// SIGTERM; SIGUSR1 and SIGUSR2 are passed on to every process. Installed without SA_RESTART so a
// blocking wait returns at once.
#include <vector>

namespace hs {

void install_forwarded_signals();
// Signals received since the last call, each once, in signal-number order.
std::vector<int> take_pending_signals();
bool signal_pending();

}  // namespace hs
