#include "base/stop_request.hpp"

#include <csignal>

#include "base/temporary_files.hpp"

namespace tumble {
namespace {
volatile std::sig_atomic_t g_stop = 0;
bool g_installed = false;

extern "C" void on_stop_signal(int signal) {
  // A second terminating signal while a stop is pending: the default action, now.
  if (g_stop != 0 && signal != SIGUSR1) {
    remove_temporaries_now();  // (a file being written is not renamed into place now)
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  g_stop = signal;
}
}  // namespace

void install_stop_handlers() {
  if (g_installed) return;
  g_installed = true;
  struct sigaction sa = {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // a blocking write or MPI poll is not interrupted by it
  for (int s : {SIGUSR1, SIGTERM, SIGINT}) sigaction(s, &sa, nullptr);
}

int stop_signal() { return g_stop; }

int agreed_stop_signal(MPI_Comm comm) {
  int signal = g_stop;
  if (comm != MPI_COMM_NULL) MPI_Allreduce(MPI_IN_PLACE, &signal, 1, MPI_INT, MPI_MAX, comm);
  return signal;
}

void stop_if_requested(MPI_Comm comm, const std::string& what) {
  if (const int signal = agreed_stop_signal(comm); signal != 0)
    throw StopRequest("stopped by " + signal_name(signal) + " while " + what +
                      " (nothing of it is kept: the next run starts it again)");
}

std::string signal_name(int signal) {
  switch (signal) {
    case SIGUSR1:
      return "SIGUSR1";
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    default:
      return "signal " + std::to_string(signal);
  }
}

}  // namespace tumble
