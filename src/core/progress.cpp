#include "meso/core/progress.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

#include <unistd.h>

namespace meso {

std::string formatDuration(double s) {
  const int total = static_cast<int>(s + 0.5);
  return fmt::format("{}:{:02d}", total / 60, total % 60);
}

ProgressBar::ProgressBar(std::string label, int64_t total, bool enabled,
                         std::chrono::milliseconds delay)
    : label_(std::move(label)),
      total_(std::max<int64_t>(total, 1)),
      active_(enabled && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      delay_(delay) {
  shown_ = delay_.count() <= 0;  // undelayed bars always draw their final state
  if (active_) thread_ = std::thread([this] { loop(); });
}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::finish() {
  {
    std::lock_guard lock(mutex_);
    if (finished_) return;
    finished_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (active_ && shown_) draw(true);
}

void ProgressBar::loop() {
  std::unique_lock lock(mutex_);
  if (delay_.count() > 0) wake_.wait_for(lock, delay_, [this] { return finished_; });
  while (!finished_) {
    draw(false);
    shown_ = true;
    wake_.wait_for(lock, std::chrono::milliseconds(250));
  }
}

// The bar is redrawn in place with '\r'; ETA assumes the remaining work goes at the mean rate so
// far.
void ProgressBar::draw(bool final) const {
  const int64_t done = std::min(done_.load(std::memory_order_relaxed), total_);
  const double fraction = static_cast<double>(done) / static_cast<double>(total_);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(filled, '=');
  bar.resize(kWidth, ' ');
  std::string eta = done > 0 ? formatDuration(elapsed * (1.0 - fraction) / fraction) : "?";
  std::fprintf(stderr, "\r%s [%s] %lld/%lld  elapsed %s  ETA %s ", label_.c_str(), bar.c_str(),
               static_cast<long long>(done), static_cast<long long>(total_),
               formatDuration(elapsed).c_str(), eta.c_str());
  if (final) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace meso
