#pragma once
#include <stdexcept>

namespace fscil {

// A stop asked of a command by SIGTERM (Slurm's warning before a time limit or a preemption) or
// SIGINT. The handler only records the signal; training polls it after every epoch and session
// and then throws StopRequested, so what survives is the checkpoint of the last finished session,
// from which --resume (or a requeued Slurm task) continues with the same numbers. A second SIGINT
// (Ctrl-C twice) ends the process at once; a second SIGTERM changes nothing.
void install_stop_handlers();

// The signal that asked to stop, or 0.
int stop_signal();

// Throws StopRequested when a stop was asked.
void stop_if_requested();

// Records a stop as the handler does (tests, and commands that stop their own children).
void request_stop(int signal);
void clear_stop_request();

class StopRequested : public std::runtime_error {
 public:
  explicit StopRequested(int signal);
  int signal() const { return signal_; }

 private:
  int signal_;
};

}  // namespace fscil
