// `meso render`: the command itself (its options: render_options.h).
#pragma once

#include "interrupt.h"
#include "render_options.h"

namespace meso::app {

// Renders and writes the EXR, its PNG preview and (optionally) the stats JSON. Throws meso::Error.
void runRender(const RenderCommandOptions& options);

}  // namespace meso::app
