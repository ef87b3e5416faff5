// Warnings that library code reports and the caller prints (the CLI as "meso: warning: TEXT"), in
// the order they were added. Adding is thread-safe; tasks that run at once and must report in a
// fixed order whatever the thread count each fill their own Warnings, which the caller then
// appends in task order.
#pragma once

#include <fmt/format.h>

#include <cstddef>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace meso {

class Warnings {
 public:
  Warnings() = default;
  // Moving is not thread-safe: no other thread may use either object meanwhile.
  Warnings(Warnings&& other) noexcept : texts_(std::move(other.texts_)) {}
  Warnings& operator=(Warnings&& other) noexcept;
  Warnings(const Warnings&) = delete;
  Warnings& operator=(const Warnings&) = delete;

  // Adds one warning; an empty text adds none (callers pass what an operation reported, if
  // anything).
  void add(std::string text);
  template <class... Args>
  void warn(fmt::format_string<Args...> format, Args&&... args) {
    add(fmt::format(format, std::forward<Args>(args)...));
  }
  // Adds `other`'s warnings after these, in their order, and empties it.
  void append(Warnings&& other);

  // A copy of the warnings in the order they were added.
  std::vector<std::string> list() const;
  size_t size() const;
  bool empty() const { return size() == 0; }

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> texts_;
};

}  // namespace meso
