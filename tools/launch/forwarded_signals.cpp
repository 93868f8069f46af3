#include "tools/launch/forwarded_signals.h"

#include <atomic>
#include <csignal>

namespace hs {
namespace {

constexpr int kSignals[] = {SIGHUP, SIGINT, SIGQUIT, SIGUSR1, SIGUSR2, SIGTERM};
std::atomic<unsigned> g_pending{0};  // bit per signal number
static_assert(std::atomic<unsigned>::is_always_lock_free);

void on_signal(int sig) {
  g_pending.fetch_or(1u << sig);
}

}  // namespace

void install_forwarded_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  for (int sig : kSignals) sigaction(sig, &sa, nullptr);
}

std::vector<int> take_pending_signals() {
  const unsigned bits = g_pending.exchange(0);
  std::vector<int> out;
  for (int sig : kSignals)
    if (bits & (1u << sig)) out.push_back(sig);
  return out;
}

bool signal_pending() {
  return g_pending.load() != 0;
}

}  // namespace hs
