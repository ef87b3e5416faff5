// SIGINT and SIGTERM for every command: the frame in progress stops, nothing partial is written,
// status 128 + the signal's number, as a shell reports a process the signal ended (130 for SIGINT,
// 143 for SIGTERM).
#pragma once

#include <atomic>
#include <exception>

namespace meso::app {

// Installs the handler and its watchdog (once, before a command runs).
void installInterruptHandler();
// True once SIGINT or SIGTERM arrived (for commands that poll it in their long loops, and as
// RenderOptions::cancel).
const std::atomic<bool>& interruptRequested();
// The exit status for the signal that arrived: 128 + its number (130 when none did).
int interruptedStatus();
// Thrown by a command that stopped because of the signal; main() exits with interruptedStatus().
struct RenderInterrupted : std::exception {
  const char* what() const noexcept override { return "interrupted"; }
};

}  // namespace meso::app
