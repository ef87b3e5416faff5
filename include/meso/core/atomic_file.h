// Output files appear under their final name only when complete: write a temporary, check every
// write, fsync and close, then rename. Outputs that exist and are not regular files (a device
// node, FIFO, symlink or folder) are refused rather than replaced by the rename.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace meso {

// A temporary name in the same folder as `target` (so rename is atomic), keeping its extension so
// format-sniffing writers pick the right format: "dir/.name.tmp-PID-N.ext".
std::filesystem::path temporarySibling(const std::filesystem::path& target);

// Throws meso::Error("TARGET: what: expected ...") unless `target` can be written as a regular
// file: it does not exist or is a regular file (not a symlink, FIFO, device or folder), every
// existing ancestor is a folder, and the nearest existing one lets this process write into it.
// `what` names the option ("-o", "--stats").
void checkOutputFile(const std::filesystem::path& target, const std::string& what);

// Creates `folder` and its parents; throws meso::Error naming the path (not a filesystem_error)
// when a component exists and is not a folder or cannot be created.
void createOutputFolder(const std::filesystem::path& folder, const std::string& what);

// How a file is written.
struct WriteOptions {
  // Fail with ENOSPC, as a full disk does, once the file would grow past this many bytes (tests
  // stand in for a full disk with it). Negative: no limit.
  long long maxBytes = -1;
};

// Writes `bytes` to a new file `file` (which must not exist), checking every write, the fsync and
// the close: throws meso::Error("SHOWN: cannot write: <errno text>") on a full disk or I/O error
// (SHOWN: `shown`, the final name of a temporary, or `file` when empty).
void writeBytes(const std::filesystem::path& file, std::string_view bytes,
                const std::filesystem::path& shown = {}, const WriteOptions& options = {});

// Calls write(tmp) and renames tmp to target; on any exception removes tmp and rethrows.
void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path&)>& write);

// writeAtomically with writeBytes: the one way meso writes a whole file.
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes,
                         const WriteOptions& options = {});

// Several files that must appear together or not at all (a frame's EXR and PNG and the run's
// stats): stage() writes each completely under a temporary name, commit() renames them all; the
// destructor removes whatever was staged and not committed.
class StagedFiles {
 public:
  StagedFiles() = default;
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();
  void stage(const std::filesystem::path& target, std::string_view bytes);
  void commit();
  bool empty() const { return staged_.empty(); }

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;  // tmp, target
};

// Removes every temporary made by temporarySibling() that was neither renamed nor removed yet (for
// a process stopped by SIGINT/SIGTERM on its way out: no partial file stays behind). Returns how
// many were removed. forgetTemporary() drops one from that list (after renaming it by hand).
int removeTemporaries();
void forgetTemporary(const std::filesystem::path& tmp);

}  // namespace meso
