// `meso render`: the command itself (its options: render_options.h).
#pragma once

#include "command.h"
#include "interrupt.h"
#include "render_options.h"

#include <memory>

namespace meso::app {

// The `render` command (options: render_options.h), registered on `cli`. It renders and writes the
// EXR, its PNG preview and (optionally) the stats JSON.
std::unique_ptr<Command> makeRenderCommand(CLI::App& cli);

}  // namespace meso::app
