#include "meso/core/cache_file.h"

#include <string>
#include <system_error>
#include <utility>

namespace meso {

CacheFileReader::CacheFileReader(std::filesystem::path file, std::string instead,
                                 std::string* warning)
    : file_(std::move(file)), instead_(std::move(instead)), warning_(warning) {
  in_.open(file_, std::ios::binary);
  opened_ = static_cast<bool>(in_);
}

bool CacheFileReader::read(void* data, size_t size, const char* why) {
  if (in_.read(static_cast<char*>(data), static_cast<std::streamsize>(size))) return true;
  reject(why);
  return false;
}

bool CacheFileReader::atEnd() {
  if (in_.peek() == std::char_traits<char>::eof()) return true;
  reject("trailing bytes");
  return false;
}

std::nullopt_t CacheFileReader::reject(const char* why) {
  if (warning_) *warning_ = file_.string() + ": " + why + "; " + instead_;
  in_.close();
  std::error_code ignored;
  std::filesystem::remove(file_, ignored);
  return std::nullopt;
}

}  // namespace meso
