#include "core/stop_request.h"

#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace fscil {

namespace {

// Lock-free, so safe in a handler, and seen by every thread (the signal may land on any of them).
std::atomic<int> requested_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void record_stop(int signal) {
  if (signal == SIGINT && requested_signal != 0) {  // Ctrl-C after any stop request: stop now
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  // A second SIGTERM is the same request: Slurm may signal the process and its batch script, which
  // passes the signal on.
  int none = 0;
  requested_signal.compare_exchange_strong(none, signal);
}

}  // namespace

StopRequested::StopRequested(int signal)
    : Error(fmt::format("stopped by {}", signal == SIGTERM ? "SIGTERM" : signal == SIGINT ? "SIGINT" : strsignal(signal)),
            exit_status::stopped_by(signal)),
      signal_(signal) {}

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = record_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // blocking calls go on; the stop is acted on where it is polled
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
}

int stop_signal() { return requested_signal; }

void stop_if_requested() {
  if (requested_signal != 0) throw StopRequested(requested_signal);
}

void clear_stop_request() { requested_signal = 0; }

}  // namespace fscil
