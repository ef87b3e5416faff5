#include "meso/core/atomic_file.h"

#include <gtest/gtest.h>

#include <fstream>
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

}  // namespace
}  // namespace meso
