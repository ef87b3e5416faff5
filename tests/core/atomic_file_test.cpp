#include "meso/core/atomic_file.h"

#include "meso/core/error.h"
#include "meso/core/input_file.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace meso {
namespace {

namespace fs = std::filesystem;

TEST(AtomicFile, TemporaryKeepsFolderAndExtension) {
  const fs::path t = temporarySibling("/some/dir/frame_0001.exr");
  EXPECT_EQ(t.parent_path(), fs::path("/some/dir"));
  EXPECT_EQ(t.extension(), ".exr");
  EXPECT_NE(t.filename(), fs::path("frame_0001.exr"));
  EXPECT_NE(temporarySibling("/x/a.exr"), temporarySibling("/x/a.exr"));
}

TEST(AtomicFile, ThrowingWriterLeavesNothing) {
  const fs::path dir = fs::temp_directory_path() / "meso_atomic_file_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path target = dir / "out.txt";
  EXPECT_THROW(writeAtomically(target,
                               [](const fs::path& tmp) {
                                 std::ofstream(tmp) << "half";
                                 throw std::runtime_error("disk full");
                               }),
               std::runtime_error);
  EXPECT_TRUE(fs::is_empty(dir));
  writeAtomically(target, [](const fs::path& tmp) { std::ofstream(tmp) << "whole"; });
  std::ifstream in(target);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "whole");
  fs::remove_all(dir);
}

class OutputFileTest : public testing::TempDirTest {
 protected:
  std::string errorOf(const std::function<void()>& f) {
    try {
      f();
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  }
  std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
};

// A write that fails part way (WriteOptions::maxBytes stands in for a full disk) leaves neither the
// final file nor the temporary, and says which file and why.
TEST_F(OutputFileTest, FailedWriteLeavesNothing) {
  const fs::path target = dir_ / "big.bin";
  const std::string e = errorOf(
      [&] { writeFileAtomically(target, std::string(5000, 'x'), WriteOptions{.maxBytes = 1000}); });
  EXPECT_NE(e.find(target.string() + ": cannot write: No space left on device"), std::string::npos)
      << e;
  EXPECT_TRUE(fs::is_empty(dir_));
  writeFileAtomically(target, std::string(5000, 'y'));
  EXPECT_EQ(read(target), std::string(5000, 'y'));
}

// The same on a real full file system: a 4 KiB tmpfs, when this process may mount one (root).
TEST_F(OutputFileTest, FullTmpfsLeavesNothing) {
  const fs::path at = dir_ / "tmpfs";
  fs::create_directories(at);
  if (::mount("tmpfs", at.c_str(), "tmpfs", 0, "size=4096") != 0)
    GTEST_SKIP()
        << "cannot mount a tmpfs here (needs root); FailedWriteLeavesNothing covers the same path";
  const std::string e =
      errorOf([&] { writeFileAtomically(at / "big.bin", std::string(1 << 20, 'x')); });
  const bool empty = fs::is_empty(at);
  ::umount2(at.c_str(), MNT_DETACH);
  EXPECT_NE(e.find("big.bin: cannot write: No space left on device"), std::string::npos) << e;
  EXPECT_TRUE(empty);
}

// Staged files appear together on commit, and not at all when the stage is abandoned.
TEST_F(OutputFileTest, StagedFilesAllOrNothing) {
  {
    StagedFiles s;
    s.stage(dir_ / "a.exr", "A");
    s.stage(dir_ / "a.png", "P");
    EXPECT_FALSE(fs::exists(dir_ / "a.exr"));
  }
  EXPECT_TRUE(fs::is_empty(dir_));
  StagedFiles s;
  s.stage(dir_ / "a.exr", "A");
  s.stage(dir_ / "a.png", "P");
  s.commit();
  EXPECT_EQ(read(dir_ / "a.exr"), "A");
  EXPECT_EQ(read(dir_ / "a.png"), "P");
  EXPECT_TRUE(s.empty());
}

// Existing outputs that are not regular files are refused, never replaced by the rename.
TEST_F(OutputFileTest, SpecialFilesAreRefused) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0644), 0);
  fs::create_symlink(dir_ / "elsewhere", dir_ / "link");
  fs::create_directories(dir_ / "folder");
  std::ofstream(dir_ / "file") << "x";
  EXPECT_NE(errorOf([&] { checkOutputFile("/dev/null", "--stats"); })
                .find("/dev/null: --stats: expected a regular file to write (or no file), found a "
                      "character device"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { writeFileAtomically(dir_ / "fifo", "x"); }).find("found a FIFO"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { writeFileAtomically(dir_ / "link", "x"); }).find("found a symbolic link"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { writeFileAtomically(dir_ / "folder", "x"); }).find("found a folder"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              writeFileAtomically(dir_ / "file/x", "x");
            }).find("expected a folder to write into, " + (dir_ / "file").string() + " is a file"),
            std::string::npos);
  EXPECT_NE(
      errorOf([&] { createOutputFolder(dir_ / "file/sub", "-o"); }).find("-o: expected a folder"),
      std::string::npos);
  EXPECT_TRUE(fs::is_fifo(dir_ / "fifo"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "link"));
  EXPECT_FALSE(fs::exists(dir_ / "elsewhere"));
  EXPECT_EQ(read(dir_ / "file"), "x");
  writeFileAtomically(dir_ / "file", "y");  // a regular file is replaced
  EXPECT_EQ(read(dir_ / "file"), "y");
}

// Inputs: regular files only, with a size limit; a FIFO or /dev/zero is refused at once.
TEST_F(OutputFileTest, InputsAreRegularFilesOfBoundedSize) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0644), 0);
  std::ofstream(dir_ / "f.txt") << "hello";
  const auto start = std::chrono::steady_clock::now();
  EXPECT_NE(errorOf([&] {
              readInputFile(dir_ / "fifo", "scene", 1000);
            }).find("fifo: scene: expected a regular file, found a FIFO"),
            std::string::npos);
  EXPECT_NE(
      errorOf([&] { readInputFile("/dev/zero", "scene", 1000); }).find("found a character device"),
      std::string::npos);
  EXPECT_NE(errorOf([&] { readInputFile(dir_, "scene", 1000); }).find("found a folder"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              readInputFile(dir_ / "none", "scene", 1000);
            }).find("none: scene: file not found"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              readInputFile(dir_ / "f.txt", "scene", 4);
            }).find("expected a file of at most"),
            std::string::npos);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  EXPECT_EQ(readInputFile(dir_ / "f.txt", "scene", 5), "hello");
}

}  // namespace
}  // namespace meso
