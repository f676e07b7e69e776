#include "lcmio/signals.hpp"

#include <atomic>
#include <csignal>

namespace lasonic::shutdown {
namespace {
std::atomic<bool> g_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");
extern "C" void onSignal(int) { g_requested.store(true); }
}  // namespace

void installHandlers() {
  // sigaction without SA_RESTART: a blocking wait (LCM's select) returns EINTR at once.
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool requested() { return g_requested.load(); }
void request() { g_requested.store(true); }

}  // namespace lasonic::shutdown
