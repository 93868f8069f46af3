#include "drivers/trigger/trigger_options.h"

#include "common/config/process_section.h"

namespace hs {

TriggerOptions load_trigger_options(const std::string& path) {
  TriggerOptions o;
  ConfigSection top = ConfigSection::load(path);
  top.section("trigger", [&](ConfigSection& s) {
    s.read("chip", o.chip);
    if (o.chip.empty()) s.fail("chip", "must name a GPIO chip");
    s.read("output_line", o.output_line);
    if (o.output_line.empty()) s.fail("output_line", "must name a line");
    s.read("edge_line", o.edge_line);
    s.read("rate_hz", o.rate_hz);
    if (!(o.rate_hz > 0 && o.rate_hz <= 1000)) s.fail("rate_hz", "must be in (0, 1000]");
    s.read_period("pulse_width_s", o.pulse_width_ns);
    if (o.pulse_width_ns * o.rate_hz >= 1e9)
      s.fail("pulse_width_s", "must be shorter than a period");
    s.read_period("edge_timeout_s", o.edge_timeout_ns);
    s.read("sync_line", o.sync_line);
    s.read("sync_divider", o.sync_divider);
    if (o.sync_divider < 1 || o.sync_divider > 1000) s.fail("sync_divider", "must be 1 ... 1000");
    s.read_period("sync_timeout_s", o.sync_timeout_ns);
  });
  read_process_tail(top, o.heartbeat_period_ns, o.channels);
  return o;
}

}  // namespace hs
