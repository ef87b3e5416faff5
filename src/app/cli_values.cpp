#include "cli_values.h"

#include "meso/core/error.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>

namespace meso::app {

long long parseInteger(const std::string& text, const std::string& option, long long lo,
                       long long hi) {
  long long v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ptr != end || ec != std::errc() || v < lo || v > hi)
    throw Error(option + ": expected an integer in [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "], got \"" + text + "\"");
  return v;
}

std::pair<int, int> parseFrameRange(const std::string& text, int count) {
  if (text.empty()) return {0, count - 1};
  const std::string expected = "--frames: expected A, A: or A:B with 0 <= A <= B < " +
                               std::to_string(count) + ", got \"" + text + "\"";
  const size_t colon = text.find(':');
  if (colon != std::string::npos && text.find(':', colon + 1) != std::string::npos)
    throw Error(expected + " (a step is not supported)");
  try {
    const int a = static_cast<int>(parseInteger(text.substr(0, colon), "--frames", 0, count - 1));
    const int b =
        colon == std::string::npos ? a
        : colon + 1 == text.size()
            ? count - 1
            : static_cast<int>(parseInteger(text.substr(colon + 1), "--frames", 0, count - 1));
    if (b < a) throw Error(expected);
    return {a, b};
  } catch (const Error&) {
    throw Error(expected);
  }
}

std::pair<int, int> parseShard(const std::string& text) {
  if (text.empty()) return {0, 1};
  const std::string expected = "--shard: expected i/n with 0 <= i < n, got \"" + text + "\"";
  const size_t slash = text.find('/');
  if (slash == std::string::npos) throw Error(expected);
  try {
    const long long n = parseInteger(text.substr(slash + 1), "--shard", 1, 1 << 20);
    const long long i = parseInteger(text.substr(0, slash), "--shard", 0, n - 1);
    return {static_cast<int>(i), static_cast<int>(n)};
  } catch (const Error&) {
    throw Error(expected);
  }
}

std::string finiteNumberProblem(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    return "expected a finite number, got \"" + text + "\"";
  return "";
}

std::string unsignedNumberProblem(const std::string& text) {
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  if (text.empty() || !std::all_of(text.begin(), text.end(), digit))
    return "expected a whole number of 0 or more, got \"" + text + "\"";
  errno = 0;
  std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE) return "expected a whole number below 2^64, got \"" + text + "\"";
  return "";
}

}  // namespace meso::app
