#include "common/lcm/lcm_connection.h"

#include <cstdlib>
#include <fstream>

#include "common/core/error.h"

namespace hs {

std::string default_lcm_url() {
  const char* env = std::getenv("LCM_DEFAULT_URL");
  return env && *env ? env : kDefaultLcmUrl;
}

std::unique_ptr<lcm::LCM> connect_lcm(const std::string& url) {
  auto lcm = std::make_unique<lcm::LCM>(url);
  if (!lcm->good())
    throw InputError("LCM URL '" + url + "'",
                     "cannot start LCM (bad URL, or for udpm:// no multicast route: run "
                     "tools/setup.sh or `ip route add 224.0.0.0/4 dev lo`)");
  return lcm;
}

long long read_rmem_max() {
  std::ifstream in("/proc/sys/net/core/rmem_max");
  long long v = -1;
  return (in >> v) ? v : -1;
}

std::string receive_buffer_warning(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0) return "";
  long long wanted = kWantedReceiveBuffer;
  const std::string key = "recv_buf_size=";
  const size_t at = url.find(key, url.find('?'));
  if (at != std::string::npos) wanted = std::atoll(url.c_str() + at + key.size());
  const long long cap = read_rmem_max();
  if (cap < 0 || cap >= wanted) return "";
  return "net.core.rmem_max is " + std::to_string(cap) + " bytes, below the " +
         std::to_string(wanted) +
         " needed for camera frames over udpm: large messages will be lost. Run tools/setup.sh "
         "(or: sysctl -w net.core.rmem_max=16777216 net.core.rmem_default=16777216)";
}

}  // namespace hs
