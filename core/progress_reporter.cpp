#include "core/progress_reporter.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

namespace fscil {

void ProgressReporter::line(const std::string& text) {
  if (out_ == nullptr) return;
  const std::lock_guard<std::mutex> lock(said_->lines);
  fmt::print(*out_, "[fscil-bench] {}\n", text);
  out_->flush();
  said_->last = std::chrono::steady_clock::now();
}

void ProgressReporter::stage(const std::string& what) {
  stage_clock_ = Stopwatch();
  phase_.clear();
  phase_epoch_ = 0;
  phase_started_at_ = last_epoch_at_ = 0;
  {
    const std::lock_guard<std::mutex> lock(said_->lines);
    said_->stage = what;
  }
  line(what);
}

void ProgressReporter::epoch(const std::string& phase, int epoch, int epochs, double loss) {
  if (out_ == nullptr) return;
  const double now = stage_clock_.seconds();
  if (phase != phase_ || epoch <= phase_epoch_) phase_started_at_ = last_epoch_at_;  // a new phase began
  phase_ = phase;
  phase_epoch_ = epoch;
  last_epoch_at_ = now;
  const double elapsed = now - phase_started_at_;
  const double eta = epoch > 0 ? elapsed / epoch * (epochs - epoch) : 0.0;
  line(fmt::format("  {} epoch {}/{} loss {:.4f} elapsed {:.0f}s ETA {:.0f}s", phase, epoch, epochs, loss, elapsed, eta));
}

void ProgressReporter::note(const std::string& message) { line("  " + message); }

Heartbeat::Heartbeat(const ProgressReporter& progress, std::chrono::seconds every) : progress_(progress), every_(every) {
  if (progress_.silent()) return;
  thread_ = std::thread([this] {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_.wait_for(lock, std::chrono::seconds(1), [this] { return stop_; })) {
      std::string stage;
      std::chrono::steady_clock::duration quiet_for;
      {
        const std::lock_guard<std::mutex> said(progress_.said_->lines);
        quiet_for = std::chrono::steady_clock::now() - progress_.said_->last;
        stage = progress_.said_->stage;
      }
      if (quiet_for < every_) continue;
      progress_.note(fmt::format("still working ({}), {} s since the last line",
                                 stage.empty() ? std::string("preparing") : stage,
                                 std::chrono::duration_cast<std::chrono::seconds>(quiet_for).count()));
    }
  });
}

Heartbeat::~Heartbeat() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  stopping_.notify_all();
  thread_.join();
}

}  // namespace fscil
