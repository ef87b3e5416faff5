// SIGINT and SIGTERM for every command: the frame in progress stops, nothing partial is written,
// status 130.
#pragma once

#include <atomic>
#include <exception>

namespace meso::app {

// Installs the handler and its watchdog (once, before a command runs).
void installInterruptHandler();
// True once SIGINT or SIGTERM arrived (for commands that poll it in their long loops, and as
// RenderOptions::cancel).
const std::atomic<bool>& interruptRequested();
// Thrown by a command that stopped because of the signal; main() exits with 130.
struct RenderInterrupted : std::exception {
  const char* what() const noexcept override { return "interrupted"; }
};

}  // namespace meso::app
