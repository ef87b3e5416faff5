// Values of command-line options that CLI11 does not parse itself: strict (no trailing junk, no
// non-finite numbers), each error naming the option and what was expected.
#pragma once

#include <string>
#include <utility>

namespace meso::app {

// The whole of `text` as a decimal integer in [lo, hi], or meso::Error("OPTION: expected ...").
long long parseInteger(const std::string& text, const std::string& option, long long lo,
                       long long hi);

// "" (all), "A", "A:" (A to the last) or "A:B" against frames [0, count): inclusive [A, B].
std::pair<int, int> parseFrameRange(const std::string& text, int count);

// "" (one shard) or "i/n" with 0 <= i < n.
std::pair<int, int> parseShard(const std::string& text);

// Empty when `text` is a finite number with nothing after it, else what was expected (for CLI11
// validators of floating-point options: CLI11 accepts "nan", "inf" and Range() lets NaN through).
std::string finiteNumberProblem(const std::string& text);

// Empty when `text` is a whole number from 0 to 2^64 - 1 (an unsigned option: "-1" and
// 99999999999999999999999 would otherwise wrap or saturate silently); else the message.
std::string unsignedNumberProblem(const std::string& text);

}  // namespace meso::app
