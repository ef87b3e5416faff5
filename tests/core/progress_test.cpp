// The progress bar draws on a terminal only: undelayed bars always show their final state, delayed
// bars only for work that outlasts the delay, and nothing when disabled (--quiet).
#include "meso/core/progress.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

#include <fcntl.h>
#include <unistd.h>

namespace meso {
namespace {

// Runs `body` with stderr on a pseudo-terminal and returns what it wrote there.
template <class F>
std::string onTerminal(F body) {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0) return "no pty";
  const int slave = ::open(::ptsname(master), O_RDWR | O_NOCTTY);
  if (slave < 0) return "no pty";
  const int saved = ::dup(STDERR_FILENO);
  ::dup2(slave, STDERR_FILENO);
  body();
  std::fflush(stderr);
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  ::close(slave);
  ::fcntl(master, F_SETFL, O_NONBLOCK);
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(master, buf, sizeof buf)) > 0;)
    out.append(buf, static_cast<size_t>(n));
  ::close(master);
  return out;
}

TEST(ProgressBar, DrawsOnATerminalUnlessDelayedOrDisabled) {
  const std::string plain = onTerminal([] {
    ProgressBar bar("plain", 4);
    bar.advance(4);
    bar.finish();
  });
  if (plain == "no pty") GTEST_SKIP() << "no pseudo-terminal on this machine (/dev/ptmx)";
  EXPECT_NE(plain.find("plain [="), std::string::npos) << plain;
  EXPECT_NE(plain.find("4/4"), std::string::npos) << plain;

  // Work shorter than the delay draws nothing; longer work draws.
  const std::string quick = onTerminal([] {
    ProgressBar bar("quick", 4, true, std::chrono::milliseconds(2000));
    bar.advance(4);
  });
  EXPECT_EQ(quick.find("quick"), std::string::npos) << quick;
  const std::string slow = onTerminal([] {
    ProgressBar bar("slow", 4, true, std::chrono::milliseconds(50));
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    bar.advance(4);
  });
  EXPECT_NE(slow.find("slow ["), std::string::npos) << slow;
  EXPECT_NE(slow.find("4/4"), std::string::npos) << slow;

  const std::string quiet = onTerminal([] {
    ProgressBar bar("quiet", 4, false);
    bar.advance(4);
  });
  EXPECT_EQ(quiet.find("quiet"), std::string::npos) << quiet;
}

}  // namespace
}  // namespace meso
