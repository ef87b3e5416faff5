// A progress bar on stderr (done/total, elapsed, ETA), drawn from its own thread; silent when
// stderr is not a terminal.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace meso {

// A duration as m:ss (the bar's elapsed time and ETA; also the CLI's per-frame ETA).
std::string formatDuration(double seconds);

class ProgressBar {
 public:
  // enabled = false forces silence (e.g. --quiet); otherwise it draws only if stderr is a TTY.
  // With a delay the bar appears only for work that lasts longer than it
  // (nothing is drawn for a quick run, e.g. tables read from the cache).
  ProgressBar(std::string label, int64_t total, bool enabled = true,
              std::chrono::milliseconds delay = std::chrono::milliseconds(0));
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void advance(int64_t n = 1) { done_.fetch_add(n, std::memory_order_relaxed); }
  int64_t done() const { return done_.load(std::memory_order_relaxed); }
  // Draws the final state and stops the drawing thread.
  void finish();

 private:
  void draw(bool final) const;
  void loop();

  std::string label_;
  int64_t total_;
  std::atomic<int64_t> done_{0};
  bool active_;
  bool finished_ = false;
  bool shown_ = false;  // drawn at least once (guarded by mutex_)
  std::chrono::steady_clock::time_point start_;
  std::chrono::milliseconds delay_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread thread_;
};

}  // namespace meso
