#pragma once

#include "core/error.h"

namespace fscil {

// A stop asked of a command by SIGTERM (Slurm's warning before a time limit or a preemption) or
// SIGINT. The handler only records the signal; training polls it after every step, epoch and session
// and then throws StopRequested, so what survives is the checkpoint of the last finished session,
// from which --resume (or a requeued Slurm task) continues with the same numbers. A SIGINT after
// any stop request (Ctrl-C twice) ends the process at once; a second SIGTERM changes nothing.
// Dataset preparation is not interrupted: a stop asked then is acted on when training starts.
void install_stop_handlers();

// The signal that asked to stop, or 0.
int stop_signal();

// Throws StopRequested when a stop was asked.
void stop_if_requested();

// Forgets a stop request (tests).
void clear_stop_request();

// Exits with exit_status::stopped_by(signal).
class StopRequested : public Error {
 public:
  explicit StopRequested(int signal);
  int signal() const { return signal_; }

 private:
  int signal_;
};

}  // namespace fscil
