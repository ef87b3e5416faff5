#include "meso/core/timer.h"

#include <fstream>
#include <string>

namespace meso {

namespace {

// A "Key:   N kB" line of /proc/self/status, in MiB (0 when absent).
double statusMib(const char* key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  const std::string prefix = key;
  while (std::getline(status, line))
    if (line.rfind(prefix, 0) == 0) return std::stod(line.substr(prefix.size())) / 1024.0;  // kB
  return 0.0;
}

}  // namespace

double peakRssMib() { return statusMib("VmHWM:"); }
double currentRssMib() { return statusMib("VmRSS:"); }
double anonymousRssMib() { return statusMib("RssAnon:"); }

}  // namespace meso
