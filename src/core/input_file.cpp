#include "meso/core/input_file.h"

#include "meso/core/error.h"
#include "meso/core/huge_pages.h"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace meso {

const char* fileTypeName(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISREG(mode)) return "a file";
  return "not a regular file";
}

namespace {

std::string prefix(const std::filesystem::path& file, const std::string& what) {
  return file.string() + ": " + (what.empty() ? "" : what + ": ");
}

uint64_t checkStat(const struct stat& st, const std::filesystem::path& file,
                   const std::string& what, uint64_t maxBytes) {
  if (!S_ISREG(st.st_mode))
    throw Error(prefix(file, what) + "expected a regular file, found " + fileTypeName(st.st_mode));
  const uint64_t size = static_cast<uint64_t>(st.st_size);
  if (size > maxBytes)
    throw Error(prefix(file, what) + "expected a file of at most " + std::to_string(maxBytes) +
                " bytes, it has " + std::to_string(size));
  return size;
}

}  // namespace

uint64_t checkInputFile(const std::filesystem::path& file, const std::string& what,
                        uint64_t maxBytes) {
  struct stat st;
  if (::stat(file.c_str(), &st) != 0)
    throw Error(prefix(file, what) + (errno == ENOENT
                                          ? std::string("file not found")
                                          : std::string("cannot open: ") + std::strerror(errno)));
  return checkStat(st, file, what, maxBytes);
}

std::string readInputFile(const std::filesystem::path& file, const std::string& what,
                          uint64_t maxBytes) {
  checkInputFile(file, what, maxBytes);
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw Error(prefix(file, what) + "cannot open: " + std::strerror(errno));
  struct stat st;
  if (::fstat(fd, &st) != 0) {
    ::close(fd);
    throw Error(prefix(file, what) + "cannot open: " + std::strerror(errno));
  }
  uint64_t size;
  try {
    size = checkStat(st, file, what, maxBytes);
  } catch (...) {
    ::close(fd);
    throw;
  }
  std::string bytes;
  resizePopulated(bytes, size);  // a large file's pages mapped on every core before the read
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, bytes.data() + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      throw Error(prefix(file, what) + "cannot read: " + std::strerror(err));
    }
    if (n == 0) break;  // shrank while read
    done += static_cast<size_t>(n);
  }
  ::close(fd);
  bytes.resize(done);
  return bytes;
}

}  // namespace meso
