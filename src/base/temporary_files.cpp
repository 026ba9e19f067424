#include "base/temporary_files.hpp"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace tumble {
namespace {

constexpr int kSlots = 16;
constexpr std::size_t kPathMax = 4096;
// 0 free, 1 being filled or emptied, 2 holds a path. Lock-free atomics are safe in a handler.
std::atomic<int> g_state[kSlots];
char g_path[kSlots][kPathMax];

extern "C" void on_terminating_signal(int signal) {
  remove_temporaries_now();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

void register_temporary(const std::string& path) {
  if (path.size() >= kPathMax) return;
  for (int k = 0; k < kSlots; ++k) {
    int expected = 0;
    if (!g_state[k].compare_exchange_strong(expected, 1)) continue;
    std::memcpy(g_path[k], path.c_str(), path.size() + 1);
    g_state[k].store(2);
    return;
  }
}

void forget_temporary(const std::string& path) {
  for (int k = 0; k < kSlots; ++k) {
    int expected = 2;
    if (!g_state[k].compare_exchange_strong(expected, 1)) continue;
    if (path == g_path[k]) {
      g_state[k].store(0);
      return;
    }
    g_state[k].store(2);
  }
}

void remove_temporaries_now() {
  for (int k = 0; k < kSlots; ++k)
    if (g_state[k].load() == 2) ::unlink(g_path[k]);
}

void remove_temporaries_on_signal() {
  struct sigaction sa = {};
  sa.sa_handler = on_terminating_signal;
  sigemptyset(&sa.sa_mask);
  for (int s : {SIGTERM, SIGINT, SIGHUP}) sigaction(s, &sa, nullptr);
}

}  // namespace tumble
