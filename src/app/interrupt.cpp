// SIGINT/SIGTERM handling with a watchdog (see interrupt.h).
#include "interrupt.h"

#include "meso/core/atomic_file.h"

#include <chrono>
#include <csignal>
#include <thread>

#include <semaphore.h>
#include <unistd.h>

namespace meso::app {
namespace {

std::atomic<bool> gInterrupted{false};
std::atomic<int> gSignal{SIGINT};  // the signal that arrived (lock-free: async-signal-safe)
static_assert(std::atomic<int>::is_always_lock_free);
sem_t* gWake = nullptr;
// How long a command has to stop by itself after SIGINT/SIGTERM before the watchdog ends it.
constexpr int kInterruptGraceMs = 100;

extern "C" void onInterrupt(int sig) {
  gSignal.store(sig);
  gInterrupted.store(true);
  if (gWake) sem_post(gWake);
}

}  // namespace

const std::atomic<bool>& interruptRequested() { return gInterrupted; }

int interruptedStatus() { return 128 + gSignal.load(); }

void installInterruptHandler() {
  // Commands poll interruptRequested() in their long loops and stop cleanly; a loop that does not
  // (inside a library, OpenSubdiv, table building) is stopped by this watchdog, woken by the
  // handler through a semaphore (sem_post is async-signal-safe): after a grace period it removes
  // every temporary and exits with interruptedStatus(). Final names only ever hold complete files,
  // so nothing partial remains either way.
  static sem_t wake;
  sem_init(&wake, 0, 0);
  gWake = &wake;
  std::thread([] {
    while (sem_wait(gWake) != 0) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(kInterruptGraceMs));
    removeTemporaries();
    static const char message[] =
        "meso: interrupted; complete outputs are kept, nothing partial was written\n";
    (void)!::write(2, message, sizeof message - 1);
    ::_exit(interruptedStatus());
  }).detach();
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
}

}  // namespace meso::app
