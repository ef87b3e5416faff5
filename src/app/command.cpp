// The commands of meso and what they share (command.h).
#include "command.h"

#include "bands_command.h"
#include "cache_command.h"
#include "consistency_command.h"
#include "render_command.h"
#include "tables_command.h"
#include "trade_command.h"

#include "meso/core/memory_budget.h"

#include <string>

namespace meso::app {

void Command::run() {
  execute({.memoryLimitBytes =
               memoryLimitMib_ > 0 ? memoryLimitMib_ << 20 : defaultMemoryLimitBytes()});
}

void Command::addMemoryLimit() {
  app_->add_option("--memory-limit", memoryLimitMib_,
                   "MiB a job may use: jobs estimated above it are refused before allocating "
                   "(default half of physical memory, here " +
                       std::to_string(defaultMemoryLimitBytes() >> 20) + ")")
      ->check(CLI::Range(uint64_t{16}, uint64_t{1} << 30))
      ->default_str(std::to_string(defaultMemoryLimitBytes() >> 20));
}

std::vector<std::unique_ptr<Command>> registerCommands(CLI::App& cli) {
  std::vector<std::unique_ptr<Command>> commands;
  commands.push_back(makeRenderCommand(cli));
  commands.push_back(makeConsistencyCommand(cli));
  commands.push_back(makeTablesCommand(cli));
  commands.push_back(makeBandsCommand(cli));
  commands.push_back(makeTradeCommand(cli));
  commands.push_back(makeCacheCommand(cli));
  return commands;
}

}  // namespace meso::app
