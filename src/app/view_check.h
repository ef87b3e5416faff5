// Objects no frame shows: a scene whose camera or transforms put an object wholly out of view
// renders without it, without a word; `meso render` warns instead.
#pragma once

#include "meso/render/render_context.h"
#include "meso/scene/scene.h"

#include <string>
#include <vector>

namespace meso::app {

// One warning per object of `ctx` (built from `scene`) that lies outside the view frustum of every
// camera in `cameras`: the box of its limit surface's patch points (which contains the surface)
// grown by its relief's displacement bound is tested against each camera's frustum, so an object
// any frame might show is never named.
std::vector<std::string> objectsOutOfView(const Scene& scene, const RenderContext& ctx,
                                          const std::vector<CameraSettings>& cameras);

}  // namespace meso::app
