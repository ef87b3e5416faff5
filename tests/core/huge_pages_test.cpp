// adviseHugePages and the executable's memory set-up (src/core/huge_new.cpp, linked into this test
// program as into meso: its operator new and the heap reserved before main): the kernel's own
// record of the advice, the "hg" flag of a mapping in /proc/self/smaps, says which pages were
// advised.
#include "meso/core/huge_pages.h"

#include "meso/core/timer.h"

#include <gtest/gtest.h>

#include <sys/mman.h>
#include <sys/resource.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace meso {
namespace {

// Whether the mapping that holds `address` carries the huge page advice (VmFlags "hg").
bool advised(const void* address) {
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> begin >> dash >> end && dash == '-') {
      inside = begin <= at && at < end;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line.find(" hg") != std::string::npos;
  }
  return false;
}

bool kernelHasHugePages() {
  return std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled") &&
         std::filesystem::exists("/proc/self/smaps");
}

// An untouched anonymous mapping of `bytes` whose start is 2 MiB-aligned.
struct Mapping {
  explicit Mapping(std::size_t bytes) : size(bytes + kHugePageBytes) {
    raw = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    const auto r = reinterpret_cast<std::uintptr_t>(raw);
    aligned = reinterpret_cast<char*>((r + kHugePageBytes - 1) & ~(kHugePageBytes - 1));
  }
  ~Mapping() {
    if (raw != MAP_FAILED) munmap(raw, size);
  }
  std::size_t size;
  void* raw;
  char* aligned;
};

TEST(HugePages, TheWholeHugePagesInsideABlockAreAdvisedAndNothingAroundThem) {
  if (!kernelHasHugePages()) GTEST_SKIP() << "no transparent huge pages here";
  const Mapping m(8 * kHugePageBytes);
  ASSERT_NE(m.raw, MAP_FAILED);
  // A block from 4 KiB after a huge page boundary to 1 KiB before the fourth boundary after that
  // one: the two whole huge pages in between are advised, the partial ones at the ends are not.
  char* block = m.aligned + 4096;
  adviseHugePages(block, 4 * kHugePageBytes - 4096 - 1024);
  EXPECT_FALSE(advised(block));
  EXPECT_FALSE(advised(m.aligned + kHugePageBytes - 1));
  EXPECT_TRUE(advised(m.aligned + kHugePageBytes));
  EXPECT_TRUE(advised(m.aligned + 3 * kHugePageBytes - 1));
  EXPECT_FALSE(advised(m.aligned + 3 * kHugePageBytes));
  EXPECT_FALSE(advised(m.aligned + 5 * kHugePageBytes));
}

TEST(HugePages, BlocksWithoutAWholeHugePageAndNullAreLeftAlone) {
  if (!kernelHasHugePages()) GTEST_SKIP() << "no transparent huge pages here";
  const Mapping m(4 * kHugePageBytes);
  ASSERT_NE(m.raw, MAP_FAILED);
  adviseHugePages(m.aligned + 1, kHugePageBytes);  // 2 MiB, but across a boundary
  adviseHugePages(m.aligned + kHugePageBytes, kHugePageBytes - 1);
  adviseHugePages(nullptr, 4 * kHugePageBytes);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_FALSE(advised(m.aligned + k * kHugePageBytes)) << k;
  adviseHugePages(m.aligned, kHugePageBytes);  // exactly one huge page
  EXPECT_TRUE(advised(m.aligned));
  EXPECT_FALSE(advised(m.aligned + kHugePageBytes));
}

TEST(HugePages, OperatorNewAdvisesLargeBlocks) {
  if (!kHugeNewBuilt) GTEST_SKIP() << "AddressSanitizer keeps its own operator new";
  if (!kernelHasHugePages()) GTEST_SKIP() << "no transparent huge pages here";
  // Above the mmap threshold: a mapping of its own, which only operator new's advice can mark.
  const std::size_t large = kHeapMmapBytes + 3 * kHugePageBytes;
  const std::unique_ptr<char[]> big(new char[large]);
  const auto at = reinterpret_cast<std::uintptr_t>(big.get());
  const auto firstWhole = (at + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
  EXPECT_TRUE(advised(reinterpret_cast<const void*>(firstWhole)));
  big[0] = 1;
  big[large - 1] = 2;  // the block is usable to its last byte
  EXPECT_EQ(big[0] + big[large - 1], 3);
}

TEST(HugePages, SmallBlocksComeFromTheAdvisedHeapReserve) {
  if (!kHugeNewBuilt) GTEST_SKIP() << "AddressSanitizer has its own heap";
  if (!kernelHasHugePages()) GTEST_SKIP() << "no transparent huge pages here";
  rlimit limit{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &limit), 0);
  if (limit.rlim_cur != RLIM_INFINITY && limit.rlim_cur / 8 < kHeapReserveBytes)
    GTEST_SKIP() << "ulimit -v leaves no room for the heap reserve";
  // Blocks under the mmap threshold come from the heap: once the free space left in the heap's
  // first part (grown before the reserve, not advised) is used, they lie in heap that was advised
  // before main (src/core/huge_new.cpp). Without the reserve the heap's pages are plain 4 KiB ones.
  for (const std::size_t bytes : {std::size_t{16} << 10, std::size_t{1} << 20}) {
    const std::size_t count = (std::size_t{192} << 20) / bytes;  // 192 MiB of them
    std::vector<void*> blocks(count);
    std::size_t looked = 0, inAdvised = 0;
    for (std::size_t k = 0; k < count; ++k) {
      void*& b = blocks[k];
      b = bytes < (std::size_t{1} << 20) ? static_cast<void*>(new char[bytes]) : std::malloc(bytes);
      if (k % (bytes < (std::size_t{1} << 20) ? 64 : 1) == 0)  // smaps is slow to read
        ++looked, inAdvised += advised(b);
    }
    EXPECT_GE(inAdvised, looked / 2) << bytes << " bytes: " << inAdvised << " of " << looked;
    for (void* b : blocks)
      if (bytes < (std::size_t{1} << 20))
        delete[] static_cast<char*>(b);
      else
        std::free(b);
  }
}

// Memory a worker thread frees stays in its arena, resident; releaseFreedHeap gives its whole
// pages back. 48 blocks of 1 MiB (heap blocks: under kHeapMmapBytes; one heap of a thread's arena
// holds 64 MiB), written and freed by a thread that lives on, as the renderer's workers do, with a
// small block after them that keeps them from the top of its arena.
TEST(HugePages, ReleaseFreedHeapGivesBackWhatAThreadFreed) {
  if (!kHugeNewBuilt) GTEST_SKIP() << "AddressSanitizer keeps its own heap";
  std::atomic<int> stage{0};
  void* fence = nullptr;
  std::thread worker([&] {
    std::vector<char*> blocks;
    for (int k = 0; k < 48; ++k) {
      blocks.push_back(static_cast<char*>(std::malloc(std::size_t{1} << 20)));
      if (blocks.back()) std::memset(blocks.back(), 1, std::size_t{1} << 20);
    }
    fence = std::malloc(64);
    for (char* b : blocks) std::free(b);
    stage = 1;
    while (stage.load() != 2) std::this_thread::yield();
  });
  while (stage.load() != 1) std::this_thread::yield();
  const double before = anonymousRssMib();
  releaseFreedHeap();
  const double after = anonymousRssMib();
  stage = 2;
  worker.join();
  std::free(fence);
  EXPECT_GT(before - after, 32.0) << before << " MiB before, " << after << " after";
}

// The pages of [p, p + bytes) that are mapped (mincore), 4 KiB each.
std::size_t residentPages(const void* p, std::size_t bytes) {
  const std::size_t pages = (bytes + 4095) / 4096;
  std::vector<unsigned char> in(pages);
  if (mincore(const_cast<void*>(p), bytes, in.data()) != 0) return 0;
  std::size_t n = 0;
  for (unsigned char c : in) n += c & 1;
  return n;
}

// Whether this kernel populates on request (MADV_POPULATE_WRITE, Linux 5.14 and later).
bool kernelPopulates() {
#if defined(MADV_POPULATE_WRITE)
  Mapping m(4096);
  return m.raw != MAP_FAILED && madvise(m.aligned, 4096, MADV_POPULATE_WRITE) == 0;
#else
  return false;
#endif
}

// populatePages maps every whole page inside the block, on a block that starts and ends inside
// pages, and nothing around it; the contents stay as they were.
TEST(HugePages, PopulatePagesMapsTheWholePagesOfTheBlockAndNothingAround) {
  if (!kernelPopulates()) GTEST_SKIP() << "this kernel has no MADV_POPULATE_WRITE";
  constexpr std::size_t kBytes = 9 * kHugePageBytes;
  Mapping m(kBytes + kHugePageBytes);
  ASSERT_NE(m.raw, MAP_FAILED);
  // No huge pages here: one 4 KiB page at a time, so that the edges are seen page by page.
  madvise(m.aligned, kBytes + kHugePageBytes, MADV_NOHUGEPAGE);
  m.aligned[5 * 4096 + 7] = 42;  // one page written before
  ASSERT_EQ(residentPages(m.aligned, kBytes + kHugePageBytes), 1u);
  char* block = m.aligned + 3 * 4096 + 100;  // the block: 100 bytes into page 3 ...
  const std::size_t bytes = kBytes - 200;    // ... to 100 bytes before the end of its last page
  populatePages(block, bytes);
  constexpr std::size_t kPages = kBytes / 4096;  // the block ends inside page 3 + kPages - 1
  EXPECT_EQ(residentPages(m.aligned, 4 * 4096), 0u) << "page 3, partly the block's, was mapped";
  EXPECT_EQ(residentPages(m.aligned + 4 * 4096, (kPages - 2) * 4096), kPages - 2)
      << "not every page wholly inside the block is mapped";
  EXPECT_EQ(residentPages(m.aligned + (kPages + 2) * 4096, kHugePageBytes + 4096), 0u)
      << "a page after the block was mapped";
  EXPECT_EQ(m.aligned[5 * 4096 + 7], 42);
  EXPECT_EQ(m.aligned[6 * 4096], 0);
}

// resizePopulated is resize: zeros after the elements kept, on a fresh vector and on one that
// grows.
TEST(HugePages, ResizePopulatedKeepsTheElementsAndZerosTheNewOnes) {
  std::vector<float> v;
  resizePopulated(v, 3 * kHugePageBytes / sizeof(float) + 5);
  ASSERT_EQ(v.size(), 3 * kHugePageBytes / sizeof(float) + 5);
  for (float x : v) ASSERT_EQ(x, 0.0f);
  for (std::size_t k = 0; k < v.size(); ++k) v[k] = static_cast<float>(k % 1000);
  const std::size_t old = v.size();
  resizePopulated(v, 2 * old);
  ASSERT_EQ(v.size(), 2 * old);
  for (std::size_t k = 0; k < old; ++k) ASSERT_EQ(v[k], static_cast<float>(k % 1000)) << k;
  for (std::size_t k = old; k < v.size(); ++k) ASSERT_EQ(v[k], 0.0f) << k;
  resizePopulated(v, 10);  // shrinking, as resize
  EXPECT_EQ(v.size(), 10u);
  EXPECT_EQ(v[9], 9.0f);
}

}  // namespace
}  // namespace meso
