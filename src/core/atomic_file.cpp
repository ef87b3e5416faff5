#include "meso/core/atomic_file.h"

#include "meso/core/error.h"
#include "meso/core/input_file.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <set>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace meso {
namespace {

// Temporaries not yet renamed or removed: what an interrupted process must delete on its way out.
std::mutex gTemporariesMutex;
std::set<std::filesystem::path>& temporaries() {
  static std::set<std::filesystem::path> set;
  return set;
}

void forget(const std::filesystem::path& tmp) {
  std::lock_guard<std::mutex> lock(gTemporariesMutex);
  temporaries().erase(tmp);
}

[[noreturn]] void failErrno(const std::filesystem::path& file, const char* doing, int err) {
  throw Error(file.string() + ": cannot " + doing + ": " + std::strerror(err));
}

}  // namespace

std::filesystem::path temporarySibling(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  // append() rather than operator+ chains: GCC 12 warns falsely (-Wrestrict) on the latter.
  std::string name = ".";
  name.append(target.stem().string())
      .append(".tmp-")
      .append(std::to_string(::getpid()))
      .append("-");
  name.append(std::to_string(counter.fetch_add(1))).append(target.extension().string());
  std::filesystem::path tmp = target.parent_path() / name;
  std::lock_guard<std::mutex> lock(gTemporariesMutex);
  temporaries().insert(tmp);
  return tmp;
}

namespace {

// The nearest existing one of `start` and its ancestors must be a folder (else meso::Error
// "PREFIX EXPECTED, P is a ..."); nothing above it is looked at.
void requireNearestIsFolder(const std::filesystem::path& start, const std::string& prefix,
                            const char* expected) {
  struct stat st;
  for (std::filesystem::path p = start; !p.empty(); p = p.parent_path()) {
    if (::stat(p.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode))
        throw Error(prefix + expected + ", " + p.string() + " is " + fileTypeName(st.st_mode));
      return;
    }
    if (p == p.parent_path()) return;
  }
}

// The nearest existing one of `folder` and its ancestors must let this process create entries in
// it (the temporary and its rename, or the folders below it): a read-only, immutable or special
// folder fails here, before any work, not when the output is written. Probed by creating and
// removing an empty temporary there (permissions alone do not tell: root passes access(2) on
// /proc and on read-only mounts' folders).
void requireWritableFolder(const std::filesystem::path& folder, const std::string& prefix) {
  struct stat st;
  for (std::filesystem::path p = folder.empty() ? "." : folder;; p = p.parent_path()) {
    if (::stat(p.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode)) return;  // requireNearestIsFolder's error
      const std::filesystem::path probe = temporarySibling(p / "meso-write-probe");
      const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
      if (fd < 0) {
        const int err = errno;
        forget(probe);
        throw Error(prefix + "cannot write into the folder " + p.string() + ": " +
                    std::strerror(err));
      }
      ::close(fd);
      ::unlink(probe.c_str());
      forget(probe);
      return;
    }
    if (p.empty() || p == p.parent_path()) return;
  }
}

}  // namespace

void checkOutputFile(const std::filesystem::path& target, const std::string& what) {
  const std::string prefix = target.string() + ": " + (what.empty() ? "" : what + ": ");
  struct stat st;
  if (::lstat(target.c_str(), &st) == 0) {
    if (!S_ISREG(st.st_mode))
      throw Error(prefix + "expected a regular file to write (or no file), found " +
                  fileTypeName(st.st_mode));
    requireWritableFolder(target.parent_path(), prefix);
    return;
  }
  if (errno != ENOENT && errno != ENOTDIR)
    throw Error(prefix + "cannot inspect: " + std::strerror(errno));
  // Missing: its nearest existing ancestor must be a folder, and writable.
  requireNearestIsFolder(target.parent_path(), prefix, "expected a folder to write into");
  requireWritableFolder(target.parent_path(), prefix);
}

void createOutputFolder(const std::filesystem::path& folder, const std::string& what) {
  if (folder.empty()) return;
  const std::string prefix = folder.string() + ": " + (what.empty() ? "" : what + ": ");
  requireNearestIsFolder(folder, prefix, "expected a folder");
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) throw Error(prefix + "cannot create the folder: " + ec.message());
}

void writeBytes(const std::filesystem::path& path, std::string_view bytes,
                const std::filesystem::path& shown, const WriteOptions& options) {
  const std::filesystem::path& file = shown.empty() ? path : shown;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) failErrno(file, "create", errno);
  const long long limit = options.maxBytes;
  size_t done = 0;
  while (done < bytes.size()) {
    size_t chunk = std::min<size_t>(bytes.size() - done, size_t(1) << 20);
    if (limit >= 0 && static_cast<long long>(done + chunk) > limit) {
      ::close(fd);
      failErrno(file, "write", ENOSPC);
    }
    const ssize_t n = ::write(fd, bytes.data() + done, chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : EIO;
      ::close(fd);
      failErrno(file, "write", err);
    }
    done += static_cast<size_t>(n);
  }
  // Delayed allocation (and NFS) report a full disk only here.
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
    const int err = errno;
    ::close(fd);
    failErrno(file, "write (fsync)", err);
  }
  if (::close(fd) != 0) failErrno(file, "write (close)", errno);
}

namespace {

// Renames a complete temporary into place and forgets it; throws meso::Error if it cannot.
void renameIntoPlace(const std::filesystem::path& tmp, const std::filesystem::path& target) {
  std::error_code ec;
  std::filesystem::rename(tmp, target, ec);
  if (ec)
    throw Error(target.string() + ": cannot rename the complete file into place: " + ec.message());
  forget(tmp);
}

}  // namespace

void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path&)>& write) {
  checkOutputFile(target, "");
  const std::filesystem::path tmp = temporarySibling(target);
  try {
    write(tmp);
    renameIntoPlace(tmp, target);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    forget(tmp);
    throw;
  }
}

void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes,
                         const WriteOptions& options) {
  writeAtomically(
      target, [&](const std::filesystem::path& tmp) { writeBytes(tmp, bytes, target, options); });
}

StagedFiles::~StagedFiles() {
  for (const auto& [tmp, target] : staged_) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    forget(tmp);
  }
}

void StagedFiles::stage(const std::filesystem::path& target, std::string_view bytes) {
  checkOutputFile(target, "");
  const std::filesystem::path tmp = temporarySibling(target);
  try {
    writeBytes(tmp, bytes, target);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    forget(tmp);
    throw;
  }
  staged_.emplace_back(tmp, target);
}

void StagedFiles::commit() {
  for (const auto& [tmp, target] : staged_) checkOutputFile(target, "");
  while (!staged_.empty()) {
    const auto [tmp, target] = staged_.front();
    renameIntoPlace(tmp, target);
    staged_.erase(staged_.begin());
  }
}

int removeTemporaries() {
  std::lock_guard<std::mutex> lock(gTemporariesMutex);
  int removed = 0;
  for (const std::filesystem::path& tmp : temporaries()) {
    std::error_code ignored;
    removed += std::filesystem::remove(tmp, ignored) ? 1 : 0;
  }
  temporaries().clear();
  return removed;
}

void forgetTemporary(const std::filesystem::path& tmp) { forget(tmp); }

}  // namespace meso
