#pragma once
// Two "hosts" for multi-machine tests: network namespaces A and B joined by a veth pair, each end
// with its own address and the multicast route LCM's udpm needs, so `ttl=1` traffic crosses the
// link as it would between two machines on a switch. Needs root and iproute2: error() says why
// when they cannot be made. Cutting the link downs B's end, as a pulled cable does to A
// (NO-CARRIER, routes kept); restoring it re-adds B's route, as the network configuration does on
// link up.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace hs::test {

class TwoHosts {
 public:
  TwoHosts() {
    const std::string id = std::to_string(::getpid());
    a_ = "hsA" + id, b_ = "hsB" + id, veth_a_ = "hsa" + id, veth_b_ = "hsb" + id;
    if (::geteuid() != 0) {
      error_ = "not root: network namespaces need CAP_SYS_ADMIN";
      return;
    }
    const std::vector<std::string> setup = {
        "ip netns add " + a_,
        "ip netns add " + b_,
        "ip link add " + veth_a_ + " netns " + a_ + " type veth peer name " + veth_b_ + " netns " +
            b_,
        "ip -n " + a_ + " addr add 10.213.0.1/24 dev " + veth_a_,
        "ip -n " + b_ + " addr add 10.213.0.2/24 dev " + veth_b_,
        "ip -n " + a_ + " link set lo up",
        "ip -n " + b_ + " link set lo up",
        "ip -n " + a_ + " link set " + veth_a_ + " up",
        "ip -n " + b_ + " link set " + veth_b_ + " up",
        "ip -n " + a_ + " route add 224.0.0.0/4 dev " + veth_a_,
        "ip -n " + b_ + " route add 224.0.0.0/4 dev " + veth_b_};
    for (const std::string& cmd : setup)
      if (!sh(cmd)) {
        error_ = "'" + cmd + "' failed (no ip netns / veth support here?)";
        return;
      }
  }
  ~TwoHosts() {
    sh("ip netns del " + a_);
    sh("ip netns del " + b_);
  }
  TwoHosts(const TwoHosts&) = delete;
  TwoHosts& operator=(const TwoHosts&) = delete;

  const std::string& error() const { return error_; }
  const std::string& a() const { return a_; }
  const std::string& b() const { return b_; }

  // argv run inside namespace `ns` (ip netns exec execs it: the pid is the program's).
  static std::vector<std::string> in(const std::string& ns, std::vector<std::string> argv) {
    argv.insert(argv.begin(), {"ip", "netns", "exec", ns});
    return argv;
  }

  bool cut() { return sh("ip -n " + b_ + " link set " + veth_b_ + " down"); }
  bool restore() {
    return sh("ip -n " + b_ + " link set " + veth_b_ + " up") &&
           sh("ip -n " + b_ + " route replace 224.0.0.0/4 dev " + veth_b_);
  }

  // Bytes B's end of the link has received.
  uint64_t b_rx_bytes() const {
    const std::string cmd =
        "ip netns exec " + b_ + " cat /sys/class/net/" + veth_b_ + "/statistics/rx_bytes";
    FILE* p = ::popen(cmd.c_str(), "r");
    unsigned long long bytes = 0;
    if (p) {
      if (std::fscanf(p, "%llu", &bytes) != 1) bytes = 0;
      ::pclose(p);
    }
    return bytes;
  }

 private:
  static bool sh(const std::string& cmd) {
    return std::system((cmd + " >/dev/null 2>&1").c_str()) == 0;
  }

  std::string a_, b_, veth_a_, veth_b_, error_;
};

}  // namespace hs::test
