#pragma once
// What every process config ends with: the `node:` section's heartbeat period, the `channels:`
// section, and the check that no unknown key is left (ConfigSection::finish).
#include <cstdint>

#include "common/config/channels.h"
#include "common/config/config_section.h"

namespace hs {

void read_process_tail(ConfigSection& top, int64_t& heartbeat_period_ns, ChannelNames& channels);

}  // namespace hs
