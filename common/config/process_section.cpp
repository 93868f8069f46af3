#include "common/config/process_section.h"

namespace hs {

void read_process_tail(ConfigSection& top, int64_t& heartbeat_period_ns, ChannelNames& channels) {
  top.section("node",
              [&](ConfigSection& s) { s.read_period("heartbeat_period_s", heartbeat_period_ns); });
  channels = read_channel_names(top);
  top.finish();
}

}  // namespace hs
