// Small counter-based random numbers: the same (seed, pixel, sample) gives the same value on any
// thread.
#pragma once

#include <cstdint>

namespace meso {

// SplitMix64 finaliser: a good 64-bit mix, used to derive independent streams from keys.
inline uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// PCG32 (O'Neill 2014): small state, good statistics, cheap to seed per pixel.
class Rng {
 public:
  explicit Rng(uint64_t seed, uint64_t stream = 0) {
    inc_ = (mix64(stream) << 1u) | 1u;
    state_ = 0;
    nextU32();
    state_ += mix64(seed);
    nextU32();
  }

  uint32_t nextU32() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
  }

  // Uniform in [0, 1): 24 random bits so the result is exactly representable and never 1.
  float uniform() { return static_cast<float>(nextU32() >> 8) * 0x1.0p-24f; }

 private:
  uint64_t state_;
  uint64_t inc_;
};

}  // namespace meso
