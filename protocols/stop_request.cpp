#include "protocols/stop_request.h"

#include <fmt/format.h>

#include <csignal>
#include <cstring>

namespace fscil {

namespace {

volatile std::sig_atomic_t requested_signal = 0;

extern "C" void record_stop(int signal) {
  if (signal == SIGINT && requested_signal != 0) {  // Ctrl-C twice: stop now
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  // A second SIGTERM is the same request: Slurm may signal the process and its batch script, which
  // passes the signal on.
  if (requested_signal == 0) requested_signal = signal;
}

}  // namespace

StopRequested::StopRequested(int signal)
    : std::runtime_error(fmt::format("stopped by {}", signal == SIGTERM ? "SIGTERM" : signal == SIGINT ? "SIGINT"
                                                                                                    : strsignal(signal))),
      signal_(signal) {}

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = record_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: a parent waiting for its children wakes up to forward the stop
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
}

int stop_signal() { return requested_signal; }

void stop_if_requested() {
  if (requested_signal != 0) throw StopRequested(requested_signal);
}

void request_stop(int signal) { requested_signal = signal; }

void clear_stop_request() { requested_signal = 0; }

}  // namespace fscil
