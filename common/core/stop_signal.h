#pragma once
// SIGINT/SIGTERM as a stop request for a process's receive loop. Installed without SA_RESTART,
// so a blocking wait (LCM handleTimeout, poll) returns at once and the loop sees the flag.
namespace hs {

void install_stop_signals();
bool stop_requested();

}  // namespace hs
