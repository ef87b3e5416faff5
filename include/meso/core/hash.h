// Incremental hashing of everything that shapes a cached table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace meso {

// FNV-1a, 64 bit: incremental hashing of everything that shapes a table.
class Hasher {
 public:
  Hasher& bytes(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) h_ = (h_ ^ p[i]) * 0x100000001b3ull;
    return *this;
  }
  template <typename T>
  Hasher& value(const T& v) {
    return bytes(&v, sizeof v);
  }
  Hasher& string(const std::string& s) { return value(s.size()).bytes(s.data(), s.size()); }
  uint64_t digest() const { return h_; }

 private:
  uint64_t h_ = 0xcbf29ce484222325ull;
};

}  // namespace meso
