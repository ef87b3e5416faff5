// Warnings keep the order they were added in, formatted as fmt formats; adding from many threads at
// once loses none and keeps each thread's own order; append puts a task's warnings after the rest.
#include "meso/core/warnings.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

namespace meso {
namespace {

TEST(Warnings, KeepTheOrderTheyWereAddedInAndSkipEmptyTexts) {
  Warnings w;
  EXPECT_TRUE(w.empty());
  w.add("first");
  w.add("");  // nothing to report
  w.warn("material '{}': {} sets at a step of {:.4g}", "stone", 3, 0.123456);
  w.add("last");
  const std::vector<std::string> expected = {
      "first", "material 'stone': 3 sets at a step of 0.1235", "last"};
  EXPECT_EQ(w.list(), expected);
  EXPECT_EQ(w.size(), 3u);
}

TEST(Warnings, AppendPutsAnotherSinksWarningsAfterTheseAndEmptiesIt) {
  Warnings all, task1, task2;
  all.add("scene");
  task1.add("1a");
  task1.add("1b");
  task2.add("2a");
  // In task order, whatever order the tasks finished in.
  all.append(std::move(task1));
  all.append(std::move(task2));
  EXPECT_EQ(all.list(), (std::vector<std::string>{"scene", "1a", "1b", "2a"}));
  EXPECT_TRUE(task1.empty());
  Warnings moved = std::move(all);
  EXPECT_EQ(moved.size(), 4u);
}

TEST(Warnings, ThreadsAddingAtOnceLoseNoneAndKeepTheirOwnOrder) {
  constexpr int kThreads = 8, kEach = 2000;
  Warnings w;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&w, t] {
      for (int i = 0; i < kEach; ++i) w.warn("{} {}", t, i);
    });
  for (std::thread& t : threads) t.join();
  const std::vector<std::string> list = w.list();
  ASSERT_EQ(list.size(), size_t{kThreads} * kEach);
  std::vector<int> next(kThreads, 0);
  for (const std::string& s : list) {
    const size_t space = s.find(' ');
    ASSERT_NE(space, std::string::npos) << s;
    const int t = std::stoi(s.substr(0, space)), i = std::stoi(s.substr(space + 1));
    ASSERT_EQ(i, next[t]) << "thread " << t << " out of order";
    ++next[t];
  }
}

}  // namespace
}  // namespace meso
