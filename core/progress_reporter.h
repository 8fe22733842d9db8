#pragma once
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>

#include "core/stopwatch.h"

namespace fscil {

// Progress of long work on stderr: what runs, epochs with loss and ETA. Silent when quiet. Copies
// report to the same place and share what was said last (for Heartbeat).
class ProgressReporter {
 public:
  explicit ProgressReporter(std::ostream* out) : out_(out), said_(std::make_shared<Said>()) {}
  static ProgressReporter quiet() { return ProgressReporter(nullptr); }

  // A new stage, e.g. "prototype seed 1 | session 0 (base, 75 classes)".
  void stage(const std::string& what);
  // One finished epoch of `epochs` of `phase` in the current stage; its elapsed time and ETA count
  // from the end of the phase before (a stage's pretraining, then its pseudo-incremental phase).
  void epoch(const std::string& phase, int epoch, int epochs, double loss);
  void note(const std::string& message);
  bool silent() const { return out_ == nullptr; }

 private:
  friend class Heartbeat;
  struct Said {
    std::mutex lines;  // one line at a time, whichever thread says it
    std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
    std::string stage;
  };
  void line(const std::string& text);

  std::ostream* out_;
  Stopwatch stage_clock_;
  std::string phase_;             // of the last epoch line
  int phase_epoch_ = 0;           // its epoch
  double phase_started_at_ = 0;   // on stage_clock_: the phase before's last epoch line (or the stage's start)
  double last_epoch_at_ = 0;      // on stage_clock_: the last epoch line
  std::shared_ptr<Said> said_;
};

// While it lives, a line every `every` of silence saying that the stage goes on and for how long
// nothing was said, so a long step (a session's 1000 probes, a large dataset's preparation) is not
// taken for a hang.
class Heartbeat {
 public:
  Heartbeat(const ProgressReporter& progress, std::chrono::seconds every);
  ~Heartbeat();
  Heartbeat(const Heartbeat&) = delete;
  Heartbeat& operator=(const Heartbeat&) = delete;

 private:
  ProgressReporter progress_;
  std::chrono::seconds every_;
  std::mutex mutex_;
  std::condition_variable stopping_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace fscil
