// One subcommand of meso (render, consistency, tables, bands, trade, cache): it registers its own
// options on the command line, with their checks and the defaults --help shows, and runs once the
// whole line has been parsed. main.cpp only registers the commands and runs the one named.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace meso::app {

// What a command's run gets besides its own options.
struct RunContext {
  uint64_t memoryLimitBytes = 0;  // --memory-limit (default half of physical memory)
};

class Command {
 public:
  Command() = default;
  virtual ~Command() = default;
  Command(const Command&) = delete;
  Command& operator=(const Command&) = delete;

  // Whether the command line named this command.
  bool chosen() const { return app_->parsed(); }
  // Runs the command with the options parsed. Throws meso::Error on bad input.
  void run();

 protected:
  // Adds --memory-limit, the option every command has (registered after the command's own).
  void addMemoryLimit();
  virtual void execute(const RunContext& context) = 0;

  // The command's subcommand, set by the derived class once its options (members, constructed
  // after this base) exist.
  CLI::App* app_ = nullptr;

 private:
  uint64_t memoryLimitMib_ = 0;  // 0: not given
};

// A command whose options are one struct: `add` registers them (returning the subcommand) and `run`
// runs the command with them.
template <class Options>
class OptionsCommand : public Command {
 public:
  using Add = CLI::App* (*)(CLI::App& cli, Options& options);
  using Run = void (*)(const Options& options, const RunContext& context);
  OptionsCommand(CLI::App& cli, Add add, Run run) : run_(run) {
    app_ = add(cli, options_);
    addMemoryLimit();
  }

 private:
  void execute(const RunContext& context) override { run_(options_, context); }
  Options options_;
  Run run_;
};

// Every command of meso, registered on `cli` in the order --help lists them.
std::vector<std::unique_ptr<Command>> registerCommands(CLI::App& cli);

}  // namespace meso::app
