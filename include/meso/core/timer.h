// Wall-clock phase timing and peak memory, for --stats.
#pragma once

#include <chrono>

namespace meso {

class Timer {
 public:
  Timer() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  void reset() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

// Peak resident set size of this process in MiB (VmHWM), 0 if unknown.
double peakRssMib();
// Resident memory now (VmRSS), MiB; 0 where /proc/self/status is not readable.
double currentRssMib();
// Anonymous resident memory now (RssAnon: what the process allocated, without the pages of its
// libraries and mapped files), MiB; 0 where /proc/self/status is not readable.
double anonymousRssMib();

}  // namespace meso
