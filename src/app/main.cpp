// The meso command line: registers the commands (each with its own options), parses, and runs the
// command named. Exit status 2 on bad input.
#include "command.h"
#include "interrupt.h"

#include "meso/core/error.h"
#include "meso/core/floating_point.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  meso::useFlushToZero();  // before any parallel loop (core/floating_point.h)
  CLI::App cli{"meso: bumpy surfaces at every distance (Becker & Max 1993)"};
  cli.set_version_flag("--version", "meso " MESO_VERSION, "Print meso's version and exit");
  cli.require_subcommand(1);
  const auto commands = meso::app::registerCommands(cli);
  meso::app::installInterruptHandler();
  try {
    cli.parse(argc, argv);
    for (const auto& command : commands)
      if (command->chosen()) command->run();
  } catch (const CLI::ParseError& e) {
    const int status = cli.exit(e);
    return status == 0 ? 0 : 2;
  } catch (const meso::app::RenderInterrupted&) {
    std::fprintf(stderr,
                 "meso: interrupted; complete frames are kept, nothing partial was written\n");
    return meso::app::interruptedStatus();
  } catch (const meso::Error& e) {
    std::fprintf(stderr, "meso: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "meso: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
