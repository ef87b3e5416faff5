// Reading back a file of an on-disk cache (the table cache, `meso trade`'s reference renders): a
// file that fails any check is deleted and a warning says why, so that the caller rebuilds it;
// it is never trusted.
#pragma once

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

namespace meso {

class CacheFileReader {
 public:
  // Opens `file`; `instead` says what the caller does with a rejected one ("rebuilding").
  // `warning` may be null.
  CacheFileReader(std::filesystem::path file, std::string instead, std::string* warning);

  // False when there is no file to read (a miss: nothing to warn about).
  bool opened() const { return opened_; }
  // Reads `size` bytes; false (the file rejected with `why`) when it ends first.
  bool read(void* data, size_t size, const char* why);
  // Reads a fixed-size header; false (rejected: "truncated header") when the file is shorter.
  template <class Header>
  bool readHeader(Header& header) {
    return read(&header, sizeof header, "truncated header");
  }
  // True at the end of the file; else the file is rejected ("trailing bytes").
  bool atEnd();
  // Sets the warning "FILE: WHY; INSTEAD", closes and deletes the file. Returns nullopt, so that a
  // loader can `return reader.reject(...)`.
  std::nullopt_t reject(const char* why);

 private:
  std::filesystem::path file_;
  std::string instead_;
  std::string* warning_;
  std::ifstream in_;
  bool opened_ = false;
};

}  // namespace meso
