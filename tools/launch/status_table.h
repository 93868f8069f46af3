#pragma once
// hs-launch's status: one line per process (state, pid, uptime, starts, last exit) with what its
// latest HEARTBEAT says (state, age, message, queue depths).
#include <cstdint>
#include <string>
#include <vector>

#include "tools/launch/supervisor.h"

namespace hs {

// "OK", "DEGRADED", ... for heartbeat_t::state.
const char* heartbeat_state_name(int8_t state);

// One line per process, columns aligned, no trailing newline.
std::vector<std::string> format_status(const std::vector<SupervisedProcess>& processes,
                                       int64_t now_ns);

}  // namespace hs
